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
# Mean paired difference with its 95 % t interval (Student's t quantiles for 1-30 degrees of
# freedom), and the mean absolute difference.
awk -F'\t' 'BEGIN { split("12.706 4.303 3.182 2.776 2.571 2.447 2.365 2.306 2.262 2.228 2.201 2.179 2.160 2.145 2.131 2.120 2.110 2.101 2.093 2.086 2.080 2.074 2.069 2.064 2.060 2.056 2.052 2.048 2.045 2.042", tq, " ")
    name[0] = "V_out^x [m/s]"; name[1] = "V_out^y [m/s]"; name[2] = "omega_out [rad/s]" }
  NR > 1 { n++; for (k = 0; k < 3; k++) { d = $(8 + k) - $(5 + k); s[k] += d; ss[k] += d * d
      a[k] += (d < 0 ? -d : d) } }
  END { printf "%d states; after - before (95 %% t interval), mean |after - before|:\n", n > "/dev/stderr"
    for (k = 0; k < 3; k++) { m = s[k] / n; sd = sqrt((ss[k] - n * m * m) / (n - 1))
      h = tq[n - 1] * sd / sqrt(n)
      printf "  %-18s %+.4f [%+.4f, %+.4f]   %.4f\n", name[k], m, m - h, m + h, a[k] / n > "/dev/stderr" } }' \
  "$RES/out.tsv"
