#!/usr/bin/env python3
"""Checks the benchmark's case generator (`ffd-benchmark-tool case`) where a draw of T_true leaves a region vertex
without a preimage: on the smoke torus with no margin around the region (`--margin 0`), so that displacements at
the domain's edge open gaps there.

- smooth regime (grid 8, seed 1): the first draw does not fold but leaves a vertex without a preimage; it is
  replaced by the next seed's draw (case.json: 2 attempts, 1 draw without a preimage, generator seed 1 + 7919), and
  the case is written whole;
- paper regime (grid 30, seed 1): one draw only, so the tool stops with one line naming the vertices without a
  preimage, exits non-zero and writes no case file.

Usage: test_benchmark_case.py FFD_BENCHMARK_TOOL WORK_DIR. Prints "benchmark case check passed"."""

import json
import os
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import run_benchmark  # noqa: E402

problems = []


def check(condition, text):
    if not condition:
        problems.append(text)


def off_counts(path):
    with open(path) as stream:
        words = stream.read().split()
    return int(words[1]), int(words[2])


def run_case(tool, mesh, folder, regime, seed, grid):
    shutil.rmtree(folder, ignore_errors=True)
    os.makedirs(folder)
    return subprocess.run([tool, "case", "--mesh", mesh, "--out-dir", folder, "--truth-dir", folder, "--regime",
                           regime, "--seed", str(seed), "--grid", str(grid), "--margin", "0"],
                          capture_output=True, text=True)


def main():
    tool, work = sys.argv[1], sys.argv[2]
    os.makedirs(work, exist_ok=True)
    mesh = run_benchmark.write_torus(os.path.join(work, "torus.off"))

    smooth = os.path.join(work, "smooth")
    result = run_case(tool, mesh, smooth, "smooth", 1, 8)
    check(result.returncode == 0, "smooth case failed: " + result.stderr.strip())
    if result.returncode == 0:
        with open(os.path.join(smooth, "case.json")) as stream:
            case = json.load(stream)
        check(case["draws_without_preimage"] == 1, "draws without a preimage: %s" % case["draws_without_preimage"])
        check(case["attempts"] == 2, "attempts: %s" % case["attempts"])
        check(case["generator_seed"] == 1 + 7919, "generator seed: %s" % case["generator_seed"])
        check(case["min_jacobian_determinant"] > 0.2, "min det J %s" % case["min_jacobian_determinant"])
        vertices, _ = off_counts(os.path.join(smooth, "target.off"))
        check(vertices == case["target_vertices"] > 0, "target vertices %d, case.json %s"
              % (vertices, case["target_vertices"]))
        with open(os.path.join(smooth, "truth.txt")) as stream:
            pairs = [line for line in stream if not line.startswith("#")]
        check(len(pairs) == vertices, "truth.txt holds %d pairs for %d target vertices" % (len(pairs), vertices))
        check(os.path.isfile(os.path.join(smooth, "T_true.tfm")), "no T_true.tfm")

    paper = os.path.join(work, "paper")
    result = run_case(tool, mesh, paper, "paper", 1, 30)
    check(result.returncode != 0, "the paper case without preimages exited 0")
    lines = result.stderr.strip().splitlines()
    check(len(lines) == 1 and "have no preimage under T_true" in lines[0], "paper error: %r" % result.stderr)
    check(os.listdir(paper) == [], "the failed paper case wrote %s" % sorted(os.listdir(paper)))

    for problem in problems:
        print("benchmark case check: " + problem)
    if problems:
        return 1
    print("benchmark case check passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
