#!/usr/bin/env python3
"""The "posed" check of the pose stage: a benchmark case's target posed by a known similarity (rotation about an
oblique axis through the target's centroid, scale, shift), matched by ffd-match with a pose stage, against the same
case aligned (no pose stage). The true error of the posed run is in the posed target's units, i.e. scaled by the
pose's scale; the goal is posed <= 1.25 x scale x aligned.

  benchmark/posed_cases.py --ffd-match build/apps/ffd-match --tool build/benchmark/ffd-benchmark-tool \\
      --cases /tmp/bcpd/work/cases --case bunny00-smooth-1 --angles 30 90 180 --work /tmp/posed
"""
import argparse
import json
import math
import os
import random
import subprocess
import sys


def read_off(path):
    """Vertices and the face lines (kept verbatim) of an OFF file with one vertex per line."""
    with open(path) as f:
        lines = [line for line in f.read().splitlines() if line.strip() and not line.lstrip().startswith("#")]
    if not lines or lines[0].split()[0] != "OFF":
        raise RuntimeError("%s: not an OFF file" % path)
    header = lines[0].split()[1:] or lines[1].split()
    first = 1 if len(lines[0].split()) > 1 else 2
    nv, nf = int(header[0]), int(header[1])
    vertices = [tuple(float(w) for w in lines[first + i].split()[:3]) for i in range(nv)]
    return vertices, nf, lines[first + nv:]


def write_off(path, vertices, nf, faces):
    with open(path, "w") as f:
        f.write("OFF\n%d %d 0\n" % (len(vertices), nf))
        for v in vertices:
            f.write("%.9g %.9g %.9g\n" % v)
        f.write("\n".join(faces) + "\n")


def rotation(axis, degrees):
    n = math.sqrt(sum(a * a for a in axis))
    x, y, z = (a / n for a in axis)
    t = math.radians(degrees)
    c, s, C = math.cos(t), math.sin(t), 1.0 - math.cos(t)
    return [[c + x * x * C, x * y * C - z * s, x * z * C + y * s],
            [y * x * C + z * s, c + y * y * C, y * z * C - x * s],
            [z * x * C - y * s, z * y * C + x * s, c + z * z * C]]


def pose_mesh(source_path, output_path, axis, degrees, scale, shift):
    """Writes the mesh posed by x -> c + shift + scale R (x - c), c its vertex centroid, R the rotation by degrees
    about axis; returns c."""
    vertices, nf, rest = read_off(source_path)
    centre = [sum(v[d] for v in vertices) / len(vertices) for d in range(3)]
    r = rotation(axis, degrees)
    posed = []
    for v in vertices:
        q = [v[d] - centre[d] for d in range(3)]
        posed.append(tuple(centre[a] + shift[a] + scale * sum(r[a][b] * q[b] for b in range(3)) for a in range(3)))
    write_off(output_path, posed, nf, rest)
    return centre


def pose_error(drawn, found):
    """The error of a pose found by ffd-match (its report's "pose" block, target to source) against the drawn pose
    (aligned target to posed target, random_pose): the rotation angle (degrees) of R_found R_drawn, which is the
    identity when the found rotation undoes the drawn one, and the relative error of scale_found x scale_drawn."""
    a = rotation(found["rotation_axis"], found["rotation_angle_degrees"])
    b = rotation(drawn["rotation_axis"], drawn["rotation_angle_degrees"])
    trace = sum(a[i][k] * b[k][i] for i in range(3) for k in range(3))
    angle = math.degrees(math.acos(max(-1.0, min(1.0, 0.5 * (trace - 1.0)))))
    return angle, found["scale"] * drawn["scale"] - 1.0


def bounding_box_diagonal(path):
    vertices = read_off(path)[0]
    return math.sqrt(sum((max(v[d] for v in vertices) - min(v[d] for v in vertices)) ** 2 for d in range(3)))


def unit_vector(generator):
    """A direction uniform on the sphere."""
    z = generator.uniform(-1.0, 1.0)
    phi = generator.uniform(0.0, 2.0 * math.pi)
    r = math.sqrt(max(0.0, 1.0 - z * z))
    return [r * math.cos(phi), r * math.sin(phi), z]


def random_pose(seed, diagonal):
    """The benchmark's posed regime: a similarity drawn from seed (random.Random(seed)): rotation angle uniform in
    [0, 180] degrees about a uniformly random axis, isotropic scale log-uniform in [0.5, 2], shift of a length
    uniform in [0, diagonal] in a uniformly random direction."""
    generator = random.Random(seed)
    angle = generator.uniform(0.0, 180.0)
    axis = unit_vector(generator)
    scale = math.exp(generator.uniform(math.log(0.5), math.log(2.0)))
    direction = unit_vector(generator)
    length = generator.uniform(0.0, diagonal)
    return {"rotation_angle_degrees": angle, "rotation_axis": axis, "scale": scale,
            "shift": [length * d for d in direction], "shift_length": length}


def run(command, log):
    with open(log, "w") as f:
        result = subprocess.run(command, stdout=f, stderr=subprocess.STDOUT)
    return result.returncode


def match_and_score(args, case, target, folder, initial):
    os.makedirs(folder, exist_ok=True)
    deformed = os.path.join(folder, "deformed.off")
    report = os.path.join(folder, "report.json")
    command = [args.ffd_match, "--source", os.path.join(case, "inputs", "source.off"), "--target", target,
               "--method", args.method, "--output", deformed, "--report", report, "--transform-out",
               os.path.join(folder, "transform.tfm"), "--initial-transform", initial, "--threads", str(args.threads)]
    if run(command, os.path.join(folder, "match.log")) != 0:
        return None
    score = os.path.join(folder, "score.json")
    if run([args.tool, "score", "--deformed", deformed, "--target", target, "--truth",
            os.path.join(case, "truth", "truth.txt"), "--output", score], os.path.join(folder, "score.log")) != 0:
        return None
    with open(score) as f:
        scores = json.load(f)
    with open(report) as f:
        data = json.load(f)
    return {"true_error": scores["true_error"]["mean"], "min_det_j": data.get("min_jacobian_determinant"),
            "pose": data.get("pose"), "seconds": data["seconds"]}


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--ffd-match", required=True)
    parser.add_argument("--tool", required=True, help="ffd-benchmark-tool")
    parser.add_argument("--cases", required=True, help="folder of benchmark cases (run_benchmark.py's work/cases)")
    parser.add_argument("--case", action="append", required=True)
    parser.add_argument("--angles", type=float, nargs="+", default=[30.0, 90.0, 180.0])
    parser.add_argument("--axis", type=float, nargs=3, default=[0.3, -0.5, 0.8])
    parser.add_argument("--scale", type=float, default=1.1)
    parser.add_argument("--shift", type=float, nargs=3, default=[30.0, -20.0, 25.0])
    parser.add_argument("--method", default="go+cpd")
    parser.add_argument("--initial-transform", default="similarity")
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--work", required=True)
    args = parser.parse_args()
    rows = []
    for name in args.case:
        case = os.path.join(args.cases, name)
        target = os.path.join(case, "inputs", "target.off")
        aligned = match_and_score(args, case, target, os.path.join(args.work, name, "aligned"), "none")
        for angle in args.angles:
            posed_target = os.path.join(args.work, name, "posed-%g" % angle, "target.off")
            os.makedirs(os.path.dirname(posed_target), exist_ok=True)
            pose_mesh(target, posed_target, args.axis, angle, args.scale, args.shift)
            posed = match_and_score(args, case, posed_target, os.path.dirname(posed_target), args.initial_transform)
            row = {"case": name, "angle": angle, "scale": args.scale, "shift": args.shift,
                   "aligned": aligned, "posed": posed}
            if aligned and posed:
                row["ratio_to_scaled_aligned"] = posed["true_error"] / (args.scale * aligned["true_error"])
            rows.append(row)
            print(json.dumps(row), flush=True)
    with open(os.path.join(args.work, "posed.json"), "w") as f:
        json.dump(rows, f, indent=1)
    print("| case | rotation | aligned TRE (mm) | posed TRE (mm) | posed / (scale x aligned) | pose found: angle, scale"
          " | min det J | pose s |")
    print("|---|---|---|---|---|---|---|---|")
    for row in rows:
        a, p = row["aligned"], row["posed"]
        if not a or not p:
            print("| %s | %g | %s | failed | | | | |" % (row["case"], row["angle"], a and "%.3f" % a["true_error"]))
            continue
        # With --initial-transform none there is no pose stage: no pose found, no pose time.
        found = ("%.2f°, %.4f" % (p["pose"]["rotation_angle_degrees"], p["pose"]["scale"])
                 if p["pose"] else "none (no pose stage)")
        print("| %s | %g° | %.3f | %.3f | %.2f | %s | %.3f | %.1f |" % (
            row["case"], row["angle"], a["true_error"], p["true_error"], row["ratio_to_scaled_aligned"], found,
            p["min_det_j"], p["seconds"]["pose"]))
    return 0


if __name__ == "__main__":
    sys.exit(main())
