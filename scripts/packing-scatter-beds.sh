#!/usr/bin/env bash
# The solid fractions of docs/resolved-calibration.md, "Packing from release to release": the seven
# beds of liggghts-inputs/campaigns/lab-cylinders-packing-scatter.toml (its [bed]: E_grain_Pa
# 1.5e7, mur_gg 0.66; bed j poured with mu_pour 0.18 + j (0.2 / 6) on replica seed j, the design's
# release k on bed k mod 7), built or found in the cache and measured by `ricochet dem bed`
# (the grains' volume over the levelled bed's, src-ext/bed.hpp). About 4 min of one core per bed
# when not cached; prints one markdown table row per bed.
#
#   scripts/packing-scatter-beds.sh [RICOCHET] [CACHE]     (defaults build/cli/ricochet,
#                                                           results/packing-scatter/dem-cache)
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
BIN=${1:-$ROOT/build/cli/ricochet}
CACHE=${2:-$ROOT/results/packing-scatter/dem-cache}
[ -x "$BIN" ] || { echo "packing-scatter-beds: no program $BIN" >&2; exit 2; }
mkdir -p "$CACHE"
echo "| bed (seed) | mu_pour | grains | solid fraction | bulk density [kg/m^3] |"
echo "| --: | --: | --: | --: | --: |"
MU=(0.18 0.2133 0.2467 0.28 0.3133 0.3467 0.38)
for j in 0 1 2 3 4 5 6; do
  "$BIN" dem bed --cache "$CACHE" --decks "$ROOT/liggghts-inputs" --seed "$j" \
    --set bed.E_grain_Pa=1.5e7 --set bed.mur_gg=0.66 --set "bed.mu_pour=${MU[$j]}" --json |
    python3 -c "import json,sys; d=json.load(sys.stdin); print(f\"| $j | ${MU[$j]} | {d['grains']} | {d['solid_fraction']:.3f} | {d['bulk_density_kg_m3']:.0f} |\")"
done
