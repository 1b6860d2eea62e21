#!/usr/bin/env python3
"""Writes generated mesh pairs for the batch workflow: a smooth closed template (an ellipsoid of icosphere
triangles) and targets that are the template under smooth random deformations, one draw per pair.

  make_pairs.py --count N --out DIR [--seed S] [--subdivisions L] [--amplitude MM]

writes DIR/template.off, DIR/targets/pair-NNN.off and DIR/pairs.csv (id,source,target: every pair matches the
template to one target; paths relative to DIR). Uses only Python's standard library.
"""
import argparse
import csv
import math
import os
import random


def icosphere(subdivisions):
    """Vertices (unit sphere) and triangles of an icosahedron subdivided `subdivisions` times."""
    t = (1.0 + math.sqrt(5.0)) / 2.0
    points = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t),
              (0, -1, -t), (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    points = [tuple(c / math.sqrt(1 + t * t) for c in p) for p in points]
    faces = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2),
             (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5),
             (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    for _ in range(subdivisions):
        middle = {}

        def midpoint(a, b):
            key = (min(a, b), max(a, b))
            if key not in middle:
                m = [(points[a][i] + points[b][i]) / 2.0 for i in range(3)]
                norm = math.sqrt(sum(c * c for c in m))
                points.append(tuple(c / norm for c in m))
                middle[key] = len(points) - 1
            return middle[key]

        refined = []
        for a, b, c in faces:
            ab, bc, ca = midpoint(a, b), midpoint(b, c), midpoint(c, a)
            refined += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        faces = refined
    return points, faces


def write_off(path, points, faces):
    with open(path, "w") as off:
        off.write(f"OFF\n{len(points)} {len(faces)} 0\n")
        off.writelines(f"{x:.6f} {y:.6f} {z:.6f}\n" for x, y, z in points)
        off.writelines(f"3 {a} {b} {c}\n" for a, b, c in faces)


def deform(points, rng, amplitude):
    """Each vertex moved by a smooth field: three low-frequency sine waves per axis with random directions."""
    waves = []
    for axis in range(3):
        for _ in range(3):
            direction = [rng.gauss(0.0, 1.0) for _ in range(3)]
            norm = math.sqrt(sum(c * c for c in direction))
            waves.append((axis, [c / norm * 2.0 * math.pi / 120.0 for c in direction], rng.uniform(0, 2 * math.pi),
                          rng.gauss(0.0, amplitude / 2.0)))
    moved = []
    for p in points:
        q = list(p)
        for axis, k, phase, weight in waves:
            q[axis] += weight * math.sin(sum(k[i] * p[i] for i in range(3)) + phase)
        moved.append(tuple(q))
    return moved


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--count", type=int, required=True, help="number of pairs")
    parser.add_argument("--out", required=True, help="folder to write (created)")
    parser.add_argument("--seed", type=int, default=1, help="seed of the deformations (default 1)")
    parser.add_argument("--subdivisions", type=int, default=2, help="icosphere subdivisions (2: 162 vertices)")
    parser.add_argument("--amplitude", type=float, default=4.0, help="deformation size in mm (default 4)")
    arguments = parser.parse_args()
    if arguments.count < 1:
        parser.error("--count must be at least 1")
    unit, faces = icosphere(arguments.subdivisions)
    template = [(40.0 * x, 30.0 * y, 25.0 * z) for x, y, z in unit]
    os.makedirs(os.path.join(arguments.out, "targets"), exist_ok=True)
    write_off(os.path.join(arguments.out, "template.off"), template, faces)
    rng = random.Random(arguments.seed)
    with open(os.path.join(arguments.out, "pairs.csv"), "w", newline="") as manifest:
        writer = csv.writer(manifest)
        writer.writerow(["id", "source", "target"])
        for i in range(arguments.count):
            name = f"pair-{i:03d}"
            write_off(os.path.join(arguments.out, "targets", name + ".off"), deform(template, rng, arguments.amplitude),
                      faces)
            writer.writerow([name, "template.off", f"targets/{name}.off"])


if __name__ == "__main__":
    main()
