#!/usr/bin/env python3
"""Times ffd-voxelize (TriangleMeshToVoxelImageFilter) on a 50,000-triangle sphere at 100^3 voxels.

Usage: voxelization_timing.py PATH/TO/ffd-voxelize [--threads N] [--work-dir DIR]

The sphere (radius 48, 200 segments x 126 rings = 50,000 triangles, written as OFF) is voxelized at
voxel size 1 with a margin of 2, i.e. a 100 x 100 x 100 grid, once per mode; the voxelization time
is read from each run's JSON report (mesh reading and image writing excluded). Prints one line per
mode and checks the solid volume against the sphere's.
"""

import argparse
import json
import math
import os
import subprocess
import sys
import tempfile


def write_sphere(path, segments=200, rings=126, radius=48.0):
    points = [(0.0, 0.0, radius)]
    for i in range(1, rings):
        theta = math.pi * i / rings
        for j in range(segments):
            phi = 2.0 * math.pi * j / segments
            points.append((radius * math.sin(theta) * math.cos(phi), radius * math.sin(theta) * math.sin(phi),
                           radius * math.cos(theta)))
    points.append((0.0, 0.0, -radius))
    south = len(points) - 1

    def index(i, j):
        return 1 + (i - 1) * segments + (j % segments)

    triangles = [(0, index(1, j), index(1, j + 1)) for j in range(segments)]
    for i in range(1, rings - 1):
        for j in range(segments):
            a, b, c, d = index(i, j), index(i + 1, j), index(i + 1, j + 1), index(i, j + 1)
            triangles += [(a, b, c), (a, c, d)]
    triangles += [(south, index(rings - 1, j + 1), index(rings - 1, j)) for j in range(segments)]
    with open(path, "w") as out:
        out.write("OFF\n%d %d 0\n" % (len(points), len(triangles)))
        out.writelines("%.9g %.9g %.9g\n" % p for p in points)
        out.writelines("3 %d %d %d\n" % t for t in triangles)
    return len(triangles)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("program")
    parser.add_argument("--threads", type=int, default=0)
    parser.add_argument("--work-dir", default=None)
    args = parser.parse_args()
    work = args.work_dir or tempfile.mkdtemp(prefix="ffd-voxelize-timing-")
    os.makedirs(work, exist_ok=True)
    mesh = os.path.join(work, "sphere50k.off")
    print("sphere: %d triangles" % write_sphere(mesh))
    status = 0
    for mode in ("occupancy", "solid", "sdf", "band", "winding"):
        report = os.path.join(work, "report-%s.json" % mode)
        command = [args.program, mesh, os.path.join(work, "sphere-%s.nrrd" % mode), "--mode", mode,
                   "--voxel-size", "1", "--margin", "2", "--report", report]
        if args.threads:
            command += ["--threads", str(args.threads)]
        subprocess.run(command, check=True, stderr=subprocess.DEVNULL)
        with open(report) as handle:
            result = json.load(handle)
        print("%-9s %s voxels, %d threads: %.3f s" % (mode, "x".join(map(str, result["size"])), result["threads"],
                                                     result["seconds"]["voxelize"]))
        if mode == "solid":
            volume = 4.0 / 3.0 * math.pi * 48.0 ** 3
            error = abs(result["inside_value_voxels"] - volume) / volume
            print("          solid volume %d voxels, sphere %.0f (%.2f %%)" % (result["inside_value_voxels"], volume,
                                                                                100 * error))
            status |= error > 0.01
    return status


if __name__ == "__main__":
    sys.exit(main())
