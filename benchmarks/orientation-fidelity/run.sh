#!/usr/bin/env bash
# Issue 35, item 1: is the lab triangles' orientation average converged? The leak-free held-out
# error of the paper's law (`ricochet compare --no-release-fits`, seed 1, 5 folds x 2 repeats) at
# the defaults (search rule 6 orientations, polish rule 24, 32 cold starts, 3 ends polished, each
# release's rules shifted by its id: fit/orientation_rule.hpp), and with each setting refined or
# coarsened alone. Converged means every refinement moves it by less than 1 % (the issue's rule).
#
#   benchmarks/orientation-fidelity/run.sh [RICOCHET] [OUT.tsv] [ROWS]
#
# Writes one row per setting: the options, the held-out and in-sample errors, the quadrature
# error of the held-out error (half rules), the change against the first row run [%], the wall
# time [s] and the collisions simulated (the cost on any machine). ROWS: an extended regular
# expression on the settings' names (default: every row; keep "defaults" in it, the rows'
# reference). About 1 min a row on 2 cores (the 64-start and 48-orientation rows 2-3 min).
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
BIN=${1:-$ROOT/build/cli/ricochet}
OUT=${2:-/dev/stdout}
ROWS=${3:-.}
DATA=$ROOT/data/lab/triangles.csv
rows=(
  "defaults|"
  "polish rule 48|--polish-orientations 48"
  "polish rule 12|--polish-orientations 12"
  "starts 64|--orientation-starts 64"
  "starts 16|--orientation-starts 16"
  "search rule 3|--orientations 3"
  "search rule 12|--orientations 12"
  "search rule 12, starts 64|--orientations 12 --orientation-starts 64"
  "no polish (6-point grid)|--polish-orientations 0 --orientation-starts 1"
  "response surface on 24|--orientation-search surface"
  "search xtol 3e-3|--search-xtol 3e-3"
  "search xtol 1e-2|--search-xtol 1e-2"
  "search xtol 3e-2|--search-xtol 3e-2"
)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
printf 'setting\toptions\theldout_error\tinsample_error\tquadrature_error\tchange_pct\tseconds\tcollisions\n' > "$tmp/out.tsv"
base=""
for row in "${rows[@]}"; do
  name=${row%%|*}
  opts=${row#*|}
  [[ $name =~ $ROWS ]] || continue
  echo "orientation-fidelity: $name ($opts)" >&2
  start=$(date +%s.%N)
  # shellcheck disable=SC2086
  "$BIN" compare "$DATA" --shape triangle --no-release-fits --seed 1 $opts --json > "$tmp/r.json"
  end=$(date +%s.%N)
  read -r ho ins q n < <(jq -r '"\(.heldout_error) \(.insample_error) \(.heldout_quadrature_error) \(.collisions)"' "$tmp/r.json")
  [ -n "$base" ] || base=$ho
  change=$(awk -v a="$ho" -v b="$base" 'BEGIN { printf "%+.2f", 100 * (a - b) / b }')
  secs=$(awk -v a="$start" -v b="$end" 'BEGIN { printf "%.1f", b - a }')
  printf '%s\t%s\t%.4f\t%.4f\t%.4f\t%s\t%s\t%s\n' "$name" "${opts:-(defaults)}" "$ho" "$ins" "$q" \
    "$change" "$secs" "$n" >> "$tmp/out.tsv"
done
cat "$tmp/out.tsv" > "$OUT"
