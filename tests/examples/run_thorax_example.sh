#!/usr/bin/env bash
# Runs the thorax demo (examples/thorax/run.sh, as the README gives it) in a
# scratch folder and checks the demo's figures on its outputs: the tumour
# track of the adaptive run within 1 mm of the pure-StVK run's, both tracks
# and the real-time factors written, frames and pictures present.
set -euo pipefail
binary=$1
source_dir=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
WORK="$work" TENSORMASS="$binary" bash "$source_dir/examples/thorax/run.sh" > "$work/log.txt" 2>&1 ||
  { cat "$work/log.txt"; exit 1; }
sed -n '/== tumour track/,$p' "$work/log.txt"
for file in thorax.msh out/tumour_track.png out/thorax.png out/thorax_inspiration.png \
            out/adaptive/track_tumour.csv out/stvk/track_tumour.csv out/adaptive/series.pvd; do
  test -s "$work/$file" || { echo "missing $file"; exit 1; }
done
/usr/bin/python3 - "$work" "$source_dir" <<'PY'
import json, subprocess, sys
work, source = sys.argv[1], sys.argv[2]
out = subprocess.run(["/usr/bin/python3", f"{source}/scripts/compare_tracks.py", f"{work}/out/adaptive/track_tumour.csv",
                      f"{work}/out/stvk/track_tumour.csv", "--json"], check=True, capture_output=True, text=True).stdout
difference = json.loads(out)
print("adaptive vs stvk:", difference)
assert difference["max_mm"] < 1.0, f"tumour trajectories differ by {difference['max_mm']} mm (target < 1 mm)"
for run in ("adaptive", "stvk"):
    summary = json.load(open(f"{work}/out/{run}/summary.json"))
    assert summary["status"] == "ok", run
    assert summary["real_time_factor"] > 0, run
    print(f"{run}: real-time factor {summary['real_time_factor']:.2f}")
adaptive = json.load(open(f"{work}/out/adaptive/summary.json"))
assert adaptive["switches"] > 0, "the adaptive run switched no element"
PY
echo "thorax example ran"
