#!/usr/bin/env bash
# Issue 31, item 4: the closed loop on the independent simulator (tests/detection/truth_sim.hpp),
# which shares no code with the engine. Per family and seed:
#   1. 40 releases at the lab's incident states with the hidden effect (seed K);
#   2. `ricochet diagnose`: its confidence set of laws (before);
#   3. `ricochet design` on that set: BUDGET throws in the box below;
#   4. the same truth throws the plan (another seed: new ground and noise draws);
#   5. `ricochet diagnose` of the old and new releases together: the set after.
# One line per loop in OUT/loops.tsv (resumable: loops already there are skipped), then a table
# (OUT/summary.md): set size and families before and after, the truth's family in the set, none
# in the set, the set holding only the truth's family. Not part of CI (minutes per family).
#
#   scripts/closed-loop-study.sh BUILD_DIR OUT_DIR [SEEDS] [BUDGET]
#
# FIRST_SEED (environment, default 1): the loops use seeds FIRST_SEED .. FIRST_SEED + SEEDS - 1.
# Exploratory run: seeds 1-5; reporting run: FIRST_SEED=9101, 10 seeds (fixed in
# docs/detection-benchmark.md before it).
#
# FAMILIES (environment): "family:strength ..." (strength x the family's reference).
#
# The oracle (truth_sim.hpp, "The oracle's ceiling": it knows the hidden law's form and size) gives
# per loop the power with which the hidden effect could be seen at all, on the 40 lab states
# (oracle_before) and on the lab states plus the plan (oracle_after), at the family-wise level of
# a family of 45 hypotheses: the issue's target counts only loops with oracle_after >= 0.9.
source "$(dirname "$0")/study-env.sh" "$1" "$2"
SEEDS=${3:-5}
BUDGET=${4:-40}
FAMILIES=${FAMILIES:-"crsp_restitution:3.65068 spin_rolling:2.01086 depth_friction_exp:33.2814 kd_drag:83.7314"}
BOX="--range vin_x=1.5:6 --range vin_y=-5:-1 --range win=-90:0"
TSV=$OUT/loops.tsv
[ -f "$TSV" ] || printf 'family\tstrength\tseed\tbefore_n\tbefore_families\tbefore_none\tafter_n\tafter_families\tafter_none\tpower_plan\tpower_uniform\tplan_n\toracle_before\toracle_after\n' > "$TSV"

families_of() {  # diagnose JSON on stdin -> "n<TAB>fam1,fam2<TAB>none?"
  python3 -c '
import json, sys
d = json.load(sys.stdin)
m = d["confidence_set"]
fams = []
for x in m:
    if x["family"] not in fams: fams.append(x["family"])
print("%d\t%s\t%s" % (len(m), ",".join(fams), "yes" if "none" in fams else "no"))'
}

for spec in $FAMILIES; do
  fam=${spec%%:*}; s=${spec#*:}
  for seed in $(seq "${FIRST_SEED:-1}" $(( ${FIRST_SEED:-1} + SEEDS - 1 ))); do
    if grep -q "^$fam	$s	$seed	" "$TSV"; then continue; fi
    base=$OUT/sets/$fam-$seed
    "$T" --family "$fam" --strength "$s" --n 40 --design lab --seed "$seed" --out "$base.old.csv" > /dev/null
    before=$("$R" diagnose "$base.old.csv" --json 2>/dev/null | families_of)
    # shellcheck disable=SC2086  # BOX: zero or more options, split on purpose
    "$R" design "$base.old.csv" --shape cylinder --budget "$BUDGET" $BOX --seed "$seed" \
      --out "$base.plan.csv" --json > "$base.design.json" 2>/dev/null
    "$T" --family "$fam" --strength "$s" --states "$base.plan.csv" --seed $((seed + 100000)) \
      --id-prefix D --out "$base.new.csv" > /dev/null
    # Old and new releases in one set: the second file's comment and header lines dropped.
    { cat "$base.old.csv"; grep -v '^#' "$base.new.csv" | tail -n +2; } > "$base.both.csv"
    after=$("$R" diagnose "$base.both.csv" --json 2>/dev/null | families_of)
    powers=$(python3 -c '
import json, sys
d = json.load(open(sys.argv[1]))
nz = lambda x: float("nan") if x is None else x
print("%.3f\t%.3f\t%d" % (nz(d["min_pair"]["plan"]["power"]), nz(d["min_pair"]["uniform"]["power"]), d["budget"]))' "$base.design.json" 2>/dev/null || printf 'nan\tnan\tnan')
    oracle() {  # STATES_FILE -> the oracle's family-wise power on those incident states
      "$T" --family "$fam" --strength "$s" --states "$1" --seed "$seed" --oracle 2>/dev/null |
        python3 -c 'import json, sys; print("%.3f" % json.loads(sys.stdin.readline())["power_family"])' ||
        echo nan
    }
    oracles="$(oracle "$base.old.csv")	$(oracle "$base.both.csv")"
    printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$fam" "$s" "$seed" "$before" "$after" "$powers" "$oracles" >> "$TSV"
    echo "$(date +%T) $fam s=$s seed $seed: before [$before] after [$after] power $powers"
  done
done
# The table: per family, how often the truth's family is in the set, none is out, and the set
# holds the truth's family alone, before and after the plan (Wilson 95 % intervals).
python3 - "$TSV" > "$OUT/summary.md" <<'PY'
import csv, math, sys
truth = {"crsp_restitution": "restitution", "kd_drag": "drag", "spin_rolling": "rolling_resistance",
         "depth_friction_exp": "sliding_friction", "rankine_plough": "ploughing",
         "yield_restitution": "restitution", "depth_speed_drag": "drag",
         "slip_spin_friction": "sliding_friction"}
from study_stats import wilson_text
def wilson(k, n):
    return wilson_text(k, n, 2) if n else "-"
rows = list(csv.DictReader(open(sys.argv[1]), delimiter="\t"))
print("| family | strength | loops | mean set size before -> after | truth's family in the set, before / after | none in the set, before / after | the truth's family alone, after | predicted weakest-pair power, plan / uniform (median) | plan size (median) | oracle power before / after (median) | detectable loops (oracle after >= 0.9): truth's family alone / kept |")
print("| :-- | --: | --: | :-- | :-- | :-- | :-- | :-- | --: | :-- | :-- |")
def num(r, k):
    v = r.get(k)
    return float(v) if v not in (None, "", "nan") else float("nan")
for fam in dict.fromkeys(r["family"] for r in rows):
    rs = [r for r in rows if r["family"] == fam]; n = len(rs); t = truth.get(fam, "none")
    inb = sum(t in r["before_families"].split(",") for r in rs)
    ina = sum(t in r["after_families"].split(",") for r in rs)
    nb = sum(r["before_none"] == "yes" for r in rs); na = sum(r["after_none"] == "yes" for r in rs)
    alone = sum(r["after_families"] == t for r in rs)
    med = lambda k: sorted(num(r, k) for r in rs)[n // 2]
    size = med("plan_n")
    # Older loop files have no oracle columns: their loops count as not measured ("-").
    det = [r for r in rs if num(r, "oracle_after") >= 0.9]
    det_alone = sum(r["after_families"] == t for r in det)
    det_kept = sum(t in r["after_families"].split(",") for r in det)
    measured = any(not math.isnan(num(r, "oracle_after")) for r in rs)
    print("| %s | %s | %d | %.1f -> %.1f | %s / %s | %s / %s | %s | %.2f / %.2f | %.0f | %s | %s |" % (
        fam, rs[0]["strength"], n, sum(int(r["before_n"]) for r in rs) / n,
        sum(int(r["after_n"]) for r in rs) / n, wilson(inb, n), wilson(ina, n), wilson(nb, n),
        wilson(na, n), wilson(alone, n), med("power_plan"), med("power_uniform"), size,
        "%.2f / %.2f" % (med("oracle_before"), med("oracle_after")) if measured else "-",
        "%s / %s" % (wilson(det_alone, len(det)), wilson(det_kept, len(det))) if measured else "-"))
# The issue's coverage target, pooled over families: on detectable loops (the oracle's
# family-wise power >= 0.9 on the releases diagnosed), the truth's family in the set.
if any(not math.isnan(num(r, "oracle_after")) for r in rows):
    for when, col, fams in (("first diagnosis (40 lab releases)", "oracle_before", "before_families"),
                            ("after the plan", "oracle_after", "after_families")):
        det = [r for r in rows if num(r, col) >= 0.9]
        kept = sum(truth.get(r["family"], "none") in r[fams].split(",") for r in det)
        print("\nTruth's family in the set on detectable loops, %s: %s" % (when, wilson(kept, len(det))))
PY
cat "$OUT/summary.md"
echo "loops: $TSV"
