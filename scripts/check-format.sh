#!/usr/bin/env bash
# Checks that every tracked C++ source follows .clang-format (clang-format 14,
# Debian 12). Generated code is formatted by the generator and is skipped.
# Usage: scripts/check-format.sh [--fix]   (--fix rewrites the files in place)
set -euo pipefail
cd "$(dirname "$0")/.."
mapfile -t files < <(git ls-files '*.cpp' '*.hpp' '*.h' | grep -v '^generated/')
if [ "${1:-}" = "--fix" ]; then
  clang-format -i "${files[@]}"
  exit 0
fi
if ! clang-format --dry-run --Werror "${files[@]}" 2> /tmp/tensormass-format.log; then
  grep -E '^[^ ].*: (error|warning):' /tmp/tensormass-format.log | cut -d: -f1 | sort -u | sed 's/^/  needs formatting: /'
  echo "format check failed: run scripts/check-format.sh --fix (clang-format $(clang-format --version | grep -o '[0-9][0-9.]*' | head -1))" >&2
  exit 1
fi
echo "format check: ${#files[@]} files follow .clang-format"
