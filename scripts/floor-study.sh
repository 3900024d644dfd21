#!/usr/bin/env bash
# Issue 31, 5b: with the measurement floor fitted from the set (noise-plus-scatter model,
# diagnosis/scatter.hpp), does any set whose hidden effect the oracle sees at z >= 5 still get
# the verdict `adequate` (which since the power gate also needs every family visible at z_80 <= 5,
# docs/diagnosis.md "Verdict")? Cells: every cell of the shipped detection studies
# (data/detection/study-{lab,wide,new-forms}.summary.json) whose mean oracle z was >= 5, plus
# the null cells of both designs; 10 fresh sets each, seeds FLOOR_SEEDS (default 8601-8610
# since the power gate; 8301-8310 before it: both fixed in docs/detection-benchmark.md before their run), diagnosed with the defaults. The oracle's z is
# recomputed per set (`independent_truth --oracle`). Resumable (rows in OUT/floor.tsv skipped).
#
#   scripts/floor-study.sh BUILD_DIR OUT_DIR
source "$(dirname "$0")/study-env.sh" "$@"
TSV=$OUT/floor.tsv
[ -f "$TSV" ] || printf 'design\tfamily\tstrength\tseed\toracle_z\tverdict\tfloor_source\tnoise_scale\tratio_to_floor\n' > "$TSV"
CELLS="lab:none:0 wide:none:0
lab:depth_friction_exp:16.6407 lab:depth_friction_exp:33.2814 lab:rankine_plough:82551.6
lab:spin_rolling:2.01086 lab:two:1.82534 lab:slip_spin_friction:75240.4
lab:yield_restitution:6.19814 wide:crsp_restitution:1.0 wide:crsp_restitution:1.09569
wide:depth_friction_exp:1.0 wide:rankine_plough:20568.2 wide:rankine_plough:41136.4
wide:spin_rolling:1.95847 wide:two:0.979235"
for cell in $CELLS; do
  IFS=: read -r design fam s <<< "$cell"
  for seed in ${FLOOR_SEEDS:-$(seq 8601 8610)}; do
    grep -q "^$design	$fam	$s	$seed	" "$TSV" && continue
    f=$OUT/sets/$design-$fam-$s-$seed
    z=$("$T" --family "$fam" --strength "$s" --n 40 --design "$design" --seed "$seed" \
          --out "$f.csv" --oracle | python3 -c 'import json,sys; print("%.3f" % json.load(sys.stdin)["z"])')
    "$R" diagnose "$f.csv" --json > "$f.json" 2>/dev/null
    python3 - "$f.json" "$design" "$fam" "$s" "$seed" "$z" >> "$TSV" <<'PY'
import json, sys
d = json.load(open(sys.argv[1])); design, fam, s, seed, z = sys.argv[2:]
sc = (d.get("scatter") or {}).get("noise_scale_to_table1") or {}
g = ",".join("%.2f" % v for v in sc.values()) or "-"
print("%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%.3f" % (design, fam, s, seed, z, d["verdict"],
      d["noise_floor_source"], g, d["base_error"] / d["noise_floor"]))
PY
  done
  echo "$cell done" >&2
done
python3 - "$TSV" > "$OUT/summary.md" <<'PY'
import csv, math, sys
from study_stats import cells, wilson_text as wilson
rows = list(csv.DictReader(open(sys.argv[1]), delimiter="\t"))
print("| design | hidden effect | strength | sets | mean oracle z | adequate | inconclusive | scatter | missing physics | mean held-out error / floor |")
print("| :-- | :-- | --: | --: | --: | :-- | :-- | :-- | :-- | --: |")
for c, rs in cells(rows, "design", "family", "strength"):
    n = len(rs)
    v = lambda x: "%d" % sum(r["verdict"] == x for r in rs)
    print("| %s | %s | %s | %d | %.1f | %s | %s | %s | %s | %.2f |" % (c + (n, sum(float(r["oracle_z"]) for r in rs) / n,
          v("adequate"), v("inconclusive"), v("scatter"), v("missing physics"), sum(float(r["ratio_to_floor"]) for r in rs) / n)))
z5 = [r for r in rows if float(r["oracle_z"]) >= 5]
print("\nSets whose oracle z >= 5 given the verdict `adequate`: %s." % wilson(sum(r["verdict"] == "adequate" for r in z5), len(z5)))
# What the power gate does not change (docs/diagnosis.md, "Verdict"): how often such a set is
# within its floor with nothing found, whichever of the two verdicts says so.
print("Sets whose oracle z >= 5 with no misfit found (`adequate` or `inconclusive`): %s." % wilson(sum(r["verdict"] in ("adequate", "inconclusive") for r in z5), len(z5)))
nulls = [r for r in rows if r["family"] == "none"]
print("Null sets given `adequate`: %s; `inconclusive`: %s." % (wilson(sum(r["verdict"] == "adequate" for r in nulls), len(nulls)), wilson(sum(r["verdict"] == "inconclusive" for r in nulls), len(nulls))))
PY
cat "$OUT/summary.md"
