#!/usr/bin/env python3
"""Runs ffd-match on one pair of the batch workflow and records the outcome in a status file (JSON).

A pair that ffd-match refuses (it prints one line 'ffd-match: error: ...' and exits 1) is recorded with that line as
its status and this script exits 0, so that the workflow goes on with the other pairs. A run that ends otherwise (a
signal, e.g. killed for memory, or an exit without an error line) exits 1 so that Snakemake retries it, and is
recorded as failed on the last attempt. Outputs of an earlier run are removed before the run, so a pair's folder
never holds a mesh that the status does not vouch for; ffd-match itself writes its outputs all or nothing.
"""
import argparse
import json
import os
import resource
import signal
import socket
import subprocess
import sys
import time

ERROR_PREFIX = "ffd-match: error:"


def error_line(log_path):
    """The last 'ffd-match: error: ...' line of the log, or None."""
    found = None
    with open(log_path, errors="replace") as log:
        for line in log:
            if line.startswith(ERROR_PREFIX):
                found = line.strip()
    return found


def write_status(path, record):
    """Writes the status file whole or not at all (a temporary file renamed over it)."""
    temporary = path + ".partial"
    with open(temporary, "w") as status:
        json.dump(record, status, indent=1)
        status.write("\n")
    os.replace(temporary, path)


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--ffd-match", required=True, help="the ffd-match program")
    parser.add_argument("--id", required=True)
    parser.add_argument("--source", required=True)
    parser.add_argument("--target", required=True)
    parser.add_argument("--folder", required=True, help="the pair's output folder")
    parser.add_argument("--mesh-format", default="vtp", help="extension of the deformed mesh")
    parser.add_argument("--status", required=True, help="the status file to write")
    parser.add_argument("--threads", type=int, default=1)
    parser.add_argument("--attempt", type=int, default=1, help="Snakemake's attempt number of this job")
    parser.add_argument("--attempts", type=int, default=1, help="the number of attempts Snakemake makes")
    parser.add_argument("options", nargs=argparse.REMAINDER, help="more ffd-match options, after --")
    arguments = parser.parse_args()
    options = arguments.options[1:] if arguments.options[:1] == ["--"] else arguments.options

    os.makedirs(arguments.folder, exist_ok=True)
    outputs = {
        "output": os.path.join(arguments.folder, "deformed." + arguments.mesh_format),
        "transform": os.path.join(arguments.folder, "transform.tfm"),
        "report": os.path.join(arguments.folder, "report.json"),
    }
    for path in outputs.values():
        if os.path.lexists(path):
            os.remove(path)
    log_path = os.path.join(arguments.folder, "ffd-match.log")
    command = [arguments.ffd_match, "--source", arguments.source, "--target", arguments.target,
               "--output", outputs["output"], "--transform-out", outputs["transform"], "--report", outputs["report"],
               "--threads", str(arguments.threads)] + options
    start = time.monotonic()
    with open(log_path, "w") as log:
        code = subprocess.run(command, stdout=log, stderr=subprocess.STDOUT).returncode
    seconds = time.monotonic() - start
    record = {
        "id": arguments.id,
        "status": "ok",
        "source": arguments.source,
        "target": arguments.target,
        "exit_code": code,
        "seconds": round(seconds, 3),
        "max_rss_mb": round(resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024.0, 1),
        "attempt": arguments.attempt,
        "host": socket.gethostname(),
        "command": command,
    }
    complete = all(os.path.isfile(path) for path in outputs.values())
    if code == 0 and complete:
        record.update(outputs)
    else:
        for path in outputs.values():
            if os.path.lexists(path):
                os.remove(path)
        line = error_line(log_path)
        if line is None:
            if code < 0:
                line = f"ffd-match ended by signal {signal.Signals(-code).name}"
            elif code == 0:
                line = "ffd-match exited 0 but did not write all its outputs"
            else:
                line = f"ffd-match exited with code {code} without an error line"
            line += f" (attempt {arguments.attempt} of {arguments.attempts}; see {log_path})"
            if arguments.attempt < arguments.attempts:
                print(f"{arguments.id}: {line}; Snakemake retries it", file=sys.stderr)
                return 1
        record["status"] = line
    write_status(arguments.status, record)
    print(f"{arguments.id}: {record['status']} ({seconds:.1f} s)", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
