#!/usr/bin/env bash
# Reliability build of FFDShapeMatching (issue "Reliability"): the module, its tests and programs built with
# Clang, AddressSanitizer and UndefinedBehaviorSanitizer; the WHOLE test suite run under them (any report fails
# the test that caused it); then each libFuzzer target fuzzed from its seed corpus in test/Fuzz/Corpus for
# FUZZ_RUNS (default 20000) inputs or FUZZ_SECONDS (default 60) seconds, whichever comes first, from the random
# seed FUZZ_SEED (default 1). The seed fixes libFuzzer's mutations, but not the whole run: which inputs it keeps
# follows the coverage it measures, which varies slightly between runs, and a slower machine stops earlier. A
# crash, hang (> 10 s per input), leak or sanitizer report fails the run and leaves the input in
# $build_dir/fuzz-artifacts: add it to the corpus and to the bad-input matrix as a regression test once fixed
# (test/Fuzz/Findings/README.md).
#
#   Utilities/SanitizerAndFuzzBuild.sh            build dir ./build-sanitize
#   FUZZ_SECONDS=600 FUZZ_RUNS=-1 FUZZ_SEED=0 Utilities/SanitizerAndFuzzBuild.sh   (longer, new inputs each time)
#
# Debian's ITK was built with GCC; CMake/FFDShapeMatchingClangWithDebianITK.cmake lets Clang use it.
set -euo pipefail
cd "$(dirname "$0")/.."
bash Utilities/InstallDependencies.sh
build_dir=${FFD_SANITIZE_BUILD_DIR:-build-sanitize}
fuzz_seconds=${FUZZ_SECONDS:-60}
fuzz_runs=${FUZZ_RUNS:-20000}
fuzz_seed=${FUZZ_SEED:-1}
sanitizers="-fsanitize=address,undefined"
compile_flags="$sanitizers -fno-omit-frame-pointer -g"
start=$(date +%s)

cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
  "-DCMAKE_C_FLAGS=$compile_flags" "-DCMAKE_CXX_FLAGS=$compile_flags" \
  "-DCMAKE_EXE_LINKER_FLAGS=$sanitizers" "-DCMAKE_SHARED_LINKER_FLAGS=$sanitizers" \
  -DFFDShapeMatching_BUILD_FUZZERS=ON
cmake --build "$build_dir" -j"$(nproc)"
echo "== sanitizer build: $(( $(date +%s) - start )) s =="

supp="$PWD/Utilities/Sanitizers"
export ASAN_OPTIONS="detect_leaks=1:strict_string_checks=1:detect_stack_use_after_return=1:check_initialization_order=1"
export LSAN_OPTIONS="suppressions=$supp/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="suppressions=$supp/ubsan.supp:print_stacktrace=1:halt_on_error=1"
# Every test's whole output is kept: a sanitizer report fails the run even in a test that passed on its own
# terms (tests that check a program's printed result or its failing exit code do not see the report).
status=0
(cd "$build_dir" && ctest -j"$(nproc)" --timeout 900 -V > ctest-sanitize.log 2>&1) || status=$?
grep -E "^[0-9]+/[0-9]+ Test|tests passed|tests failed" "$build_dir/ctest-sanitize.log" | tail -n 200
if grep -E "ERROR: (Address|Leak)Sanitizer|runtime error:" "$build_dir/ctest-sanitize.log"; then
  echo "error: sanitizer reports in the test output (see $build_dir/ctest-sanitize.log)" >&2
  exit 1
fi
if [ "$status" -ne 0 ]; then
  # The names of the failed tests, last, so that a log cut to its end still shows them.
  sed -n '/The following tests FAILED/,$p' "$build_dir/ctest-sanitize.log" >&2
  echo "error: tests failed under the sanitizers (see $build_dir/ctest-sanitize.log)" >&2
  exit "$status"
fi
echo "== sanitizer test run: $(( $(date +%s) - start )) s =="

if [ "$fuzz_seconds" -eq 0 ]; then
  echo "== timed fuzzing not run (FUZZ_SECONDS=0); the corpora were replayed by the test suite =="
  exit 0
fi
mkdir -p "$build_dir/fuzz-artifacts"
for fuzzer in ffdMeshFuzzer ffdTransformFuzzer; do
  case $fuzzer in
    ffdMeshFuzzer) seeds=test/Fuzz/Corpus/Mesh ;;
    ffdTransformFuzzer) seeds=test/Fuzz/Corpus/Transform ;;
  esac
  work=$(mktemp -d)
  echo "== fuzzing $fuzzer: $fuzz_runs inputs or $fuzz_seconds s, seed $fuzz_seed =="
  "$build_dir/test/Fuzz/$fuzzer" -seed="$fuzz_seed" -runs="$fuzz_runs" -max_total_time="$fuzz_seconds" \
    -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
    -artifact_prefix="$build_dir/fuzz-artifacts/$fuzzer-" "$work" "$seeds"
  rm -rf "$work"
done
echo "== sanitizer and fuzz run passed in $(( $(date +%s) - start )) s =="
