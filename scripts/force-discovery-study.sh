#!/usr/bin/env bash
# Issue 33, item 4: the force-residual discovery's rates on the independent simulator, on the
# seeds fixed in docs/detection-benchmark.md ("The force-residual discovery on fresh seeds").
#
#   scripts/force-discovery-study.sh BUILD_DIR OUT_PREFIX
#
# Writes OUT_PREFIX.tsv (one line per set) and OUT_PREFIX.summary.md (the rates with Wilson 95 %
# intervals and the command that made them), then the power curve against the oracle (its plan
# and seeds in the same section of the docs) into OUT_PREFIX-power.tsv, its table appended to the
# summary. About a minute on one core.
set -euo pipefail
BUILD=$(cd "$1" && pwd)
OUT=$2
BIN=$BUILD/tests/detection/force_discovery_study
[ -x "$BIN" ] || { echo "no $BIN: build the target force_discovery_study" >&2; exit 2; }
mkdir -p "$(dirname "$OUT")"
{
  echo "# Force-residual discovery on fresh seeds (issue 33, item 4)"
  echo
  echo "Made by \`scripts/force-discovery-study.sh\` at $(cd "$(dirname "$0")/.." && git rev-parse --short HEAD) on $(date -u +%F)."
  echo
  echo '```'
  "$BIN" --first-null 3001 --nulls 100 --first-seed 4001 --seeds 10 --out "$OUT.tsv"
  echo '```'
  echo
  "$BIN" --power-z 2,4,8,16,32 --probe-seed 4001 --first-seed 5001 --seeds 20 \
    --out "$OUT-power.tsv"
} > "$OUT.summary.md"
cat "$OUT.summary.md"
