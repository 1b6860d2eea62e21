#!/usr/bin/env python3
"""CTest of the batch workflow (workflows/Snakefile) on generated pairs.

  workflow_test.py local|slurm|template|retry SNAKEMAKE FFD_MATCH WORKDIR

local: 3 generated pairs, one per-pair option, a damaged target (a cut OFF file) and a missing target, run with 2
cores. The table must hold 5 rows: 3 matched (distance reduced, no folding), the damaged and the missing pair with
ffd-match's one-line errors. A second run does nothing; after both inputs are repaired a third run matches exactly
those two pairs (the others' status files untouched) and the table then holds 5 matched rows.
slurm: the same through a single-node Slurm on localhost (workflows/test/local_slurm.sh, stopped at the end) with the
profile workflows/slurm, on 2 pairs and the damaged one; every match job must have run through sbatch, and the
profile's status command must answer success, failed and a usage error for a finished, an unknown and a bad job id.
template: one template and a folder of 3 targets (--config template=... targets=...), with templates=2: the learned
templates (ffd-templates) are read by ffd-match --method par.
retry: a pair killed on its first attempt is retried and matched, one killed on every attempt is a row with the
signal; a matched pair whose target is then damaged loses its earlier outputs.
Prints "PASS: <mode>" at the end; any failed check prints "FAIL: ..." and exits 1.
"""
import csv
import os
import re
import shutil
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
WORKFLOWS = os.path.dirname(HERE)
# Small and fast: a coarse grid and voxels, one level, few iterations (a sanitizer build is 5-10x slower).
OPTIONS = "--method go --grid 5 --voxel-size 4 --levels 1 --iterations 15"


def fail(message):
    print(f"FAIL: {message}", flush=True)
    sys.exit(1)


def check(condition, message):
    if not condition:
        fail(message)


def snakemake(arguments, config, label, extra=()):
    """Runs the workflow and returns its log (stdout and stderr)."""
    command = [SNAKEMAKE, "--snakefile", os.path.join(WORKFLOWS, "Snakefile"), "--directory", WORKDIR,
               *extra, *arguments, "--config", f"outdir={WORKDIR}/out", f"ffd_match={FFD_MATCH}",
               f"options={OPTIONS}", *config]
    print(f"--- {label}: {' '.join(command)}", flush=True)
    result = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    print(result.stdout[-6000:], flush=True)
    check(result.returncode == 0, f"{label}: snakemake exited {result.returncode}")
    return result.stdout


def matched_ids(log):
    """The pair ids whose match job ran, from Snakemake's log."""
    return sorted(re.findall(r"rule match:\n(?:    .*\n)*?    wildcards: id=(\S+)", log))


def read_table():
    with open(os.path.join(WORKDIR, "out", "population.csv"), newline="") as table:
        return {row["id"]: row for row in csv.DictReader(table)}


def check_matched(row):
    if row["status"] != "ok":
        # ffd-match's own output (e.g. a sanitizer's report) is in the pair's log, not in Snakemake's.
        with open(os.path.join(WORKDIR, "out", row["id"], "ffd-match.log"), errors="replace") as log:
            print(log.read()[-6000:])
        fail(f"{row['id']}: status '{row['status']}', expected ok")
    after, before = float(row["mean_directed_distance"]), float(row["mean_directed_distance_before"])
    check(after < 0.8 * before, f"{row['id']}: mean directed distance {after} not below 80 % of {before}")
    check(float(row["min_det_jacobian"]) > 0.0, f"{row['id']}: folding, min det J {row['min_det_jacobian']}")
    check(float(row["seconds"]) > 0.0, f"{row['id']}: no time recorded")
    for name in ("deformed.vtp", "transform.tfm", "report.json"):
        check(os.path.isfile(os.path.join(WORKDIR, "out", row["id"], name)), f"{row['id']}: {name} missing")


def make_pairs(count):
    subprocess.run([sys.executable, os.path.join(WORKFLOWS, "scripts", "make_pairs.py"), "--count", str(count),
                    "--out", os.path.join(WORKDIR, "pairs"), "--subdivisions", "2"], check=True)
    return os.path.join(WORKDIR, "pairs")


def add_broken_pairs(pairs):
    """A cut copy of the first target (pair 'damaged') and a target that does not exist (pair 'missing'); pair-001
    gets a per-pair option. Returns the manifest."""
    with open(os.path.join(pairs, "targets", "pair-000.off")) as good:
        text = good.read()
    with open(os.path.join(pairs, "damaged.off"), "w") as damaged:
        lines = text.splitlines(keepends=True)
        damaged.write("".join(lines[: len(lines) // 2]))
    with open(os.path.join(pairs, "pairs.csv"), newline="") as manifest:
        rows = list(csv.DictReader(manifest))
    for row in rows:
        row["options"] = "--grid 6" if row["id"] == "pair-001" else ""
    rows.append({"id": "damaged", "source": "template.off", "target": "damaged.off", "options": ""})
    rows.append({"id": "missing", "source": "template.off", "target": "missing.off", "options": ""})
    path = os.path.join(pairs, "with-failures.csv")
    with open(path, "w", newline="") as manifest:
        writer = csv.DictWriter(manifest, fieldnames=["id", "source", "target", "options"])
        writer.writeheader()
        writer.writerows(rows)
    return path, text


def run_failures_and_repair(arguments, ids, label):
    """The failure-isolation and resumption checks, shared by the local and the Slurm run."""
    pairs = make_pairs(len(ids))
    manifest, good_text = add_broken_pairs(pairs)
    config = [f"manifest={manifest}"]
    log = snakemake(arguments, config, f"{label}: first run")
    check(matched_ids(log) == sorted(ids + ["damaged", "missing"]), f"first run matched {matched_ids(log)}")
    table = read_table()
    check(sorted(table) == sorted(ids + ["damaged", "missing"]), f"table rows {sorted(table)}")
    for pair_id in ids:
        check_matched(table[pair_id])
    check(re.fullmatch(r"ffd-match: error: .*damaged\.off.*the file ends after [0-9]+ of 320 faces",
                       table["damaged"]["status"]), f"damaged: status '{table['damaged']['status']}'")
    check(re.fullmatch(r"ffd-match: error: cannot read target mesh .*missing\.off.*", table["missing"]["status"]),
          f"missing: status '{table['missing']['status']}'")
    check(not os.path.exists(os.path.join(WORKDIR, "out", "damaged", "deformed.vtp")), "damaged: a mesh was left")
    if "pair-001" in ids:
        with open(os.path.join(WORKDIR, "out", "pair-001", "report.json")) as report:
            check('"grid": 6,' in report.read(), "pair-001: the per-pair option --grid 6 was not used")
    check(os.path.getsize(os.path.join(WORKDIR, "out", "population.png")) > 10000, "population.png missing or empty")

    log = snakemake(arguments, config, f"{label}: second run, nothing changed")
    check(matched_ids(log) == [] and "Nothing to be done" in log, f"second run matched {matched_ids(log)}")

    times = {i: os.stat(os.path.join(WORKDIR, "out", i, "status.json")).st_mtime_ns for i in ids}
    for name in ("damaged.off", "missing.off"):
        with open(os.path.join(pairs, name), "w") as repaired:
            repaired.write(good_text)
    log = snakemake(arguments, config, f"{label}: third run, after the repair")
    check(matched_ids(log) == ["damaged", "missing"], f"after the repair the run matched {matched_ids(log)}")
    for pair_id in ids:
        mtime = os.stat(os.path.join(WORKDIR, "out", pair_id, "status.json")).st_mtime_ns
        check(mtime == times[pair_id], f"{pair_id} was written again")
    table = read_table()
    for pair_id in table:
        check_matched(table[pair_id])


def run_template_folder():
    """One template, a folder of 3 targets, and templates learned from the 3 transforms (ffd-templates, beside
    ffd-match) that ffd-match --method par then reads."""
    pairs = make_pairs(3)
    ffd_templates = os.path.join(os.path.dirname(FFD_MATCH), "ffd-templates")
    log = snakemake(["--cores", "2"], [f"template={pairs}/template.off", f"targets={pairs}/targets", "templates=2",
                                       f"ffd_templates={ffd_templates}"], "template")
    ids = ["pair-000", "pair-001", "pair-002"]
    check(matched_ids(log) == ids, f"template run matched {matched_ids(log)}")
    table = read_table()
    check(sorted(table) == ids, f"table rows {sorted(table)}")
    for row in table.values():
        check_matched(row)
    with open(os.path.join(WORKDIR, "out", "templates.log")) as log_file:
        text = log_file.read()
    print(text)
    check("ffd-templates: 3 transforms" in text and re.search(r"[12] modes explain", text), "templates.log")
    templates = os.path.join(WORKDIR, "out", "templates.tfm")
    command = [FFD_MATCH, "--source", f"{pairs}/template.off", "--target", f"{pairs}/targets/pair-000.off",
               "--method", "par", "--templates", templates, "--output", os.path.join(WORKDIR, "par.vtp"),
               "--grid", "5", "--voxel-size", "4"]
    result = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    print(result.stdout[-2000:])
    check(result.returncode == 0 and re.search(r"template weights from .*templates.tfm", result.stdout),
          "ffd-match --method par did not run with the learned templates")


# An ffd-match stand-in for the retry test: killed by SIGKILL on its first call for a pair (a marker in the pair's
# folder), and on every call for pair-001; otherwise the real ffd-match.
CRASHING_FFD_MATCH = """#!{python}
import os, signal, sys
output = sys.argv[sys.argv.index("--output") + 1]
marker = os.path.join(os.path.dirname(output), "crashed-once")
target = sys.argv[sys.argv.index("--target") + 1]
if "pair-001" in target or not os.path.exists(marker):
    open(marker, "w").close()
    os.kill(os.getpid(), signal.SIGKILL)
os.execv({real!r}, [{real!r}] + sys.argv[1:])
"""


def run_retry():
    """Snakemake's retries: a crash on the first attempt is retried and the pair matched (attempt 2); a pair that
    crashes on every attempt is recorded with the signal. Then a matched pair's target is damaged: the re-run records
    the error and removes the mesh, transform and report of the earlier run."""
    global FFD_MATCH
    pairs = make_pairs(2)
    crashing = os.path.join(WORKDIR, "crashing-ffd-match")
    with open(crashing, "w") as script:
        script.write(CRASHING_FFD_MATCH.format(python=sys.executable, real=os.path.abspath(FFD_MATCH)))
    os.chmod(crashing, 0o755)
    real, FFD_MATCH = FFD_MATCH, crashing
    log = snakemake(["--cores", "2"], [f"manifest={pairs}/pairs.csv", "retries=1"], "retry")
    FFD_MATCH = real
    check(matched_ids(log).count("pair-000") == 2, f"pair-000 ran {matched_ids(log).count('pair-000')} times, not 2")
    table = read_table()
    check_matched(table["pair-000"])
    check(table["pair-000"]["attempt"] == "2", f"pair-000: attempt {table['pair-000']['attempt']}, expected 2")
    check(re.fullmatch(r"ffd-match ended by signal SIGKILL \(attempt 2 of 2; see .*ffd-match.log\)",
                       table["pair-001"]["status"]), f"pair-001: status '{table['pair-001']['status']}'")

    with open(os.path.join(pairs, "targets", "pair-000.off"), "w") as damaged:
        damaged.write("OFF\n3 1 0\n0 0 0\n")
    log = snakemake(["--cores", "2"], [f"manifest={pairs}/pairs.csv", "retries=1"], "retry: damaged after a match")
    check(matched_ids(log) == ["pair-000"], f"after the damage the run matched {matched_ids(log)}")
    row = read_table()["pair-000"]
    check(row["status"].startswith("ffd-match: error: ") and row["attempt"] == "1", f"pair-000: {row}")
    for name in ("deformed.vtp", "transform.tfm", "report.json"):
        check(not os.path.exists(os.path.join(WORKDIR, "out", "pair-000", name)), f"pair-000: a stale {name} is left")


def run_slurm():
    slurm_dir = os.path.join(WORKDIR, "slurm")
    script = (f"source {HERE}/local_slurm.sh; trap slurm_stop EXIT; slurm_start {slurm_dir} || exit 1; "
              f"{sys.executable} {os.path.abspath(__file__)} slurm-inside {SNAKEMAKE} {FFD_MATCH} {WORKDIR}")
    result = subprocess.run(["bash", "-c", script], env=dict(os.environ, USER=os.environ.get("USER", "root")))
    leftovers = subprocess.run(["pgrep", "-f", slurm_dir], stdout=subprocess.PIPE, text=True).stdout.split()
    check(not leftovers, f"Slurm daemons still running: {leftovers}")
    return result.returncode


def main():
    global SNAKEMAKE, FFD_MATCH, WORKDIR
    if len(sys.argv) != 5 or sys.argv[1] not in ("local", "slurm", "slurm-inside", "template", "retry"):
        fail(f"usage: {sys.argv[0]} local|slurm|template|retry SNAKEMAKE FFD_MATCH WORKDIR")
    mode, SNAKEMAKE, FFD_MATCH, WORKDIR = sys.argv[1:]
    if mode != "slurm-inside":
        check(shutil.which(SNAKEMAKE) is not None, f"snakemake not found ('{SNAKEMAKE}'): install Debian's snakemake")
        if mode == "slurm" and os.path.isdir(os.path.join(WORKDIR, "slurm")):
            # Daemons an earlier run left (killed at a time-out: its trap could not run), by their pid files.
            subprocess.run(["bash", "-c", f"source {HERE}/local_slurm.sh; SLURM_DIR={WORKDIR}/slurm slurm_stop"])
        shutil.rmtree(WORKDIR, ignore_errors=True)
        os.makedirs(WORKDIR)
    if mode == "local":
        run_failures_and_repair(["--cores", "2"], ["pair-000", "pair-001", "pair-002"], "local")
    elif mode == "template":
        run_template_folder()
    elif mode == "retry":
        run_retry()
    elif mode == "slurm":
        if run_slurm() != 0:
            fail("the Slurm run failed (see above)")
    else:
        run_failures_and_repair(["--profile", os.path.join(WORKFLOWS, "slurm"), "--jobs", "2"],
                                ["pair-000", "pair-001"], "slurm")
        # Every match job ran through sbatch: 4 in the first run (2 pairs, the damaged and the missing one), none
        # in the second, 2 after the repair; each wrote its Slurm log.
        logs = sorted(os.listdir(os.path.join(WORKDIR, "slurm-logs")))
        check(len(logs) == 6 and all(name.startswith("match-") for name in logs), f"Slurm job logs: {logs}")
        # The profile's status command on a finished job, on a job Slurm does not know and on a malformed id.
        status = os.path.join(WORKFLOWS, "slurm", "slurm-status.py")
        finished = re.fullmatch(r"match-\d+-(\d+)\.log", logs[0]).group(1)
        for job, expected, code in ((f"{finished};ffdtest", "success", 0), ("999999", "failed", 0), ("x1", "", 2)):
            answer = subprocess.run([status, job], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
            check(answer.returncode == code and answer.stdout.strip() == expected,
                  f"slurm-status.py {job}: exit {answer.returncode}, '{answer.stdout.strip()}' ({answer.stderr.strip()})")
        return
    print(f"PASS: {mode}")


if __name__ == "__main__":
    main()
