#!/usr/bin/env bash
# Issue 31, item 2: does the diagnosis's predicted power come true? For two hidden laws whose
# form a candidate has exactly (the independent simulator's spin_rolling = muR_spin_linear,
# c = 0.008 s/rad x strength; kd_drag = inertial_drag, cd = 40 kg/m x strength), the power of
# the candidate's score test is predicted from a NULL set (same seed, same incident states and
# noise draws, strength 0) by the diagnosis's own power formula (JSON
# minimum_detectable_by_candidate: Phi((c_crit + 0.8416) beta / change_80 - c_crit)), and
# measured as the rate at which that test rejects at the diagnosis's family-wise level on the
# sets WITH the law (its max-T adjusted score p < alpha / 2).
#
# Strengths are chosen on exploration seeds 8001-8005 (fractions 0.5, 0.7, 0.85, 1.0, 1.2 of the
# median change_80 of the first power formula) and written to OUT/strengths.tsv before any
# reporting seed is drawn (an existing strengths.tsv is kept). Reporting seeds, fixed in
# docs/detection-benchmark.md before each run and never used for a choice: 8101-8130 for the
# first formula (beta |s|^2 / sigma_S), 8501-8530 for the one with the spread term (power.hpp),
# the default. Resumable: rows already in OUT/cells.tsv are skipped.
#
#   [SEEDS="8101 ... 8130"] scripts/power-calibration.sh BUILD_DIR OUT_DIR
source "$(dirname "$0")/study-env.sh" "$@"
FAMILIES="spin_rolling kd_drag"
declare -A CAND=([spin_rolling]=muR_spin_linear [kd_drag]=inertial_drag)
declare -A REF=([spin_rolling]=0.008 [kd_drag]=40)
FRACTIONS="0.5 0.7 0.85 1.0 1.2"

# The candidate's change_80 and critical value in a diagnosis JSON.
c80() {  # JSON CANDIDATE
  python3 - "$1" "$2" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
r = [x for x in d["minimum_detectable_by_candidate"] if x["effect"] == sys.argv[2]][0]
print("%.10g\t%.10g" % (r["change_80"], r["critical_value"]))
PY
}
diag() {  # SEED STRENGTH FAMILY -> JSON path
  local f=$OUT/sets/$3-$2-$1
  [ -s "$f.json" ] && { echo "$f.json"; return; }
  "$T" --family "$3" --strength "$2" --n 40 --design lab --seed "$1" --no-refit \
    --out "$f.csv" > /dev/null
  "$R" diagnose "$f.csv" --json > "$f.tmp" 2>/dev/null
  mv "$f.tmp" "$f.json"
  echo "$f.json"
}

# 1. Strengths, from the exploration seeds' null sets only.
if [ ! -s "$OUT/strengths.tsv" ]; then
  printf 'family\tfraction\tstrength\n' > "$OUT/strengths.tmp"
  for fam in $FAMILIES; do
    vals=()
    for seed in 8001 8002 8003 8004 8005; do
      vals+=("$(c80 "$(diag "$seed" 0 none)" "${CAND[$fam]}" | cut -f1)")
    done
    med=$(printf '%s\n' "${vals[@]}" | sort -g | sed -n 3p)
    for fr in $FRACTIONS; do
      printf '%s\t%s\t%s\n' "$fam" "$fr" \
        "$(python3 -c "print('%.4g' % ($fr * abs($med) / ${REF[$fam]}))")" >> "$OUT/strengths.tmp"
    done
  done
  mv "$OUT/strengths.tmp" "$OUT/strengths.tsv"
fi
cat "$OUT/strengths.tsv"

# 2. The reporting seeds.
TSV=$OUT/cells.tsv
[ -f "$TSV" ] || printf 'family\tfraction\tstrength\tseed\tpredicted\trejected\tverdict\ttop_family\tpredicted_t\tt\n' > "$TSV"
total=$(( $(wc -l < "$OUT/strengths.tsv") - 1 ))
for seed in ${SEEDS:-$(seq 8501 8530)}; do
  null=$(diag "$seed" 0 none)
  tail -n +2 "$OUT/strengths.tsv" | while IFS=$'\t' read -r fam fr s; do
    grep -q "^$fam	$fr	$s	$seed	" "$TSV" && continue
    j=$(diag "$seed" "$s" "$fam")
    python3 - "$null" "$j" "${CAND[$fam]}" "$fam" "$fr" "$s" "$seed" "${REF[$fam]}" >> "$TSV" <<'PY'
import json, math, sys
null, j, cand, fam, fr, s, seed, ref = sys.argv[1:]
dn = json.load(open(null)); d = json.load(open(j))
r = [x for x in dn["minimum_detectable_by_candidate"] if x["effect"] == cand][0]
c, a, ceil = r["critical_value"], r["t_per_unit"], r["t_ceiling"] or math.inf
beta = float(s) * float(ref)
t_mean = beta * a / math.sqrt(1 + (beta * a / ceil) ** 2)  # power.hpp
pred = 0.5 * math.erfc(-(t_mean - c) / math.sqrt(2))
tested = [x for x in d["ranking"] + d["screened_out"] if x["effect"] == cand][0]
rej = tested["p_adjusted"] < 0.025
top = d["confidence_set_detail"]["members"][0]["family"] if d["confidence_set_detail"]["members"] else "-"
sup = d["ranking"][0]["supported"] if d["ranking"] else False
print("%s\t%s\t%s\t%s\t%.4f\t%s\t%s\t%s\t%.3f\t%.3f" % (fam, fr, s, seed, pred, "yes" if rej else "no",
      d["verdict"], top if sup else "-", t_mean, tested["t"]))
PY
  done
  echo "seed $seed done ($(( $(wc -l < "$TSV") - 1 )) cells-seeds)" >&2
done

# 3. The table and the calibration curve.
python3 - "$TSV" "$OUT" > "$OUT/summary.md" <<'PY'
import csv, math, sys
from study_stats import cells, wilson
rows = list(csv.DictReader(open(sys.argv[1]), delimiter="\t"))
fam_of = {"spin_rolling": "rolling_resistance", "kd_drag": "drag"}
groups = cells(rows, "family", "fraction", "strength")
print("| hidden law | strength | sets | predicted power (mean over seeds) | measured: the law's score test rejects | inside the 95 % interval | verdict missing physics, top supported of the truth's family | score statistic T: predicted mean (median over seeds) / measured mean |")
print("| :-- | --: | --: | --: | :-- | :-- | :-- | :-- |")
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
    print("| %s | %s | %d | %.3f | %d/%d = %.3f [%.3f, %.3f] | %s | %d/%d = %.3f [%.3f, %.3f] | %.2f / %.2f |" % (
        fam, s, n, pred, k, n, p, lo, hi, "yes" if ok else "no", k2, n, p2, lo2, hi2, pt, mt))
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
