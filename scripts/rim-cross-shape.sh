#!/usr/bin/env bash
# The rim's test on a set it was not shaped on (issue 33; docs/diagnosis.md, "Added: the rim",
# the check fixed on 2026-12-06): the reduced laws fitted to the stiff bed's cylinders predict the
# blind triangles on the same grains, nothing refitted.
#   1. `ricochet ladder data/resolved/sand-verification-1.5e9.h5 --add crater_rim`: rung 0, the
#      paper's law, and rung 1, with crater_rim, each at its fit on the 27 cylinder rebounds;
#   2. each written as a model file with nothing calibrated (OUT/base-law.toml, OUT/rim-law.toml);
#   3. `ricochet compare` of the blind triangles (data/resolved/sand-blind-triangles-1.5e9.h5, the
#      zone check's duplicates left out by SAND_BLIND_WHERE) under each law, on V_out alone
#      (--no-features: the contact features would refit kn and w_rim), the orientation of each
#      impact known from its design;
#   4. the paired difference of the two laws' per-release errors (Eq. 7), rim minus base, its mean
#      and a 95 % Student t interval over the releases.
# Reading: the rim holds on the triangles when the interval lies below 0, fails when it lies above
# 0, and the set cannot tell otherwise. A preview on the first 5 blind rebounds was printed on the
# day the check was fixed (base 2.55 +- 0.95, rim 2.83 +- 1.28): it is not the result.
# The second reading (added on 2026-12-06 with 7 of the 31 in, before any law predicted a
# triangle's contact; the first reading stays the primary one): the same two held laws, kn and
# w_rim held as fitted on the cylinders (`hold`, so that nothing is refitted), predict the
# triangles' penetration and contact duration too (the error with contact terms), read by the
# same paired interval. This is where the rim changed the cylinders most (the duration term
# 0.338 -> 0.011).
# The drag's test (fixed on 2026-12-06, evening, before any law with it predicted a triangle;
# docs/diagnosis.md, "The next rung: inertial drag"): the cylinders' ladder gains a third rung,
# + inertial_drag on the rim law (found by hand on the same cylinders, where the diagnosis's
# screen passed it over), written and held the same way (OUT/drag-law.toml, kn and w_rim held,
# cd as fitted). It is read by the same rule, drag minus rim, paired over the same rebounds:
# the drag holds on the triangles when the interval lies below 0, fails when it lies above 0,
# and the set cannot tell otherwise; both readings, V_out alone the primary one. Rungs 0 and 1
# are fitted as before (a ladder's rungs are sequential), so the rim's result is unchanged.
#
#   scripts/rim-cross-shape.sh [BUILD_DIR] [OUT_DIR]     (default build, results/rim-cross-shape)
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
export PYTHONPATH="$ROOT/scripts${PYTHONPATH:+:$PYTHONPATH}"  # study_stats.py
BUILD=${1:-$ROOT/build}
OUT=${2:-$ROOT/results/rim-cross-shape}
R=$BUILD/cli/ricochet
# shellcheck source=sand-calibration-args.sh
source "$ROOT/scripts/sand-calibration-args.sh"
mkdir -p "$OUT"
"$R" ladder "$ROOT/data/resolved/sand-verification-1.5e9.h5" --add crater_rim --add inertial_drag --json \
  > "$OUT/ladder-cylinders.json"
# law RUNG EFFECTS HOLD FILE: the rung's fitted parameters as a model file with nothing
# calibrated and the parameters HOLD (those the contact features would calibrate) held.
law() {
  {
    echo "# rung $1 of ricochet ladder data/resolved/sand-verification-1.5e9.h5 --add crater_rim" \
      "--add inertial_drag, held"
    echo "effects = $2"
    echo "calibrate = []"
    echo "hold = $3"
    echo
    echo "[parameters]"
    jq -r ".rungs[$1].parameters | to_entries[] | \"\(.key) = \(.value)\"" "$OUT/ladder-cylinders.json"
  } > "$4"
}
law 0 '["normal", "tangential", "rolling"]' '["kn"]' "$OUT/base-law.toml"
law 1 '["normal", "tangential", "rolling", "crater_rim"]' '["kn", "w_rim"]' "$OUT/rim-law.toml"
law 2 '["normal", "tangential", "rolling", "crater_rim", "inertial_drag"]' '["kn", "w_rim"]' \
  "$OUT/drag-law.toml"
for m in base rim drag; do
  "$R" compare "$ROOT/data/resolved/sand-blind-triangles-1.5e9.h5" --shape triangle \
    --where "$SAND_BLIND_WHERE" --model "$OUT/$m-law.toml" --no-features --json > "$OUT/compare-$m.json"
  "$R" compare "$ROOT/data/resolved/sand-blind-triangles-1.5e9.h5" --shape triangle \
    --where "$SAND_BLIND_WHERE" --model "$OUT/$m-law.toml" --json > "$OUT/compare-$m-features.json"
done
# pair LAW OTHER: the paired reading of LAW against OTHER in both readings.
pair() {
  for reading in "" -features; do
    python3 - "$OUT/compare-$2$reading.json" "$OUT/compare-$1$reading.json" "$reading" "$1" "$2" <<'PY'
import json, statistics, sys
from study_stats import paired_t
other_doc, law_doc = (json.load(open(p)) for p in sys.argv[1:3])
law, other = sys.argv[4], sys.argv[5]
what = "V_out + penetration + duration" if sys.argv[3] else "V_out"
print(f"-- {what}")
for name, doc in ((other, other_doc), (law, law_doc)):
    assert doc["calibrated"] == [], f"{name}: compare refitted {doc['calibrated']}"
    print(f"{name}: {what} error {doc['heldout_error']:.3f} +- {doc['heldout_se']:.3f} over "
          f"{len(doc['releases'])} blind rebounds; per term "
          + ", ".join(f"{k} {v:.3g}" for k, v in doc["heldout_per_component"].items()))
b = {r["id"]: r["heldout_error"] for r in other_doc["releases"]}
d = [r["heldout_error"] - b[r["id"]] for r in law_doc["releases"]]
n = len(d)
mean = statistics.fmean(d)
if n < 2:
    print(f"{law} - {other} over {n} release: {mean:+.3f}; too few for an interval")
    sys.exit(0)
mean, lo, hi = paired_t(d)  # Student's t, 95 %
verdict = (f"the {law} holds" if hi < 0 else f"the {law} fails" if lo > 0
           else "the set cannot tell")
print(f"{law} - {other}, paired over {n} releases: {mean:+.3f}, 95 % interval [{lo:+.3f}, "
      f"{hi:+.3f}]: {verdict} on the blind triangles")
PY
  done
}
pair rim base
pair drag rim
