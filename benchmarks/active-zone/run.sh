#!/usr/bin/env bash
# The active zone (run.active_zone_m, liggghts-inputs/impact/zone.in): how much it saves and how
# far it moves V_out, against the whole bed. One bed of the tests' grains (4-6 mm, E_grain 2e8
# Pa, the small test bed's law) but as long as the sand campaigns' reruns: 1.5 x 0.10 x 0.10 m,
# about 19,000 grains. For each incident state (STATES of them, landing at x 0.25-0.31 of the
# bed), the whole bed, the whole bed with V_in^x moved by 1e-9 m/s (granular contacts are
# chaotic: this row is the scatter a round-off perturbation alone gives), and each zone.
#
#   benchmarks/active-zone/run.sh [RICOCHET] [OUT.tsv] [STATES] [ZONES]
#   SETTINGS='NAME|--set K=V;...' benchmarks/active-zone/run.sh ...   (other numerical settings
#       against the same whole bed, e.g. the checkpoints: SETTINGS='checkpoints every 1000
#       steps|--set run.checkpoint_steps=1000'; ZONES='' to run those alone)
#
# Writes one row per impact: state, setting, status, V_out (3), the CPU seconds and steps of the
# impact, and the grains the zone moved (the bed's own count for the whole bed). Then, on
# stderr, per setting: the mean |V_out - whole bed| per component over the states, and the CPU
# time against the whole bed's. Defaults: 4 states, zones 0.45 0.3 0.2 0.15 m. Each impact is
# its own process (one core): about 30 s for the whole bed on a quiet core; the bed is built once
# (about 3 min) into results/active-zone/dem-cache and reused.
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
BIN=${1:-$ROOT/build/cli/ricochet}
OUT=${2:-/dev/stdout}
STATES=${3:-4}
ZONES=${4:-"0.45 0.3 0.2 0.15"}
CACHE=$ROOT/results/active-zone/dem-cache
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
mkdir -p "$CACHE"
source "$ROOT/scripts/long-test-bed.sh"
decks=(--decks "$ROOT/liggghts-inputs" --cache "$CACHE")
"$BIN" dem bed "${LONG_TEST_BED[@]}" "${decks[@]}" >&2
printf 'state\tsetting\tstatus\tvout_x_mps\tvout_y_mps\twout_radps\tcpu_s\tsteps\tactive_grains\n' \
  > "$WORK/out.tsv"
for ((i = 0; i < STATES; i++)); do
  frac=$(awk -v i="$i" 'BEGIN { print 0.25 + 0.02 * i }')
  vx=$(awk -v i="$i" 'BEGIN { print 2.7 + 0.1 * i }')
  vy=$(awk -v i="$i" 'BEGIN { print -2.1 - 0.1 * i }')
  settings=("whole bed|$vx|" "whole bed, V_in^x + 1e-9|$(awk -v v="$vx" 'BEGIN { printf "%.12f", v + 1e-9 }')|")
  for z in $ZONES; do settings+=("zone $z m|$vx|--set run.active_zone_m=$z"); done
  IFS=';' read -r -a others <<< "${SETTINGS:-}"
  for o in "${others[@]}"; do settings+=("${o%%|*}|$vx|${o#*|}"); done
  for s in "${settings[@]}"; do
    IFS='|' read -r name v extra <<< "$s"
    id="s$i-$(echo "$name" | tr -c 'a-z0-9.' '_')"
    # shellcheck disable=SC2086
    "$BIN" dem impact "${LONG_TEST_BED[@]}" "${LONG_TEST_BLOCK[@]}" "${decks[@]}" --set "run.x_impact_frac=$frac" \
      --vin "$v,$vy,-65" $extra --work "$WORK" --id "$id" --json > "$WORK/$id.json"
    active=$(awk '$1 == "active_grains" { print $2 }' "$WORK/$id/impact.summary.txt")
    jq -r --arg s "$i" --arg n "$name" --arg a "$active" \
      '[$s, $n, .status, .vout[0], .vout[1], .vout[2], .cpu_s, .steps,
        (if $a == "" then .grains else ($a | tonumber) end)] | @tsv' "$WORK/$id.json" \
      >> "$WORK/out.tsv"
    echo "  state $i, $name: $(tail -1 "$WORK/out.tsv" | cut -f3-9)" >&2
  done
done
cat "$WORK/out.tsv" > "$OUT"
# Per setting, against the whole bed of the same state.
awk -F'\t' 'NR > 1 {
    k = $1; if ($2 == "whole bed") { bx[k] = $4; by[k] = $5; bw[k] = $6; bc[k] = $7 }
    row[NR] = $0 }
  END {
    for (r in row) { split(row[r], f, "\t"); k = f[1]; s = f[2]; if (s == "whole bed") continue
      n[s]++; dx[s] += (f[4] > bx[k] ? f[4] - bx[k] : bx[k] - f[4])
      dy[s] += (f[5] > by[k] ? f[5] - by[k] : by[k] - f[5])
      dw[s] += (f[6] > bw[k] ? f[6] - bw[k] : bw[k] - f[6]); c[s] += f[7] / bc[k] }
    printf "%-28s %8s %10s %10s %12s %10s\n", "setting", "states", "|dVx| m/s", "|dVy| m/s",
      "|dw| rad/s", "CPU/whole" > "/dev/stderr"
    for (s in n) printf "%-28s %8d %10.4f %10.4f %12.3f %10.2f\n", s, n[s], dx[s] / n[s],
      dy[s] / n[s], dw[s] / n[s], c[s] / n[s] > "/dev/stderr" }' "$WORK/out.tsv"
