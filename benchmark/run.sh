#!/usr/bin/env bash
# The benchmark in one command (benchmark/README.md): installs what is missing (Debian packages), builds the
# project in ./build (FFD_BUILD_DIR overrides), generates the cases, runs the module's methods and the peers,
# and writes benchmark/RESULTS.md, benchmark/results.json and benchmark/charts/*.png.
#   benchmark/run.sh                 the full benchmark (4 meshes x 2 regimes x 3 seeds)
#   benchmark/run.sh --smoke         the small smoke case
#   benchmark/run.sh --help          every option (--meshes, --regimes, --seeds, --methods, --peers, --grid, ...)
set -euo pipefail
cd "$(dirname "$0")/.."
exec python3 benchmark/run_benchmark.py "$@"
