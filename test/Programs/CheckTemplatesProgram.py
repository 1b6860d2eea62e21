#!/usr/bin/env python3
"""Tests of ffd-templates on generated B-spline transform files (standard library only).

  CheckTemplatesProgram.py CASE FFD_TEMPLATES WORKDIR

known: 6 transforms on one 6x6x6 grid, each an exact combination a_i f1 + b_i f2 of two known fields: the program
must keep exactly 2 modes, the templates must span f1 and f2 (and lie in their span), and the base must be the mean.
resampled: the same on grids shifted against each other: reported as resampled, the first two modes explain at
least 90 % of the variance (resampling is not exact near the domains' edges).
Bad input, each a one-line error, exit 1, no output written: missing, not-a-transform, mismatched-grids, identical,
one-transform, output-is-input, bad-variance.
Prints "PASS: CASE" or "FAIL: ...".
"""
import math
import os
import random
import re
import shutil
import subprocess
import sys

SIZE = 6  # control points per axis
COUNT = 3 * SIZE ** 3


def fail(message):
    print(f"FAIL: {message}")
    sys.exit(1)


def write_bspline(path, coefficients, size=SIZE, origin=(-15.0, -15.0, -15.0), spacing=10.0):
    """An ITK text transform file with one BSplineTransform_double_3_3 (fixed parameters: grid size, grid origin,
    grid spacing, direction)."""
    fixed = [size] * 3 + list(origin) + [spacing] * 3 + [1, 0, 0, 0, 1, 0, 0, 0, 1]
    with open(path, "w") as tfm:
        tfm.write("#Insight Transform File V1.0\n#Transform 0\nTransform: BSplineTransform_double_3_3\n")
        tfm.write("Parameters: " + " ".join(repr(c) for c in coefficients) + "\n")
        tfm.write("FixedParameters: " + " ".join(repr(float(f)) for f in fixed) + "\n")


def read_templates(path):
    """K, base and templates (dense) of a ParametricTemplateTransform file."""
    with open(path) as tfm:
        lines = tfm.read().splitlines()
    if not any(line.startswith("Transform: ParametricTemplateTransform") for line in lines):
        fail(f"{path} holds no ParametricTemplateTransform: {lines[:3]}")
    fixed = [float(v) for v in next(l for l in lines if l.startswith("FixedParameters:")).split()[1:]]
    at = 18
    k = int(fixed[at])
    at += 1
    vectors = []
    for _ in range(k + 1):
        m = int(fixed[at])
        dense = [0.0] * COUNT
        for j in range(m):
            dense[int(fixed[at + 1 + 2 * j])] = fixed[at + 2 + 2 * j]
        vectors.append(dense)
        at += 1 + 2 * m
    return k, vectors[0], vectors[1:]


def dot(u, v):
    return sum(a * b for a, b in zip(u, v))


def residual(vector, basis):
    """|vector - its least-squares projection onto span(basis)| / |vector| (Gram-Schmidt)."""
    orthonormal = []
    for b in basis:
        w = list(b)
        for q in orthonormal:
            c = dot(w, q)
            w = [x - c * y for x, y in zip(w, q)]
        norm = math.sqrt(dot(w, w))
        if norm > 1e-12:
            orthonormal.append([x / norm for x in w])
    rest = list(vector)
    for q in orthonormal:
        c = dot(rest, q)
        rest = [x - c * y for x, y in zip(rest, q)]
    return math.sqrt(dot(rest, rest)) / math.sqrt(dot(vector, vector))


def run(program, arguments):
    result = subprocess.run([program, *arguments], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    print(result.stdout + result.stderr)
    return result


def known_case(program, work, shifted):
    rng = random.Random(7)
    # Two smooth fields over the control points (x components, then y, then z; x fastest), so that resampling onto
    # a shifted grid changes them little.
    fields = []
    for phase in (rng.uniform(0, 3), rng.uniform(0, 3)):
        fields.append([math.sin(0.5 * (i % SIZE) + phase + axis) * math.cos(0.4 * ((i // SIZE) % SIZE) - phase)
                       * (1.0 + 0.1 * (i // SIZE ** 2)) for axis in range(3) for i in range(SIZE ** 3)])
    weights = [(rng.uniform(-2, 2), rng.uniform(-2, 2)) for _ in range(6)]
    examples, names = [], []
    for i, (a, b) in enumerate(weights):
        example = [a * x + b * y for x, y in zip(*fields)]
        examples.append(example)
        names.append(os.path.join(work, f"example-{i}.tfm"))
        origin = (-15.0 + (0.5 * i if shifted else 0.0), -15.0, -15.0)
        write_bspline(names[-1], example, origin=origin)
    output = os.path.join(work, "templates.tfm")
    result = run(program, ["--output", output, *names])
    if result.returncode != 0:
        fail(f"exit code {result.returncode}")
    if shifted:
        # Resampling onto the grid covering all domains is not exact (the fields change near the domains' edges):
        # the two generating fields must still carry most of the variance.
        if "(6 resampled onto the grid covering all their domains)" not in result.stdout:
            fail("the shifted grids were not reported as resampled")
        second = re.search(r"mode 2: .*\(cumulative ([0-9.]+) %\)", result.stdout)
        if not second or float(second.group(1)) < 90.0:
            fail("the first two modes explain less than 90 % of the variance")
        k, base, templates = read_templates(output)
        if not 2 <= k <= 5:
            fail(f"{k} templates in the file")
        return
    if "ffd-templates: 2 modes explain" not in result.stdout:
        fail("expected 2 modes")
    k, base, templates = read_templates(output)
    if k != 2:
        fail(f"{k} templates in the file, expected 2")
    for name, field in zip(("f1", "f2"), fields):
        r = residual(field, templates)
        print(f"{name} outside the templates' span: {r:.2e}")
        if r > 1e-6:
            fail(f"{name} is not in the span of the templates (relative residual {r})")
    for t, template in enumerate(templates):
        r = residual(template, fields)
        print(f"template {t + 1} outside span(f1, f2): {r:.2e}")
        if r > 1e-6:
            fail(f"template {t + 1} is not in span(f1, f2) (relative residual {r})")
    mean = [sum(e[i] for e in examples) / len(examples) for i in range(COUNT)]
    error = max(abs(x - y) for x, y in zip(base, mean))
    print(f"base - mean of the examples: {error:.2e}")
    if error > 1e-9:
        fail(f"the base is not the examples' mean (max difference {error})")


def bad_case(program, work, case):
    rng = random.Random(3)
    names = []
    for i in range(3):
        names.append(os.path.join(work, f"t{i}.tfm"))
        write_bspline(names[-1], [rng.gauss(0.0, 1.0) for _ in range(COUNT)])
    output = os.path.join(work, "templates.tfm")
    arguments = {
        "missing": ["--output", output, names[0], os.path.join(work, "no-such.tfm")],
        "not-a-transform": ["--output", output, names[0], os.path.join(work, "mesh.off")],
        "mismatched-grids": ["--output", output, names[0], os.path.join(work, "other-grid.tfm")],
        "identical": ["--output", output, names[0], os.path.join(work, "copy.tfm")],
        "one-transform": ["--output", output, names[0]],
        "output-is-input": ["--output", names[1], names[0], names[1]],
        "bad-variance": ["--output", output, "--variance", "95", names[0], names[1]],
    }[case]
    with open(os.path.join(work, "mesh.off"), "w") as mesh:
        mesh.write("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n")
    write_bspline(os.path.join(work, "other-grid.tfm"), [0.5] * (3 * 7 ** 3), size=7)
    shutil.copy(names[0], os.path.join(work, "copy.tfm"))
    before = open(names[1]).read()
    result = run(program, arguments)
    if result.returncode != 1:
        fail(f"exit code {result.returncode}, expected 1")
    if len(result.stderr.strip().splitlines()) != 1 or not result.stderr.startswith("ffd-templates: error: "):
        fail(f"expected one line 'ffd-templates: error: ...', got {result.stderr!r}")
    if case != "output-is-input" and os.path.exists(output):
        fail("an output was written")
    if open(names[1]).read() != before:
        fail("an input was changed")


def main():
    if len(sys.argv) != 4:
        fail(f"usage: {sys.argv[0]} CASE FFD_TEMPLATES WORKDIR")
    case, program, work = sys.argv[1:]
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    if case in ("known", "resampled"):
        known_case(program, work, case == "resampled")
    else:
        bad_case(program, work, case)
    print(f"PASS: {case}")


if __name__ == "__main__":
    main()
