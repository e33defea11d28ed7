#!/usr/bin/env bash
# Runs the beam examples (fewer steps, one thread) with two tensormass
# binaries and compares every output but summary.json (which holds timings)
# byte for byte: the check that a refactoring left results unchanged.
#   scripts/compare-binaries.sh OLD_TENSORMASS NEW_TENSORMASS [WORK_DIR]
# Exit 0 when identical, 1 when any output differs (the files are listed).
set -euo pipefail
if [ $# -lt 2 ]; then
  echo "usage: $0 OLD_TENSORMASS NEW_TENSORMASS [WORK_DIR]" >&2
  exit 2
fi
root="$(cd "$(dirname "$0")/.." && pwd)"
work="${3:-$(mktemp -d)}"
for tag in old new; do
  binary=$1
  [ "$tag" = new ] && binary=$2
  dir="$work/$tag"
  rm -rf "$dir" && mkdir -p "$dir"
  cp "$root"/examples/beam/*.yaml "$dir"/
  "$binary" beam -o "$dir/beam.msh" > /dev/null
  "$binary" run "$dir/static.yaml" --quiet --set solver.threads=1
  "$binary" run "$dir/implicit.yaml" --quiet --set solver.steps=40 --set solver.threads=1
  "$binary" run "$dir/explicit.yaml" --quiet --set solver.steps=500 --set solver.threads=1
  "$binary" run "$dir/adaptive.yaml" --quiet --set solver.threads=1
done
if diff -r -q -x summary.json "$work/old" "$work/new"; then
  echo "identical outputs (beam examples) in $work"
else
  echo "outputs differ (see above) in $work" >&2
  exit 1
fi
