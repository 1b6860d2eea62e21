#!/usr/bin/env bash
# Checks that every C++ file of the repository is formatted by clang-format 14 with the repository's .clang-format
# (ITK's style). Prints each file that is not and exits 1; `Utilities/CheckFormat.sh --fix` formats them instead.
set -euo pipefail
cd "$(dirname "$0")/.."
format=$(command -v clang-format-14 || command -v clang-format || true)
if [ -z "$format" ]; then
  echo "clang-format 14 is missing (Debian: apt-get install clang-format-14)" >&2
  exit 1
fi
mapfile -t files < <(git ls-files '*.h' '*.hxx' '*.cxx' '*.cpp')
if [ "${1:-}" = --fix ]; then
  "$format" -i "${files[@]}"
  exit 0
fi
bad=0
for file in "${files[@]}"; do
  if ! "$format" --dry-run -Werror "$file" > /dev/null 2>&1; then
    echo "not clang-format clean: $file (Utilities/CheckFormat.sh --fix)"
    bad=1
  fi
done
if [ "$bad" -eq 0 ]; then
  echo "clang-format: ${#files[@]} files clean"
fi
exit "$bad"
