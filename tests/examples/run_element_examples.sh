#!/usr/bin/env bash
# Runs examples/elements/cantilever.yaml on beams of each quadratic element
# that `tensormass beam` makes from the registry (quad8, quad9 in 2D; hex20,
# hex27, prism15, pyramid13 with tet10 in 3D) and checks that each sags
# within 1 % of the serendipity element of its dimension on the same grid
# (0.04 to 0.32 % measured): the elements reach the solver, its loads and
# its outputs through their element files alone.
set -euo pipefail
binary=$1
source_dir=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cp "$source_dir/examples/elements/cantilever.yaml" "$work/"
sag() { /usr/bin/python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))["max_displacement"]["value"])' "$work/out-cantilever/summary.json"; }
run() {  # run DIM TYPE CELLS: prints the sag
  "$binary" beam --dim "$1" --type "$2" --cells "$3" -o "$work/beam.msh" > /dev/null
  "$binary" run "$work/cantilever.yaml" --quiet
  for file in final.vtu series.pvd summary.json; do
    test -s "$work/out-cantilever/$file" || { echo "$2: missing out-cantilever/$file" >&2; exit 1; }
  done
  grep -q '"status": "ok"' "$work/out-cantilever/summary.json"
  sag
}
check() {  # check DIM CELLS REFERENCE TYPE...
  local dim=$1 cells=$2 reference=$3
  shift 3
  local expected
  expected=$(run "$dim" "$reference" "$cells")
  for type in "$@"; do
    local got
    got=$(run "$dim" "$type" "$cells")
    echo "$type sags $got m, $reference $expected m"
    awk -v a="$expected" -v b="$got" 'BEGIN { d = (a - b) / a; if (d < 0) d = -d; exit !(d < 0.01) }' ||
      { echo "$type: sag $got differs from $reference's $expected by more than 1 %"; exit 1; }
  done
}
check 2 12,2 quad8 quad9
check 3 12,2,2 hex20 hex27 prism15 pyramid13
echo "element examples ran"
