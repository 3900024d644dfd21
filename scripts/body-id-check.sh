#!/usr/bin/env bash
# What the grains' unset body ids did to an impact (fixed on 2026-12-05, liggghts-inputs/impact/
# setup.in: `set group grains mol -1`). Before the fix, fix multisphere left the body id of the
# grains read from the bed's restart uninitialised: zeros in a fresh process, whose own
# `neigh_modify exclude molecule` then dropped every grain pair (and its contact history) from the
# impact's first neighbour list. Each impact here runs in a process of its own, the case of the
# first impact of every campaign rank (and of every resumed campaign).
#
#   scripts/body-id-check.sh [RICOCHET] [OUT.tsv] [STATES]
#
# The same impact with the decks of 006ac22 (before the fix) and with the tree's, on one bed of
# the tests' grains (4-6 mm, E_grain 2e8 Pa) 1.5 x 0.10 x 0.10 m (about 19,000 grains), for
# STATES incident states (default 8: V_in (2.6-3.3, -2.0 to -2.56) m/s, omega -65 rad/s, landing
# at x 0.22-0.36 of the bed). Writes one row per state (V_out before, V_out after) and prints on
# stderr the mean difference (after - before) per component with its 95 % t interval over the
# states, and the mean |difference|. Resumable: each impact's JSON is kept in
# results/body-id-check/ and not run again. About a minute per impact on a quiet core.
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
export PYTHONPATH="$ROOT/scripts${PYTHONPATH:+:$PYTHONPATH}"  # study_stats.py
BIN=${1:-$ROOT/build/cli/ricochet}
OUT=${2:-/dev/stdout}
STATES=${3:-8}
RES=$ROOT/results/body-id-check
mkdir -p "$RES/dem-cache"
if [ ! -d "$RES/decks-006ac22/liggghts-inputs" ]; then
  rm -rf "$RES/decks-006ac22.tmp" && mkdir -p "$RES/decks-006ac22.tmp"
  git -C "$ROOT" archive 006ac22 liggghts-inputs | tar -x -C "$RES/decks-006ac22.tmp"
  mv "$RES/decks-006ac22.tmp" "$RES/decks-006ac22"
fi
source "$ROOT/scripts/long-test-bed.sh"
"$BIN" dem bed "${LONG_TEST_BED[@]}" --decks "$ROOT/liggghts-inputs" --cache "$RES/dem-cache" >&2
printf 'state\tvx_in_mps\tvy_in_mps\tx_impact_frac\tbefore_vout_x\tbefore_vout_y\tbefore_wout\tafter_vout_x\tafter_vout_y\tafter_wout\n' > "$RES/out.tsv"
for ((i = 0; i < STATES; i++)); do
  frac=$(awk -v i="$i" 'BEGIN { print 0.22 + 0.02 * i }')
  vx=$(awk -v i="$i" 'BEGIN { print 2.6 + 0.1 * i }')
  vy=$(awk -v i="$i" 'BEGIN { print -2.0 - 0.08 * i }')
  for d in before after; do
    decks=$ROOT/liggghts-inputs
    [ "$d" = before ] && decks=$RES/decks-006ac22/liggghts-inputs
    json=$RES/$d-$i.json
    [ -s "$json" ] && continue
    "$BIN" dem impact "${LONG_TEST_BED[@]}" "${LONG_TEST_BLOCK[@]}" --set "run.x_impact_frac=$frac" \
      --vin "$vx,$vy,-65" --decks "$decks" --cache "$RES/dem-cache" --work "$RES/work-$d" \
      --id "s$i" --json > "$json.tmp"
    mv "$json.tmp" "$json"
    echo "  state $i, $d: $(jq -c '[.status, .vout]' "$json")" >&2
  done
  printf '%s\t%s\t%s\t%s\t%s\t%s\n' "$i" "$vx" "$vy" "$frac" \
    "$(jq -r '.vout | @tsv' "$RES/before-$i.json")" "$(jq -r '.vout | @tsv' "$RES/after-$i.json")" \
    >> "$RES/out.tsv"
done
cat "$RES/out.tsv" > "$OUT"
# Mean paired difference with its 95 % Student t interval, and the mean absolute difference.
python3 - "$RES/out.tsv" <<'PY' >&2
import csv, sys
from study_stats import paired_t
rows = list(csv.reader(open(sys.argv[1]), delimiter="\t"))[1:]
print(f"{len(rows)} states; after - before (95 % t interval), mean |after - before|:")
for k, name in enumerate(("V_out^x [m/s]", "V_out^y [m/s]", "omega_out [rad/s]")):
    d = [float(r[7 + k]) - float(r[4 + k]) for r in rows]
    m, lo, hi = paired_t(d)
    print(f"  {name:<18} {m:+.4f} [{lo:+.4f}, {hi:+.4f}]   {sum(abs(x) for x in d) / len(d):.4f}")
PY
