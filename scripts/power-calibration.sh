#!/usr/bin/env bash
# Issue 31, item 2: does the diagnosis's predicted power come true? For two hidden laws whose
# form a candidate has exactly (the independent simulator's spin_rolling = muR_spin_linear,
# c = 0.008 s/rad x strength; kd_drag = inertial_drag, cd = 40 kg/m x strength), the power of
# the candidate's score test is predicted from a NULL set (same seed, same incident states and
# noise draws, strength 0) by the diagnosis's own prediction (JSON minimum_detectable_by_candidate:
# the curve t_curve of the score statistic's mean E[T] at finite strengths, solved on the engine,
# diagnosis/power.hpp; power = Phi(E[T] - c) at the truth's strength, E[T] interpolated in log
# strength), and measured as the rate at which that test rejects at the diagnosis's family-wise
# level (its max-T adjusted score p < alpha / 2) on the sets WITH the law.
#
# Strengths are chosen on exploration seeds 8001-8005 (null sets only): per family, the median
# over those seeds of the strength at which the predicted power is 0.2, 0.4, 0.6, 0.8 and 0.95,
# written to OUT/strengths.tsv before any reporting seed is drawn (an existing strengths.tsv is
# kept). Reporting seeds, fixed in docs/detection-benchmark.md before each run and never used for
# a choice: 8801-8830 (this version, the wide design), the default. Earlier versions (first and
# second power formulas, lab design, fractions of change_80): seeds 8101-8130 and 8501-8530.
# Resumable: rows already in OUT/cells.tsv are skipped.
#
#   [SEEDS="8801 ... 8830"] [DESIGN=wide] scripts/power-calibration.sh BUILD_DIR OUT_DIR
source "$(dirname "$0")/study-env.sh" "$@"
FAMILIES="spin_rolling kd_drag"
declare -A CAND=([spin_rolling]=muR_spin_linear [kd_drag]=inertial_drag)
declare -A REF=([spin_rolling]=0.008 [kd_drag]=40)
TARGETS="0.2 0.4 0.6 0.8 0.95"
DESIGN=${DESIGN:-wide}

# E[T] of CANDIDATE at change BETA from a diagnosis JSON's t_curve (linear in log |change|,
# through E[T] = 0 at no change), and the change at which the power reaches TARGET.
CURVE_PY='
import json, math, sys
def row(path, cand):
    d = json.load(open(path))
    return [x for x in d["minimum_detectable_by_candidate"] if x["effect"] == cand][0]
def t_at(r, beta):
    pts = sorted((abs(b), t) for b, t in r["t_curve"] if b is not None and t is not None)
    if not pts or beta > pts[-1][0] * 1.0001: return float("nan")
    prev = (0.0, 0.0)
    for b, t in pts:
        if beta <= b:
            if prev[0] == 0: return t * beta / b
            w = math.log(beta / prev[0]) / math.log(b / prev[0])
            return prev[1] + w * (t - prev[1])
        prev = (b, t)
    return pts[-1][1]
def phi(x): return 0.5 * math.erfc(-x / math.sqrt(2))
def beta_at(r, target):  # smallest change with predicted power >= target (bisection in log)
    top = max(abs(b) for b, _ in r["t_curve"])
    c = r["critical_value"]
    if phi(t_at(r, top) - c) < target: return float("nan")
    lo, hi = top * 1e-4, top
    for _ in range(60):
        mid = math.sqrt(lo * hi)
        lo, hi = (lo, mid) if phi(t_at(r, mid) - c) >= target else (mid, hi)
    return hi
'
diag() {  # SEED STRENGTH FAMILY -> JSON path
  local f=$OUT/sets/$3-$2-$1
  [ -s "$f.json" ] && { echo "$f.json"; return; }
  "$T" --family "$3" --strength "$2" --n 40 --design "$DESIGN" --seed "$1" --no-refit \
    --out "$f.csv" > /dev/null
  "$R" diagnose "$f.csv" --json > "$f.tmp" 2>/dev/null
  mv "$f.tmp" "$f.json"
  echo "$f.json"
}

# 1. Strengths, from the exploration seeds' null sets only.
if [ ! -s "$OUT/strengths.tsv" ]; then
  printf 'family\ttarget\tstrength\n' > "$OUT/strengths.tmp"
  for fam in $FAMILIES; do
    nulls=()
    for seed in 8001 8002 8003 8004 8005; do nulls+=("$(diag "$seed" 0 none)"); done
    python3 -c "$CURVE_PY
fam, cand, ref, targets = sys.argv[1], sys.argv[2], float(sys.argv[3]), sys.argv[4].split()
for target in targets:
    b = sorted(beta_at(row(p, cand), float(target)) for p in sys.argv[5:])
    b = [x for x in b if not math.isnan(x)]
    if b: print('%s\t%s\t%.4g' % (fam, target, b[len(b) // 2] / ref))
" "$fam" "${CAND[$fam]}" "${REF[$fam]}" "$TARGETS" "${nulls[@]}" >> "$OUT/strengths.tmp"
  done
  mv "$OUT/strengths.tmp" "$OUT/strengths.tsv"
fi
cat "$OUT/strengths.tsv"

# 2. The reporting seeds.
TSV=$OUT/cells.tsv
[ -f "$TSV" ] || printf 'family\ttarget\tstrength\tseed\tpredicted\trejected\tverdict\ttop_family\tpredicted_t\tt\n' > "$TSV"
for seed in ${SEEDS:-$(seq 8801 8830)}; do
  null=$(diag "$seed" 0 none)
  tail -n +2 "$OUT/strengths.tsv" | while IFS=$'\t' read -r fam fr s; do
    grep -q "^$fam	$fr	$s	$seed	" "$TSV" && continue
    j=$(diag "$seed" "$s" "$fam")
    python3 -c "$CURVE_PY
null, j, cand, fam, fr, s, seed, ref = sys.argv[1:]
d = json.load(open(j))
r = row(null, cand)
c = r['critical_value']
beta = float(s) * float(ref)
t_mean = t_at(r, beta)
pred = phi(t_mean - c)
tested = [x for x in d['ranking'] + d['screened_out'] if x['effect'] == cand][0]
rej = tested['p_adjusted'] < 0.025
top = d['confidence_set_detail']['members'][0]['family'] if d['confidence_set_detail']['members'] else '-'
sup = d['ranking'][0]['supported'] if d['ranking'] else False
print('%s\t%s\t%s\t%s\t%.4f\t%s\t%s\t%s\t%.3f\t%.3f' % (fam, fr, s, seed, pred, 'yes' if rej else 'no',
      d['verdict'], top if sup else '-', t_mean, tested['t']))
" "$null" "$j" "${CAND[$fam]}" "$fam" "$fr" "$s" "$seed" "${REF[$fam]}" >> "$TSV"
  done
  echo "seed $seed done ($(( $(wc -l < "$TSV") - 1 )) cells-seeds)" >&2
done

# 3. The table and the calibration curve.
python3 - "$TSV" "$OUT" > "$OUT/summary.md" <<'PY'
import csv, math, sys
from study_stats import cells, wilson
rows = list(csv.DictReader(open(sys.argv[1]), delimiter="\t"))
fam_of = {"spin_rolling": "rolling_resistance", "kd_drag": "drag"}
groups = cells(rows, "family", "target", "strength")
print("| hidden law | strength | target power (exploration) | sets | predicted power (mean over seeds) | measured: the law's score test rejects | inside the 95 % interval | verdict missing physics, top supported of the truth's family | score statistic T: predicted mean (median over seeds) / measured mean |")
print("| :-- | --: | --: | --: | --: | :-- | :-- | :-- | :-- |")
dat = open(sys.argv[2] + "/calibration.dat", "w")
inside = 0
for (fam, fr, s), rs in groups:
    n = len(rs); pred = sum(float(r["predicted"]) for r in rs) / n
    k = sum(r["rejected"] == "yes" for r in rs); p, lo, hi = wilson(k, n)
    k2 = sum(r["verdict"] == "missing physics" and r["top_family"] == fam_of[fam] for r in rs)
    p2, lo2, hi2 = wilson(k2, n)
    ok = lo <= pred <= hi; inside += ok
    pt = sorted(float(r["predicted_t"]) for r in rs)[n // 2]
    mt = sum(float(r["t"]) for r in rs) / n
    print("| %s | %s | %s | %d | %.3f | %d/%d = %.3f [%.3f, %.3f] | %s | %d/%d = %.3f [%.3f, %.3f] | %.2f / %.2f |" % (
        fam, s, fr, n, pred, k, n, p, lo, hi, "yes" if ok else "no", k2, n, p2, lo2, hi2, pt, mt))
    dat.write("%s %.4f %.4f %.4f %.4f\n" % (fam, pred, p, lo, hi))
print("\nPredicted power inside the measured rate's 95 %% Wilson interval in %d of %d cells." % (inside, len(groups)))
PY
cat "$OUT/summary.md"
if command -v gnuplot > /dev/null; then
  gnuplot <<GP
set terminal svg size 560,460 font "sans,12"
set output "$OUT/power-calibration.svg"
set xlabel "predicted power (diagnosis, from the null set)"
set ylabel "measured rejection rate (95 % Wilson interval)"
set xrange [0:1]; set yrange [0:1]; set key top left; set grid
plot x title "perfect calibration" lw 1 lc rgb "#888888", \
  "< grep spin_rolling $OUT/calibration.dat" using 2:3:4:5 with yerrorbars pt 7 title "spin_rolling (rolling resistance)", \
  "< grep kd_drag $OUT/calibration.dat" using 2:3:4:5 with yerrorbars pt 5 title "kd_drag (drag)"
GP
fi
