#!/usr/bin/env bash
# FFDShapeMatching quick start on Debian 12.
#   ./quickstart.sh demo   install what is missing, build, run the module's demo
#   ./quickstart.sh test   install what is missing, build, run the whole test suite
# The build goes to ./build (override with FFD_BUILD_DIR).
set -euo pipefail
cd "$(dirname "$0")"
action=${1:-}
case "$action" in
  demo | test) ;;
  *)
    echo "usage: $0 demo|test" >&2
    exit 2
    ;;
esac

bash Utilities/InstallDependencies.sh
build_dir=${FFD_BUILD_DIR:-build}
jobs=$(nproc 2>/dev/null || echo 2)
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release
cmake --build "$build_dir" -j"$jobs"

if [ "$action" = demo ]; then
  # The demo's before/after picture renders off screen with VTK, which needs an X display: without one,
  # run it under a virtual X server (Debian's xvfb, installed with the other dependencies).
  if [ -z "${DISPLAY:-}" ] && command -v xvfb-run > /dev/null; then
    xvfb-run -a "$build_dir/apps/ffd-match" --demo --output-dir demo-output
  else
    "$build_dir/apps/ffd-match" --demo --output-dir demo-output
  fi
else
  # FFD_CTEST_ARGS: extra ctest arguments (the Debian 13 configuration uses it; empty by default).
  # shellcheck disable=SC2086
  (cd "$build_dir" && ctest -j"$jobs" --output-on-failure ${FFD_CTEST_ARGS:-})
fi
