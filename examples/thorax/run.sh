#!/usr/bin/env bash
# The thorax demo end to end: the synthetic thorax (make_thorax.py), its
# mesh with a region of interest around the tumour, two breathing cycles
# under the adaptive model and under pure St Venant-Kirchhoff, the tumour's
# track of both runs and a picture.
#
#   examples/thorax/run.sh            (from any directory)
#
# Environment:
#   TENSORMASS  the binary (default build/tensormass); a relative path is taken
#               from the repository root, a bare name is looked up on PATH
#   WORK        where the files go (default: this folder)
#   EDGE        surface triangle edge in metres (default 0.018: about the
#               mesher's cells near the surface, --size 0.02 with --levels 0)
#
# Writes into examples/thorax/: the STL surfaces and thorax.json, thorax.msh,
# out/adaptive/ and out/stvk/ (final.vtu, frames, series.pvd, summary.json,
# track_tumour.csv), out/tumour_track.png, out/thorax.png (end of the run)
# and out/thorax_inspiration.png (t = 2 s, the diaphragm at its lowest).
# Prints the element counts, the real-time factor of each run and the
# tumour trajectory difference between the adaptive and the StVK run.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/../.." && pwd)"
python=/usr/bin/python3

binary="${TENSORMASS:-build/tensormass}"
case "$binary" in
  /*) ;;
  */*) binary="$root/$binary" ;;
  *) binary="$(command -v "$binary" || echo "$root/$binary")" ;;
esac
if [[ ! -x "$binary" ]]; then
  echo "run.sh: no tensormass binary at $binary (build it, or set TENSORMASS)" >&2
  exit 2
fi

work="${WORK:-$here}"
mkdir -p "$work"
[[ "$work" -ef "$here" ]] || cp "$here/thorax.yaml" "$work/"
cd "$work"
step() { printf '\n== %s\n' "$*"; }

step "surfaces"
"$python" "$here/make_thorax.py" --out "$work" --edge "${EDGE:-0.018}"
# The region of interest: a ball of twice the tumour's radius around it.
roi="$("$python" -c 'import json, sys; t = json.load(open(sys.argv[1]))["tumour"]; print(*t["centre"], 2 * t["radius"], sep=",")' thorax.json)"

# --layer 0.5: prisms 1 cm thick on the surface; the default 0.5 cm ones get
# inverted where the descending diaphragm shears the fixed rim.
step "mesh (2 cm hexahedra, 1 cm in the region of interest $roi, 1 cm prism layer)"
"$binary" mesh thorax.stl --size 0.02 --levels 0 --layer 0.5 --roi "$roi,0.01" \
  --region tumour=tumour.stl --region lung_right=lung_right.stl --region lung_left=lung_left.stl \
  -o thorax.msh
"$binary" mesh-info thorax.msh

step "adaptive run (Hooke, upgraded to StVK where R_NL > 0.005)"
"$binary" run thorax.yaml

step "reference run (pure StVK)"
"$binary" run thorax.yaml \
  --set materials.0.law=stvk --set materials.1.law=stvk \
  --set materials.2.law=stvk --set materials.3.law=stvk \
  --set adaptivity= --set output.directory=out/stvk

step "tumour track"
"$python" "$root/scripts/plot_track.py" out/adaptive/track_tumour.csv out/stvk/track_tumour.csv \
  --label adaptive --label stvk -o out/tumour_track.png \
  --title "tumour centroid, adaptive (Hooke -> StVK by R_NL) vs pure StVK"
for run in adaptive stvk; do
  "$python" - "out/$run/summary.json" "$run" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
print(f"{sys.argv[2]}: real-time factor {s['real_time_factor']:.2f}"
      f" ({s['simulated_seconds']:g} s simulated in {s['time_loop_seconds']:.2f} s)")
PY
done
"$python" "$root/scripts/compare_tracks.py" out/adaptive/track_tumour.csv out/stvk/track_tumour.csv

step "pictures"
"$binary" render out/adaptive/final.vtu -o out/thorax.png
if [[ -f out/adaptive/frame_000040.vtu ]]; then
  "$binary" render out/adaptive/frame_000040.vtu -o out/thorax_inspiration.png
fi
echo
echo "done: $work/out"
