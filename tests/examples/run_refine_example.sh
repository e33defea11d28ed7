#!/usr/bin/env bash
# Runs the README's refinement example as written (in a scratch copy of
# examples/refine) and checks that the mesh was refined: more cells at the
# end than the 200 it starts with, a `level` field, refinement events.
set -euo pipefail
binary=$1
source_dir=$2
python=${3:-/usr/bin/python3}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cp "$source_dir"/examples/refine/plate_probe.yaml "$source_dir"/examples/refine/make_plate.py "$work"/
"$python" "$work/make_plate.py" > /dev/null
"$binary" run "$work/plate_probe.yaml" --quiet
for file in final.vtu series.pvd summary.json; do
  test -s "$work/out-refine/$file" || { echo "missing out-refine/$file"; exit 1; }
done
grep -q '"status": "ok"' "$work/out-refine/summary.json"
grep -q 'Name="level"' "$work/out-refine/final.vtu" || { echo "final.vtu has no level field"; exit 1; }
"$python" - "$work/out-refine/summary.json" <<'PY'
import json, sys
events = json.load(open(sys.argv[1]))["refinement"]["events"]
cells = [e["cells"] for e in events]
assert cells[0] == 200 and cells[-1] > 200, cells
print("refine example: cells", cells)
PY
