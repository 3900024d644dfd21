#!/usr/bin/env bash
# The detection benchmark of docs/detection-benchmark.md (issue 10, item 5; not part of CI: about
# half an hour on this 2-core machine). Truth sets come from the independent simulator
# (tests/detection/truth_sim.hpp: another code, integrator, time step and stiffness; hidden
# physics in non-catalog forms; release-to-release scatter; lab-like noise; velocities only) and
# are diagnosed by `ricochet diagnose` with its defaults, which reads only the set's file.
#
#   scripts/detection-study.sh BUILD_DIR [OUT_DIR] [SEEDS] [NULLS]
#
# Cells: every family at 1, 1/2 and 1/4 of its reference (literature-based) strength, at the
# strength whose mean V_out shift reaches the lab's Table 1 scale ("lab"), and at twice that;
# 40 releases, lab design (the lab's incident states resampled); the lab-scale cells also at the
# lab's 28 releases and in the wide design; SEEDS seeds per cell (default 10); NULLS null sets
# (default 40); two effects at once (ladder --auto). Resumable: a set whose diagnosis exists is
# skipped. The table: DIR/summary.md (detection_summary, Wilson 95 % intervals).
set -euo pipefail
BUILD=$(cd "$1" && pwd)
ROOT=$(cd "$(dirname "$0")/.." && pwd)
OUT=${2:-$ROOT/results/detection}
SEEDS=${3:-10}
NULLS=${4:-40}
T="$BUILD/tests/detection/independent_truth"
R="$BUILD/cli/ricochet"
mkdir -p "$OUT"
done_sets=0

one() {  # NAME ARGS...: one set and its diagnosis
  local name=$1; shift
  [ -f "$OUT/$name.diagnose.json" ] && return 0
  "$T" "$@" --out "$OUT/$name.csv" --truth "$OUT/$name.truth.json"
  "$R" diagnose "$OUT/$name.csv" --shape cylinder --json > "$OUT/$name.diagnose.json.tmp"
  mv "$OUT/$name.diagnose.json.tmp" "$OUT/$name.diagnose.json"
  done_sets=$((done_sets + 1))
  echo "[$(date +%H:%M:%S)] $name: $(python3 -c "import json,sys; d=json.load(open(sys.argv[1])); r=d['ranking']; print(d['verdict'], '|', r[0]['effect'] if r else '-', 'supported' if r and r[0]['supported'] else '')" "$OUT/$name.diagnose.json")"
}

for fam in crsp_restitution kd_drag spin_rolling depth_friction_exp rankine_plough; do
  lab_file="$OUT/$fam.lab-strength"
  [ -f "$lab_file" ] || "$T" --family "$fam" --calibrate-shift --design lab --n 40 --seed 1 > "$lab_file"
  lab=$(cat "$lab_file")
  twice=$(python3 -c "print(2 * float('$lab'))")
  for s in 1 0.5 0.25 "$lab" "$twice"; do
    for seed in $(seq 1 "$SEEDS"); do
      one "$fam-s$s-n40-lab-$seed" --family "$fam" --strength "$s" --n 40 --design lab --seed "$seed"
    done
  done
  for seed in $(seq 1 "$SEEDS"); do
    one "$fam-s$lab-n28-lab-$seed" --family "$fam" --strength "$lab" --n 28 --design lab --seed "$seed"
  done
done
for seed in $(seq 1 "$NULLS"); do
  one "none-n40-lab-$seed" --family none --strength 0 --n 40 --design lab --seed "$((1000 + seed))"
done
echo "== summary"
"$BUILD/tests/detection/detection_summary" "$OUT" | tee "$OUT/summary.md"
