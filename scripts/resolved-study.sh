#!/usr/bin/env bash
# The resolved-model studies quoted in docs/resolved-model.md and docs/diagnosis.md (issues 5 and 6;
# not part of CI: about an hour on this 2-core machine, most of it the default bed and the 28 lab
# impacts). Every campaign resumes where it stopped: run it again after a kill.
#
#   scripts/resolved-study.sh BUILD_DIR [OUT_DIR] [RANKS]
#
# 1. lab-cylinders: the 28 lab releases' incident states on the default bed -> validation
#    (`upscale --lab`: resolved V_out against the lab's, figure and KS tests).
# 2. speeds: the lab's mean impact scaled by 0.5-1.5 at two positions on the bed -> the upscaling
#    abacus against the incident speed, and the diagnosis with LIGGGHTS as the truth (compare,
#    diagnose, ladder with the best-ranked effect).
# 3. grain-stiffness: three grain Young's moduli x three replica beds on the small slab -> the
#    abacus against a grain-scale parameter.
# 4. lab-cylinders-replicas: the 28 lab states at two positions on the bed (56 impacts) -> the
#    diagnosis of the paper's law against resolved impacts at the lab's incident states, with a
#    replicate noise floor.
set -euo pipefail
BUILD=$(cd "$1" && pwd)
ROOT=$(cd "$(dirname "$0")/.." && pwd)
OUT=${2:-$ROOT/results/resolved}
RANKS=${3:-2}
R="$BUILD/cli/ricochet"
MPI="mpirun --oversubscribe --allow-run-as-root --bind-to none -np $RANKS"
C=$ROOT/liggghts-inputs/campaigns
mkdir -p "$OUT"
cd "$OUT"   # the designs' cache_dir and work_dir are relative to the working directory

for name in lab-cylinders speeds grain-stiffness lab-cylinders-replicas; do
  echo "== campaign $name ($(date +%H:%M:%S))"
  $MPI "$R" dem campaign "$C/$name.toml" --decks "$ROOT/liggghts-inputs" --out "$OUT/$name.h5" \
    --retry-crashed
done

echo "== upscaling and validation ($(date +%H:%M:%S))"
"$R" upscale "$OUT/lab-cylinders.h5" --lab "$ROOT/data/lab/cylinders.csv" \
  --figures "$OUT/figures/lab-cylinders" --json > "$OUT/upscale-lab-cylinders.json"
"$R" upscale "$OUT/speeds.h5" --figures "$OUT/figures/speeds" --json > "$OUT/upscale-speeds.json"
"$R" upscale "$OUT/grain-stiffness.h5" --figures "$OUT/figures/grain-stiffness" \
  --json > "$OUT/upscale-grain-stiffness.json"

echo "== diagnosis with LIGGGHTS as the truth ($(date +%H:%M:%S))"
"$R" compare "$OUT/speeds.h5" --shape cylinder --figures "$OUT/figures/compare-speeds" \
  --json > "$OUT/compare-speeds.json"
"$R" diagnose "$OUT/speeds.h5" --shape cylinder --figures "$OUT/figures/diagnose-speeds" \
  --json > "$OUT/diagnose-speeds.json"
BEST=$(python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['ranking'][0]['effect'])" \
  "$OUT/diagnose-speeds.json")
"$R" ladder "$OUT/speeds.h5" --shape cylinder --add "$BEST" --figures "$OUT/figures/ladder-speeds" \
  --json > "$OUT/ladder-speeds.json"
"$R" diagnose "$OUT/lab-cylinders.h5" --shape cylinder --json > "$OUT/diagnose-lab-cylinders.json"
"$R" diagnose "$OUT/speeds.h5" --shape cylinder --no-features --json > "$OUT/diagnose-speeds-vout.json"
"$R" upscale "$OUT/lab-cylinders-replicas.h5" --lab "$ROOT/data/lab/cylinders.csv" \
  --figures "$OUT/figures/lab-cylinders-replicas" --json > "$OUT/upscale-lab-cylinders-replicas.json"
for f in "" --no-features; do
  "$R" diagnose "$OUT/lab-cylinders-replicas.h5" --shape cylinder $f --json \
    > "$OUT/diagnose-lab-cylinders-replicas${f}.json"
done
echo "== done ($(date +%H:%M:%S)): results in $OUT"
