#!/usr/bin/env python3
"""Checks of the module's programs that need arithmetic or raw bytes (run by CTest, test/Programs/CMakeLists.txt).

identity-match FFD_MATCH FOLDER
    A cube 1e7 mm from the origin, with coordinates that need all of a double's digits, matched to itself with
    --method go: no vertex of the output may move by more than 1e-6 mm (float32 anywhere on the way moves them by
    up to 0.5 mm).
json-non-utf8 FFD_VOXELIZE MESH FOLDER
    ffd-voxelize with an output and a report whose names are not valid UTF-8: the report must be valid JSON that
    spells the names as their Latin-1 reading.
"""
import json
import os
import subprocess
import sys


def read_off_vertices(path):
    with open(path) as file:
        tokens = [t for line in file for t in line.split("#")[0].split()]
    if tokens[0] != "OFF":
        raise SystemExit(f"{path}: not an OFF file")
    count = int(tokens[1])
    values = [float(t) for t in tokens[4:4 + 3 * count]]
    return [values[3 * i:3 * i + 3] for i in range(count)]


def identity_match(program, folder):
    os.makedirs(folder, exist_ok=True)
    source = os.path.join(folder, "far-cube.off")
    output = os.path.join(folder, "far-cube-matched.off")
    offset = (1.0e7 + 0.123456789012, -2.0e7 + 0.987654321098, 3.0e7 + 0.314159265358)
    corners = [(x, y, z) for z in (-1, 1) for y in (-1, 1) for x in (-1, 1)]
    faces = [(0, 2, 3), (0, 3, 1), (4, 5, 7), (4, 7, 6), (0, 1, 5), (0, 5, 4),
             (2, 6, 7), (2, 7, 3), (0, 4, 6), (0, 6, 2), (1, 3, 7), (1, 7, 5)]
    with open(source, "w") as file:
        file.write(f"OFF\n{len(corners)} {len(faces)} 0\n")
        for corner in corners:
            file.write(" ".join(repr(o + 4.0 * c) for o, c in zip(offset, corner)) + "\n")
        for face in faces:
            file.write("3 " + " ".join(map(str, face)) + "\n")
    if os.path.exists(output):
        os.remove(output)
    run = subprocess.run([program, "--source", source, "--target", source, "--method", "go", "--output", output,
                          "--grid", "4", "--levels", "1", "--iterations", "3", "--voxel-size", "0.5"],
                         capture_output=True, text=True)
    sys.stdout.write(run.stdout + run.stderr)
    if run.returncode != 0:
        raise SystemExit(f"ffd-match failed with exit code {run.returncode}")
    before = read_off_vertices(source)
    after = read_off_vertices(output)
    if len(before) != len(after):
        raise SystemExit(f"{len(after)} vertices written for {len(before)}")
    largest = max(abs(a - b) for p, q in zip(before, after) for a, b in zip(p, q))
    if not largest <= 1.0e-6:
        raise SystemExit(f"a vertex moved by {largest} mm, more than 1e-6 mm")
    # Printed only once the check holds: the test's PASS_REGULAR_EXPRESSION looks for this line.
    print(f"largest vertex movement of the identity match 1e7 mm from the origin: {largest:.3g} mm")


def json_non_utf8(program, mesh, folder):
    os.makedirs(folder, exist_ok=True)
    name = b"caf\xe9-\xff"  # Latin-1 bytes, not valid UTF-8
    base = os.fsencode(folder) + b"/" + name
    output, report = base + b".mha", base + b".json"
    for path in (output, report):
        if os.path.exists(path):
            os.remove(path)
    run = subprocess.run([os.fsencode(program), os.fsencode(mesh), output, b"--mode", b"solid", b"--voxel-size",
                          b"0.5", b"--report", report], capture_output=True)
    sys.stdout.write(run.stdout.decode(errors="replace") + run.stderr.decode(errors="replace"))
    if run.returncode != 0:
        raise SystemExit(f"ffd-voxelize failed with exit code {run.returncode}")
    with open(report, "rb") as file:
        content = file.read()
    document = json.loads(content.decode("utf-8"))  # raises on invalid UTF-8 or invalid JSON
    if document["output"] != output.decode("latin-1"):
        raise SystemExit(f"the report spells the output {document['output']!r}")
    print("the report is valid JSON; output spelled", ascii(document["output"]))
    for path in (output, report):
        os.remove(path)


if __name__ == "__main__":
    if len(sys.argv) == 4 and sys.argv[1] == "identity-match":
        identity_match(sys.argv[2], sys.argv[3])
    elif len(sys.argv) == 5 and sys.argv[1] == "json-non-utf8":
        json_non_utf8(sys.argv[2], sys.argv[3], sys.argv[4])
    else:
        raise SystemExit(__doc__)
