#!/usr/bin/env python3
"""Snakemake's cluster-status command for the profile workflows/slurm.

  slurm-status.py JOBID      (JOBID as sbatch --parsable printed it: "ID" or "ID;CLUSTER")

Prints one line, "running", "success" or "failed", as Snakemake's generic cluster executor expects. The job's state
comes from sacct where the cluster keeps accounting (it remembers finished jobs), otherwise from scontrol (slurmctld
keeps a finished job for MinJobAge seconds, 300 by default, longer than Snakemake takes to ask again). A job neither
knows is reported failed with the reason on stderr, so that Snakemake retries it or records it instead of waiting
forever.
"""
import subprocess
import sys

# Slurm's job states (squeue(1), "JOB STATE CODES") in which the job may still complete.
UNFINISHED = {"PENDING", "RUNNING", "CONFIGURING", "COMPLETING", "SUSPENDED", "REQUEUED", "REQUEUE_FED",
              "REQUEUE_HOLD", "RESIZING", "SIGNALING", "STAGE_OUT", "STOPPED", "RESV_DEL_HOLD"}


# Why sacct or scontrol gave no state; printed only when neither does (on a cluster without accounting, sacct fails
# at every check).
PROBLEMS = []


def run(command):
    """The command's standard output, or None when it cannot be run or fails."""
    try:
        result = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, timeout=60)
    except (OSError, subprocess.TimeoutExpired) as error:
        PROBLEMS.append(f"{' '.join(command)}: {error}")
        return None
    if result.returncode != 0:
        PROBLEMS.append(f"{' '.join(command)}: {result.stderr.strip().replace(chr(10), ' / ')}")
        return None
    return result.stdout


def state_from_sacct(job):
    """The job's state as sacct records it ("CANCELLED by 0" is CANCELLED), or None."""
    output = run(["sacct", "-X", "--noheader", "--parsable2", "--format=State", "-j", job])
    lines = output.split() if output else []
    return lines[0] if lines else None


def state_from_scontrol(job):
    """The job's state as slurmctld knows it, or None."""
    output = run(["scontrol", "show", "job", "--oneliner", job])
    for field in (output or "").split():
        if field.startswith("JobState="):
            return field[len("JobState="):]
    return None


def main():
    if len(sys.argv) != 2 or not sys.argv[1].split(";")[0].isdigit():
        print(f"usage: {sys.argv[0]} JOBID (the job id sbatch --parsable printed)", file=sys.stderr)
        return 2
    job = sys.argv[1].split(";")[0]
    state = state_from_sacct(job) or state_from_scontrol(job)
    if state is None:
        print(f"slurm-status: neither sacct nor scontrol knows job {job}; reporting it failed "
              f"({'; '.join(PROBLEMS)})", file=sys.stderr)
        print("failed")
    elif state == "COMPLETED":
        print("success")
    elif state in UNFINISHED:
        print("running")
    else:
        print(f"slurm-status: job {job} ended {state}", file=sys.stderr)
        print("failed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
