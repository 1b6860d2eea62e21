#!/usr/bin/env python3
# ==========================================================================
#
#   Copyright NumFOCUS
#
#   Licensed under the Apache License, Version 2.0 (the "License");
#   you may not use this file except in compliance with the License.
#   You may obtain a copy of the License at
#
#          http://www.apache.org/licenses/LICENSE-2.0.txt
#
#   Unless required by applicable law or agreed to in writing, software
#   distributed under the License is distributed on an "AS IS" BASIS,
#   WITHOUT WARRANTIES OR CONDITIONS OF ANY KIND, either express or implied.
#   See the License for the specific language governing permissions and
#   limitations under the License.
#
# ==========================================================================
"""MeshShapeMatchingFilter from Python: an ellipsoid matched to a larger, shifted one.

Builds both meshes as triangulated ellipsoids, matches them with the default method (go+cpd) on a coarse grid and
checks that the matched source lies closer to the target than the source did (mean distance from each matched vertex
to the target's analytic surface), and that the filter reports its metric values.
"""
import math
import os
import sys
import tempfile

import itk

MeshType = itk.Mesh[itk.F, 3]  # the type itk.meshread returns for pixel_type=itk.F


def ellipsoid(radii, center, directory, name, rings=12, segments=24):
    """A closed triangulated ellipsoid (poles plus rings of vertices), written as an OFF file and read by ITK."""
    points = [(0.0, 0.0, 1.0)]
    for r in range(1, rings):
        theta = math.pi * r / rings
        for s in range(segments):
            phi = 2.0 * math.pi * s / segments
            points.append((math.sin(theta) * math.cos(phi), math.sin(theta) * math.sin(phi), math.cos(theta)))
    points.append((0.0, 0.0, -1.0))

    def ring(r, s):
        return 1 + (r - 1) * segments + (s % segments)

    triangles = [(0, ring(1, s), ring(1, s + 1)) for s in range(segments)]
    for r in range(1, rings - 1):
        for s in range(segments):
            triangles.append((ring(r, s), ring(r + 1, s), ring(r + 1, s + 1)))
            triangles.append((ring(r, s), ring(r + 1, s + 1), ring(r, s + 1)))
    south = len(points) - 1
    triangles += [(south, ring(rings - 1, s + 1), ring(rings - 1, s)) for s in range(segments)]

    path = os.path.join(directory, name + ".off")
    with open(path, "w") as off:
        off.write("OFF\n%d %d 0\n" % (len(points), len(triangles)))
        for x, y, z in points:
            off.write("%.6f %.6f %.6f\n" % (center[0] + radii[0] * x, center[1] + radii[1] * y,
                                            center[2] + radii[2] * z))
        for a, b, c in triangles:
            off.write("3 %d %d %d\n" % (a, b, c))
    return itk.meshread(path, pixel_type=itk.F)


def mean_distance_to_ellipsoid(mesh, radii, center):
    """Mean |F(x)| (algebraic distance scaled to millimetres) of the mesh's vertices from an ellipsoid surface."""
    total = 0.0
    for i in range(mesh.GetNumberOfPoints()):
        p = mesh.GetPoint(i)
        q = [(p[k] - center[k]) / radii[k] for k in range(3)]
        norm = math.sqrt(sum(v * v for v in q))
        total += abs(norm - 1.0) * min(radii)
    return total / mesh.GetNumberOfPoints()


def main():
    source_radii, source_center = (20.0, 15.0, 12.0), (0.0, 0.0, 0.0)
    target_radii, target_center = (22.0, 16.0, 13.0), (1.5, -1.0, 0.5)
    directory = tempfile.mkdtemp()
    source = ellipsoid(source_radii, source_center, directory, "source")
    target = ellipsoid(target_radii, target_center, directory, "target")

    matching = itk.MeshShapeMatchingFilter[MeshType, itk.Image[itk.F, 3]].New()
    matching.SetSourceMesh(source)
    matching.SetTargetMesh(target)
    matching.SetNumberOfControlPointsPerAxis(6)
    matching.SetVoxelSize(1.0)
    matching.SetRandomSeed(1)
    matching.Update()
    matched = matching.GetOutput()

    before = mean_distance_to_ellipsoid(source, target_radii, target_center)
    after = mean_distance_to_ellipsoid(matched, target_radii, target_center)
    print("mean distance to the target: %.3f mm before, %.3f mm after" % (before, after))
    if matched.GetNumberOfPoints() != source.GetNumberOfPoints():
        print("error: the matched mesh has %d points, the source %d" % (matched.GetNumberOfPoints(),
                                                                         source.GetNumberOfPoints()))
        return 1
    if not after < 0.5 * before:
        print("error: matching did not halve the distance to the target")
        return 1
    if len(matching.GetMetricValues()) == 0:
        print("error: no metric values were reported")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
