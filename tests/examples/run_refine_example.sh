#!/usr/bin/env bash
# Runs the refinement examples as written (in a scratch copy of
# examples/refine) and checks that the mesh was refined: more cells at the
# end than it starts with (200 quads; 500 hexes), a `level` field,
# refinement events.
set -euo pipefail
binary=$1
source_dir=$2
python=${3:-/usr/bin/python3}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cp "$source_dir"/examples/refine/*.yaml "$source_dir"/examples/refine/make_*.py "$work"/
check() {  # scene, output directory, cells at the start
  "$binary" run "$work/$1" --quiet
  for file in final.vtu series.pvd summary.json; do
    test -s "$work/$2/$file" || { echo "missing $2/$file"; exit 1; }
  done
  grep -q '"status": "ok"' "$work/$2/summary.json"
  grep -q 'Name="level"' "$work/$2/final.vtu" || { echo "$2/final.vtu has no level field"; exit 1; }
  "$python" - "$work/$2/summary.json" "$3" "$1" <<'PY'
import json, sys
events = json.load(open(sys.argv[1]))["refinement"]["events"]
cells = [e["cells"] for e in events]
assert cells[0] == int(sys.argv[2]) and cells[-1] > cells[0], cells
print(sys.argv[3], "cells", cells)
PY
}
"$python" "$work/make_plate.py" > /dev/null
check plate_probe.yaml out-refine 200
"$python" "$work/make_block.py" > /dev/null
check block_probe.yaml out-block 500
