#!/usr/bin/env bash
# Throughput of the batch workflow (workflows/Snakefile): pairs per minute for generated pairs (an ellipsoid template
# of 162 vertices, smoothly deformed targets; workflows/scripts/make_pairs.py) with ffd-match's default method and
# settings, one thread per pair, for each COUNT and CORES. Prints one line per run and the population's median
# time and peak memory per pair. Extra Snakemake arguments come from the environment variable SNAKEMAKE_ARGS
# (e.g. "--profile workflows/slurm --jobs 2"); with SLURM_LOCAL=1 the runs go to a single-node Slurm on localhost
# started for them (workflows/test/local_slurm.sh, stopped at the end).
#   benchmark/workflow_throughput.sh FFD_MATCH WORKDIR "8 32" "1 2"
set -euo pipefail
ffd_match=$(realpath "$1")
workdir=$2
counts=${3:-"8 32"}
cores_list=${4:-"1 2"}
here=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$workdir"
workdir=$(realpath "$workdir")
if [ "${SLURM_LOCAL:-0}" = 1 ]; then
  source "$here/workflows/test/local_slurm.sh"
  trap slurm_stop EXIT
  rm -rf "$workdir/slurm"
  slurm_start "$workdir/slurm"
  export USER=${USER:-root}
fi
for count in $counts; do
  rm -rf "$workdir/pairs-$count"
  python3 "$here/workflows/scripts/make_pairs.py" --count "$count" --out "$workdir/pairs-$count"
  for cores in $cores_list; do
    out=$workdir/out-$count-$cores
    rm -rf "$out" "$workdir/.snakemake"
    start=$(date +%s.%N)
    # shellcheck disable=SC2086
    snakemake -q --snakefile "$here/workflows/Snakefile" --directory "$workdir" --cores "$cores" ${SNAKEMAKE_ARGS:-} \
      --config manifest="$workdir/pairs-$count/pairs.csv" outdir="$out" ffd_match="$ffd_match" > "$out.log" 2>&1
    end=$(date +%s.%N)
    python3 - "$out/population.json" "$count" "$cores" "$start" "$end" "$(cut -d' ' -f1-3 /proc/loadavg)" "${SNAKEMAKE_ARGS:-}" <<'PY'
import json, sys
summary = json.load(open(sys.argv[1]))["summary"]
count, cores, start, end, load = int(sys.argv[2]), int(sys.argv[3]), float(sys.argv[4]), float(sys.argv[5]), sys.argv[6]
wall = end - start
print(f"{count} pairs, {cores} cores{' ' + sys.argv[7] if sys.argv[7] else ''}: {wall:.1f} s, {60 * count / wall:.1f} pairs/min; {summary['ok']} ok; "
      f"per pair median {summary['seconds']['median']:.2f} s (max {summary['seconds']['max']:.2f}), "
      f"peak memory median {summary['max_rss_mb']['median']:.0f} MB (max {summary['max_rss_mb']['max']:.0f}); "
      f"load average after: {load}")
PY
  done
done
