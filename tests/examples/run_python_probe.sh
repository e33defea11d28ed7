#!/usr/bin/env bash
# examples.python_probe: examples/python/probe_drag.py as the README runs it
# (defaults), into a scratch directory; it must write its frames, the force
# table and the plot, and the probe must feel the tissue push back (the
# vertical force grows with depth).
# Usage: run_python_probe.sh PYTHON_PACKAGE_DIR SOURCE_DIR
set -euo pipefail
package=$1 source=$2
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
PYTHONPATH=$package MPLBACKEND=Agg /usr/bin/python3 "$source/examples/python/probe_drag.py" -o "$scratch/out"
for file in series.pvd final.vtu summary.json force.csv force.png; do
  test -s "$scratch/out/$file" || { echo "missing $file" >&2; exit 1; }
done
/usr/bin/python3 - "$scratch/out/force.csv" <<'PY'
import sys
import numpy as np
rows = np.loadtxt(sys.argv[1], delimiter=",", skiprows=1)
pressing = rows[rows[:, 1] == 0.0]
vertical = pressing[:, 4]
assert len(pressing) >= 2 and (np.diff(vertical) > 0).all() and vertical[0] > 0, vertical
dragging = rows[rows[:, 1] > 0.0]
assert (dragging[:, 3] < 0).all(), dragging[:, 3]  # the tissue resists the drag
print(f"force at full depth {vertical[-1]:.3f} N; drag force at the end {-dragging[-1, 3]:.3f} N")
PY
