#!/usr/bin/env bash
# Runs the README's beam commands as written (in a scratch copy of
# examples/beam, with fewer steps) and checks that each writes its outputs.
set -euo pipefail
binary=$1
source_dir=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cp "$source_dir"/examples/beam/*.yaml "$work"/
"$binary" beam -o "$work/beam.msh"
"$binary" run "$work/static.yaml" --quiet
"$binary" run "$work/implicit.yaml" --quiet --set solver.steps=20
"$binary" run "$work/explicit.yaml" --quiet --set solver.steps=500
"$binary" run "$work/adaptive.yaml" --quiet
for out in out-static out-implicit out-explicit out-adaptive; do
  for file in final.vtu series.pvd summary.json; do
    test -s "$work/$out/$file" || { echo "missing $out/$file"; exit 1; }
  done
  grep -q '"status": "ok"' "$work/$out/summary.json"
done
echo "beam examples ran"
