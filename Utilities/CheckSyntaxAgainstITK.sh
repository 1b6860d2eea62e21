#!/usr/bin/env bash
# Checks that every translation unit of FFDShapeMatching compiles against another ITK release, without building
# that ITK: only its configured build tree is needed (its generated headers and ITKConfig.cmake).
#   bash Utilities/CheckSyntaxAgainstITK.sh ITK_BUILD_DIR [WORK_DIR]
# ITK_BUILD_DIR: an ITK source tree configured with CMake (for instance ITK's main branch, fetched outside this
# repository and configured with -DITK_LEGACY_REMOVE=ON -DITK_FUTURE_LEGACY_REMOVE=ON -DBUILD_TESTING=OFF). The
# module is configured against it in external-module mode with compile_commands.json, and each of its compile
# commands runs with -fsyntax-only. Prints one line per failing file and the compiler's first errors; exits 1 when
# any file fails. Nothing of ITK is copied into the repository.
set -euo pipefail
cd "$(dirname "$0")/.."
if [ $# -lt 1 ] || [ ! -f "$1/ITKConfig.cmake" ]; then
  echo "usage: $0 ITK_BUILD_DIR [WORK_DIR]   (ITK_BUILD_DIR must hold a configured ITK's ITKConfig.cmake)" >&2
  exit 2
fi
itk_build=$(cd "$1" && pwd)
work=${2:-$(mktemp -d)}
mkdir -p "$work"
cmake -S . -B "$work/module" -DITK_DIR="$itk_build" -DBUILD_TESTING=ON -DCMAKE_EXPORT_COMPILE_COMMANDS=ON \
  -DITK_USE_KWSTYLE=OFF -DITK_USE_CLANG_FORMAT=OFF -DCMAKE_CXX_COMPILER_LAUNCHER= >"$work/configure.log" 2>&1 || {
  tail -n 30 "$work/configure.log" >&2
  echo "error: configuring the module against $itk_build failed (log: $work/configure.log)" >&2
  exit 1
}
python3 - "$work/module/compile_commands.json" "$work" "$(nproc 2>/dev/null || echo 2)" <<'PYTHON'
import concurrent.futures
import json
import os
import shlex
import subprocess
import sys

commands_file, work, jobs = sys.argv[1], sys.argv[2], int(sys.argv[3])
source_root = os.getcwd()
entries = [e for e in json.load(open(commands_file)) if e["file"].startswith(source_root)]
# Generated test drivers and files outside the module are not the module's code.
entries = [e for e in entries if "/CMakeFiles/" not in e["file"]]


def check(entry):
    args = shlex.split(entry["command"]) if "command" in entry else list(entry["arguments"])
    cleaned = []
    skip = False
    for a in args:
        if skip:
            skip = False
            continue
        if a == "-o":
            skip = True
            continue
        if a.startswith("-o") and len(a) > 2:
            continue
        cleaned.append(a)
    if os.path.basename(cleaned[0]) == "ccache":
        cleaned = cleaned[1:]
    cleaned.append("-fsyntax-only")
    result = subprocess.run(cleaned, cwd=entry["directory"], capture_output=True, text=True)
    return entry["file"], result.returncode, result.stderr


failed = 0
with concurrent.futures.ThreadPoolExecutor(max_workers=jobs) as pool:
    for path, code, stderr in pool.map(check, entries):
        relative = os.path.relpath(path, source_root)
        if code != 0:
            failed += 1
            errors = [line for line in stderr.splitlines() if "error" in line][:5]
            print("FAIL " + relative)
            for line in errors:
                print("    " + line)
        else:
            print("ok   " + relative)
print("%d of %d translation units compile against the ITK of %s" % (len(entries) - failed, len(entries), commands_file))
sys.exit(1 if failed else 0)
PYTHON
