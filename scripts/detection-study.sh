#!/usr/bin/env bash
# The detection benchmark of docs/detection-benchmark.md (issue 10, item 5; not part of CI).
# Truth sets come from the independent simulator (tests/detection/truth_sim.hpp: another code,
# integrator, time step and stiffness; hidden physics in non-catalog forms; release-to-release
# scatter of the ground; lab-like noise; velocities only) and are diagnosed by
# `ricochet diagnose SET --shape cylinder --json` with its defaults: the diagnosis reads only the
# set's file, never the truth.
#
#   scripts/detection-study.sh BUILD_DIR [OUT_DIR] [SEEDS] [NULLS] [DESIGN]
#
# BUILD_DIR  the build (needs cli/ricochet, tests/detection/independent_truth, detection_summary)
# OUT_DIR    default results/detection-independent
# SEEDS      sets per cell, default 10 (>= 10 for the documented study)
# NULLS      null sets per release count, default 40
# DESIGN     lab (default: the lab's incident states, smoothed bootstrap) or wide
#
# Cells: each family in {crsp_restitution, kd_drag, spin_rolling, depth_friction_exp,
# rankine_plough} at strengths {1, 1/2, 1/4} x its reference (literature-based where a value
# exists) and at its lab-scale strength (the mean V_out shift reaches the paper's Table 1 scale,
# `independent_truth --calibrate-shift` on the design with 40 releases and seed 1), each at
# n = 28 (the lab's count) and n = 40; NULLS null sets at n = 28 and at n = 40; "two"
# (crsp_restitution + spin_rolling, each at least at the lab scale: the larger of their two
# lab-scale strengths) at n = 40, diagnosed and also run through `ricochet ladder --auto 2`.
# Seeds are explicit and distinct per release count, so an n = 28 set is not the prefix of an
# n = 40 set: n = 40 uses seeds 1..SEEDS, n = 28 101.., nulls 1001.. (n = 40) and 1101..
# (n = 28), two 2001...
#
# Resumable: a set whose NAME.diagnose.json exists is skipped (the diagnosis is written to a
# .tmp file and renamed when complete), and each family's lab-scale strength is cached in
# OUT_DIR/FAMILY.lab-strength. One progress line per set. The table: OUT_DIR/summary.md and
# OUT_DIR/summary.json (tests/detection/detection_summary.cpp, Wilson 95 % intervals).
# DETECTION_ONLY=REGEX (environment) runs only the sets whose name matches (a plumbing check:
# DETECTION_ONLY='^(spin_rolling-s1-n40|none-n40|two)-.*-(1|1001|2001)$').
# FAMILIES (environment): the hidden families studied (default the first five).
# STRENGTHS (environment, default "1 0.5 0.25 lab"): the strengths of each family, numbers
# (times the reference) or "lab" / "2lab" (once / twice the lab-scale strength).
# NS (environment, default "28 40"): the release counts. JOBS (environment, default 1): sets
# made and diagnosed at once, each on one thread (OMP_NUM_THREADS=1) when JOBS > 1.
set -euo pipefail
if [ $# -lt 1 ] || [ ! -d "$1" ]; then
  echo "usage: $0 BUILD_DIR [OUT_DIR] [SEEDS] [NULLS] [DESIGN]" >&2
  exit 2
fi
BUILD=$(cd "$1" && pwd)
ROOT=$(cd "$(dirname "$0")/.." && pwd)
OUT=${2:-$ROOT/results/detection-independent}
SEEDS=${3:-10}
NULLS=${4:-40}
DESIGN=${5:-lab}
T="$BUILD/tests/detection/independent_truth"
R="$BUILD/cli/ricochet"
S="$BUILD/tests/detection/detection_summary"
for exe in "$T" "$R" "$S"; do
  [ -x "$exe" ] || { echo "missing $exe: build it first" >&2; exit 2; }
done
case "$DESIGN" in lab | wide) ;; *) echo "DESIGN must be lab or wide" >&2; exit 2 ;; esac
mkdir -p "$OUT"
FAMILIES=${FAMILIES:-crsp_restitution kd_drag spin_rolling depth_friction_exp rankine_plough}
STRENGTHS=${STRENGTHS:-1 0.5 0.25 lab}
NS=${NS:-28 40}
JOBS=${JOBS:-1}

# Provenance of the run (appended on each resume).
echo "$(date -u +%FT%TZ) commit $(git -C "$ROOT" rev-parse --short HEAD 2>/dev/null || echo ?)" \
  "seeds $SEEDS nulls $NULLS design $DESIGN strengths '$STRENGTHS' ns '$NS' jobs $JOBS" >> "$OUT/study.log"

lab_strength() {  # FAMILY: the cached lab-scale strength ("none" where no strength reaches it)
  local f="$OUT/$1.lab-strength"
  [ -s "$f" ] || "$T" --family "$1" --calibrate-shift --design "$DESIGN" --n 40 --seed 1 > "$f" ||
    echo none > "$f"
  cat "$f"
}

strength_of() {  # FAMILY TOKEN: a number, "lab" or "2lab"
  case "$2" in
    lab) lab_strength "$1" ;;
    2lab) awk -v s="$(lab_strength "$1")" 'BEGIN { if (s == "none") print s; else printf "%.6g\n", 2 * s }' ;;
    *) echo "$2" ;;
  esac
}

# The list of sets: NAME FAMILY STRENGTH N SEED LADDER(0/1).
plan() {
  local fam s n seed k two
  for fam in $FAMILIES; do
    for tok in $STRENGTHS; do
      s=$(strength_of "$fam" "$tok")
      [ "$s" = none ] && continue
      for n in $NS; do
        for k in $(seq 1 "$SEEDS"); do
          seed=$([ "$n" = 40 ] && echo "$k" || echo $((100 + k)))
          echo "$fam-s$s-n$n-$DESIGN-$seed $fam $s $n $seed 0"
        done
      done
    done
  done
  for n in $NS; do
    for k in $(seq 1 "$NULLS"); do
      seed=$([ "$n" = 40 ] && echo $((1000 + k)) || echo $((1100 + k)))
      echo "none-n$n-$DESIGN-$seed none 0 $n $seed 0"
    done
  done
  two=$(printf '%s\n%s\n' "$(lab_strength crsp_restitution)" "$(lab_strength spin_rolling)" |
    sort -g | tail -1)
  for k in $(seq 1 "$SEEDS"); do
    echo "two-s$two-n40-$DESIGN-$((2000 + k)) two $two 40 $((2000 + k)) 1"
  done
}

PLAN=$(plan)
if [ -n "${DETECTION_ONLY:-}" ]; then
  PLAN=$(echo "$PLAN" | awk -v re="$DETECTION_ONLY" '$1 ~ re')
  [ -n "$PLAN" ] || { echo "DETECTION_ONLY matches no set" >&2; exit 2; }
fi
TOTAL=$(echo "$PLAN" | wc -l)
[ "$JOBS" -gt 1 ] && export OMP_NUM_THREADS=1

one_set() {  # I NAME FAMILY STRENGTH N SEED LADDER
  local i=$1 name=$2 fam=$3 s=$4 n=$5 seed=$6 ladder=$7 extra=""
  if [ -f "$OUT/$name.diagnose.json" ] && { [ "$ladder" = 0 ] || [ -f "$OUT/$name.ladder.json" ]; }; then
    return 0
  fi
  "$T" --family "$fam" --strength "$s" --n "$n" --design "$DESIGN" --seed "$seed" \
    --out "$OUT/$name.csv" --truth "$OUT/$name.truth.json"
  if [ ! -f "$OUT/$name.diagnose.json" ]; then
    "$R" diagnose "$OUT/$name.csv" --shape cylinder --json > "$OUT/$name.diagnose.json.tmp"
    mv "$OUT/$name.diagnose.json.tmp" "$OUT/$name.diagnose.json"
  fi
  if [ "$ladder" = 1 ]; then
    "$R" ladder "$OUT/$name.csv" --shape cylinder --auto 2 --json > "$OUT/$name.ladder.json.tmp"
    mv "$OUT/$name.ladder.json.tmp" "$OUT/$name.ladder.json"
    extra=" | ladder: $(jq -r '[.rungs[1:][].added] | join(", ")' "$OUT/$name.ladder.json")"
  fi
  echo "[$(date +%H:%M:%S)] $i/$TOTAL $name: $(jq -r '[.verdict, (if (.ranking | length) > 0 then .ranking[0].effect + (if .ranking[0].supported then " (supported)" else "" end) else "-" end), "\(.seconds | floor) s"] | join(" | ")' "$OUT/$name.diagnose.json")$extra"
}

i=0
while read -r name fam s n seed ladder <&3; do
  i=$((i + 1))
  one_set "$i" "$name" "$fam" "$s" "$n" "$seed" "$ladder" &
  while [ "$(jobs -rp | wc -l)" -ge "$JOBS" ]; do wait -n || exit 1; done
done 3<<< "$PLAN"
wait

echo "== summary ($OUT/summary.md, $OUT/summary.json)"
"$S" "$OUT" | tee "$OUT/summary.md"
