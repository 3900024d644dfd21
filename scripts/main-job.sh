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
R="$BUILD/cli/ricochet"
CYL=$ROOT/data/lab/cylinders.csv
TRI=$ROOT/data/lab/triangles.csv

echo "== Statistics of the lab releases (paper Table 2)"
"$R" stats "$CYL"
"$R" stats "$TRI"
echo "== Transfer-matrix model (paper Eq. 2, Table 3)"
"$R" transfer fit "$CYL" --figures "$OUT/figures" --out "$OUT/transfer-cylinders.h5"
"$R" transfer fit "$TRI" --split vin_x=3.5 --figures "$OUT/figures" --out "$OUT/transfer-triangles.h5"
echo "== The paper's contact law, one collision at the mean cylinder state (section 4.1)"
"$R" simulate --vin 2.9,-2.3,-65
echo "== Per-release calibration with identifiability (Eq. 7, Table 4)"
"$R" calibrate "$CYL" --shape cylinder --figures "$OUT/figures" --out "$OUT/calibrate-cylinders.h5"
if [ $QUICK -eq 0 ]; then
  "$R" calibrate "$TRI" --shape triangle --figures "$OUT/figures" --out "$OUT/calibrate-triangles.h5"
fi
echo "== Monte Carlo against the measured CDFs (section 4.3, Fig. 16)"
N_MC=50000; N_SOBOL=4096
[ $QUICK -eq 1 ] && N_MC=5000 && N_SOBOL=512
"$R" montecarlo --shape cylinder --n $N_MC --compare "$CYL" --seed 1 --figures "$OUT/figures" \
  --out "$OUT/montecarlo-cylinders.h5"
echo "== Sobol indices (section 4.4, Figs. 17-18)"
"$R" sobol --shape cylinder --n $N_SOBOL --seed 1 --figures "$OUT/figures" --out "$OUT/sobol-cylinders.h5"
echo "== Compare, diagnose, model ladder and the HTML validation report (issue 6, docs/diagnosis.md)"
# Every cached LIGGGHTS campaign with an impact set (/impacts) joins the lab data: the diagnosis
# works on any impact set, so the resolved model is judged as a truth like the lab.
REPORT_DATA=("$CYL"); REPORT_LABELS=(--label "lab cylinders")
if [ $QUICK -eq 0 ]; then REPORT_DATA+=("$TRI"); REPORT_LABELS+=(--label "lab triangles"); fi
for c in "$OUT"/dem/*.h5 "$OUT"/*campaign*.h5; do
  [ -f "$c" ] && "$R" stats "$c" > /dev/null 2>&1 || continue
  REPORT_DATA+=("$c"); REPORT_LABELS+=(--label "LIGGGHTS campaign $(basename "$c" .h5)")
done
"$R" diagnose "$CYL" --shape cylinder --figures "$OUT/figures/diagnosis-cylinders" \
  --out "$OUT/diagnose-cylinders.h5"
"$R" report "${REPORT_DATA[@]}" "${REPORT_LABELS[@]}" --rounds 2 --out "$OUT/report.html"
echo "== Results in $OUT"
