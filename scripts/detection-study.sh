#!/usr/bin/env bash
# Detection rate of the diagnosis against effect magnitude and number of releases (issue 6; not
# part of CI: about 20-30 minutes on this 2-core machine).
#
# For every effect family of the catalog, three magnitudes (1/4, 1/2 and 1 x the magnitude of
# the tests in tests/diagnosis/test_detection.cpp), three set sizes and several seeds, a
# synthetic set is generated with that effect hidden (`ricochet synth`, wide design, the same
# base parameters and noise as the tests) and diagnosed (`ricochet diagnose --json`). A run
# DETECTS the effect when the diagnosis ranks it first AND supports it. Sets without a hidden
# effect measure the false-alarm rate (any effect supported).
#
# usage: scripts/detection-study.sh BUILD_DIR [OUT_DIR] [SEEDS]
# Results: OUT_DIR/detection-study.csv (one row per run, appended as runs finish: a killed study
# resumes where it stopped) and OUT_DIR/detection-study.md (the summary table, rewritten at the
# end). docs/diagnosis.md quotes the numbers measured on this machine.
set -euo pipefail
BUILD=$(cd "$1" && pwd)
ROOT=$(cd "$(dirname "$0")/.." && pwd)
OUT=${2:-$ROOT/results/detection-study}
SEEDS=${3:-3}
R="$BUILD/ricochet"
[ -x "$R" ] || R="$BUILD/cli/ricochet"
mkdir -p "$OUT/sets"
CSV=$OUT/detection-study.csv
[ -f "$CSV" ] || echo "effect,magnitude,parameter,value,n,seed,top,supported,detected,drop,drop_se,heldout,base_error,noise_floor,false_alarm,seconds" > "$CSV"

BASE="--set en2=0.2 --set mu=0.4 --set muR=0.15"
LAB_NOISE="lab"
# effect | parameter | full magnitude | extra truth settings | noise
FAMILIES=(
  "rate_restitution|kv|0.25||lab"
  "inertial_drag|cd|2000||lab"
  "ploughing|cp|6e8||lab"
  "depth_friction|a_mu|1000|--set mu=0.05|lab,scale=0.5"
  "hertz_stiffness|beta|1.0||lab,penetration=1e-4,contact_duration=2e-4"
)

done_before() {  # effect magnitude n seed
  grep -q "^$1,$2,[^,]*,[^,]*,$3,$4," "$CSV"
}

run_one() {  # effect parameter value magnitude n seed extra noise
  local effect=$1 param=$2 value=$3 mag=$4 n=$5 seed=$6 extra=$7 noise=$8
  done_before "$effect" "$mag" "$n" "$seed" && return 0
  local set="$OUT/sets/$effect-$mag-$n-$seed.csv"
  local add=""
  [ "$effect" != none ] && add="--add $effect --set $param=$value"
  # shellcheck disable=SC2086
  "$R" synth --n "$n" --seed "$seed" --design wide $BASE $add $extra --noise "$noise" \
    --out "$set" > /dev/null
  local t0 t1
  t0=$(date +%s.%N)
  "$R" diagnose "$set" --shape cylinder --no-release-fits --json > "$set.json"
  t1=$(date +%s.%N)
  python3 - "$set.json" "$effect" "$mag" "$param" "$value" "$n" "$seed" "$t0" "$t1" >> "$CSV" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
effect, mag, param, value, n, seed, t0, t1 = sys.argv[2:10]
top = d["ranking"][0]
hidden = next((c for c in d["ranking"] if c["effect"] == effect), None)
supported_any = any(c["supported"] for c in d["ranking"])
detected = int(top["effect"] == effect and top["supported"])
drop = hidden["error_drop"] if hidden else float("nan")
se = hidden["drop_se"] if hidden else float("nan")
print(f"{effect},{mag},{param},{value},{n},{seed},{top['effect']},{int(top['supported'])},"
      f"{detected},{drop:.6g},{se:.6g},{(hidden or top)['heldout_error']:.6g},"
      f"{d['base_error']:.6g},{d['noise_floor']:.6g},"
      f"{int(supported_any and effect == 'none')},{float(t1) - float(t0):.2f}")
PY
  tail -1 "$CSV"
}

for n in 15 30 60; do
  for ((seed = 101; seed < 101 + SEEDS; ++seed)); do
    for fam in "${FAMILIES[@]}"; do
      IFS='|' read -r effect param full extra noise <<< "$fam"
      for frac in 0.25 0.5 1; do
        value=$(python3 -c "print(f'{$full * $frac:.6g}')")
        run_one "$effect" "$param" "$value" "$frac" "$n" "$seed" "$extra" "$noise"
      done
    done
    # No hidden effect (false alarms): twice as many seeds.
    run_one none - 0 0 "$n" "$seed" "" "$LAB_NOISE"
    run_one none - 0 0 "$n" "$((seed + 1000))" "" "$LAB_NOISE"
  done
done

python3 - "$CSV" > "$OUT/detection-study.md" <<'PY'
import csv, sys, collections
rows = list(csv.DictReader(open(sys.argv[1])))
cells = collections.defaultdict(list)
for r in rows:
    cells[(r["effect"], float(r["magnitude"]), int(r["n"]))].append(r)
print("| effect | magnitude (x test) | parameter value | n = 15 | n = 30 | n = 60 |")
print("| :-- | --: | --: | --: | --: | --: |")
effects = sorted({k[0] for k in cells if k[0] != "none"})
for e in effects:
    for m in sorted({k[1] for k in cells if k[0] == e}):
        vals = []
        value = ""
        for n in (15, 30, 60):
            rs = cells.get((e, m, n), [])
            if rs:
                value = rs[0]["value"]
                det = sum(int(r["detected"]) for r in rs)
                z = [float(r["drop"]) / float(r["drop_se"]) for r in rs
                     if float(r["drop_se"]) > 0]
                vals.append(f"{det}/{len(rs)} (z {sum(z)/len(z):.1f})" if z else f"{det}/{len(rs)}")
            else:
                vals.append("-")
        print(f"| {e} | {m:g} | {rows and value} | " + " | ".join(vals) + " |")
for n in (15, 30, 60):
    rs = cells.get(("none", 0.0, n), [])
    if rs:
        fa = sum(int(r["false_alarm"]) for r in rs)
        print(f"\nNo hidden effect, n = {n}: {fa}/{len(rs)} false alarms")
secs = [float(r["seconds"]) for r in rows]
print(f"\n{len(rows)} diagnoses, median {sorted(secs)[len(secs)//2]:.1f} s each")
PY
cat "$OUT/detection-study.md"
