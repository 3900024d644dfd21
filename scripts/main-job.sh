#!/usr/bin/env bash
# The main job on the embedded lab data (paper Appendix A). Results go to results/.
# usage: scripts/main-job.sh BUILD_DIR [--quick]
set -euo pipefail
BUILD=$1; shift
QUICK=0
[ "${1:-}" = "--quick" ] && QUICK=1
ROOT=$(cd "$(dirname "$0")/.." && pwd)
OUT=$ROOT/results
mkdir -p "$OUT/figures"
R="$BUILD/ricochet"
CYL=$ROOT/data/lab/cylinders.csv
TRI=$ROOT/data/lab/triangles.csv

echo "== Statistics of the lab releases (paper Table 2)"
"$R" stats "$CYL"
"$R" stats "$TRI"
echo "== Transfer-matrix model (paper Eq. 2, Table 3)"
"$R" transfer fit "$CYL" --figures "$OUT/figures" --out "$OUT/transfer-cylinders.h5"
"$R" transfer fit "$TRI" --split vin_x=3.5 --figures "$OUT/figures" --out "$OUT/transfer-triangles.h5"
echo "== Results in $OUT"
