#!/usr/bin/env bash
# A run killed with SIGKILL part way and resumed with --resume
# ends bit for bit where the uninterrupted run ends (final state, frames,
# streamed tracks and adaptivity records, series), for each integrator: implicit (CHOLMOD, whose factor is
# restored), static (load-step extrapolation history) and explicit, and for
# the adaptive model (laws switching up and down with blends, the folded
# linear part's sums, the counters), and for runs that refine their mesh
# (dynamic with coarsening, and static; the mesh is replayed from the
# checkpoint's history, the refinement events in summary.json match too),
# and for a viscoelastic law (its history per quadrature point), implicit
# and explicit.
set -euo pipefail
binary=$1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
"$binary" beam --dim 3 --cells 40,6,6 --type tet6 -o beam.msh > /dev/null

write_scene() {  # name, solver block, frame every, checkpoint every[, adaptivity block]
  cat > "$1.yaml" <<YAML
mesh: beam.msh
materials:
  - {region: all, law: stvk, young: 1.0e7, poisson: 0.3, density: 1000}
fixed: [clamp]
loads:
  gravity: [0, -9.81, 0]
solver:
$2
output: {directory: out-$1, every: $3, track: [body], checkpoint_every: $4}
${5:-}
YAML
}
write_scene implicit "  {type: implicit, dt: 0.01, steps: 120, newton_iterations: 3, tolerance: 1.0e-8}" 10 7
write_scene static "  {type: static, load_steps: 60, tolerance: 1.0e-10}" 10 7
write_scene explicit "  {type: explicit, dt: 2.0e-5, steps: 3000, damping: {mass: 5}}" 500 300
write_scene adaptive "  {type: implicit, dt: 0.01, steps: 120, newton_iterations: 2}" 10 7 \
  "adaptivity: {criteria: [{name: R_NL, threshold: 0.002}], ladder: [hooke, stvk], blend_steps: 3,
  downgrade: {hysteresis: 0.5, calm_steps: 2}}"
sed -i 's/law: stvk/law: hooke/' adaptive.yaml  # the adaptive run starts under Hooke
write_scene refining "  {type: implicit, dt: 0.01, steps: 50, newton_iterations: 2, damping: {mass: 2}}" 10 7 \
  "adaptivity: {refine: {criteria: [{name: R_ZZ, threshold: 0.5}], max_level: 1, every: 3,
  coarsen: {hysteresis: 0.7, calm_steps: 2}}}"
write_scene refining_static "  {type: static, load_steps: 16, tolerance: 1.0e-10}" 4 3 \
  "adaptivity: {refine: {criteria: [{name: R_ZZ, threshold: 0.4}], max_level: 1}}"

for solver in implicit explicit; do
  sed 's/law: stvk, young: 1.0e7, poisson: 0.3/law: viscoelastic_neohookean, mu: 3.4e6, kappa: 8.0e6, g1: 0.3, tau1: 0.05, g2: 0.2, tau2: 0.5, k1: 0.1, k2: 0/; s/out-'"$solver"'/out-viscous_'"$solver"'/' \
    "$solver.yaml" > "viscous_$solver.yaml"
done

kill_and_resume() {  # name, frame to wait for
  local name=$1 frame=$2
  "$binary" run "$name.yaml" --quiet --set output.directory=reference-$name
  "$binary" run "$name.yaml" --quiet &
  local pid=$!
  while [[ ! -f out-$name/$frame ]]; do
    kill -0 "$pid" 2> /dev/null || { echo "$name: the run ended before it could be killed"; exit 1; }
    sleep 0.01
  done
  kill -KILL "$pid"
  wait "$pid" 2> /dev/null || true
  [[ ! -f out-$name/final.vtu ]] || { echo "$name: killed too late (final.vtu exists)"; exit 1; }
  [[ -f out-$name/track_body.csv.partial ]] || { echo "$name: the killed run left no streamed track"; exit 1; }
  "$binary" run "$name.yaml" --resume 2>&1 | grep "resuming from"
  local files="final.vtu series.pvd track_body.csv"
  [[ ! -f reference-$name/adaptivity.jsonl ]] || files+=" adaptivity.jsonl"
  for file in $files; do
    cmp "reference-$name/$file" "out-$name/$file" || { echo "$name: $file differs after resuming"; exit 1; }
  done
  for frame_file in reference-$name/frame_*.vtu; do
    cmp "$frame_file" "out-$name/$(basename "$frame_file")" || { echo "$name: $frame_file differs"; exit 1; }
  done
  echo "$name: killed after $frame, resumed, bitwise equal"
}
kill_and_resume implicit frame_000050.vtu
kill_and_resume static frame_000020.vtu
kill_and_resume explicit frame_001000.vtu
kill_and_resume adaptive frame_000050.vtu
kill_and_resume viscous_implicit frame_000050.vtu
kill_and_resume viscous_explicit frame_001000.vtu
grep -q '"switches": [1-9]' out-adaptive/summary.json || { echo "adaptive: no law switched"; exit 1; }
for name in refining:frame_000020.vtu refining_static:frame_000008.vtu; do
  kill_and_resume "${name%%:*}" "${name#*:}"
  name=${name%%:*}
  /usr/bin/python3 - reference-$name/summary.json out-$name/summary.json <<'PY'
import json, sys
reference, resumed = (json.load(open(path))["refinement"]["events"] for path in sys.argv[1:])
assert resumed == reference, (reference, resumed)
assert len(reference) > 1, "the mesh never changed"
print("refinement events equal:", [event["cells"] for event in reference])
PY
done
