#!/usr/bin/env bash
# Issue 32, item 2: does the angle of repose of the grains hang on how it is measured? The repose
# deck (liggghts-inputs/repose) collapses a column of aspect ratio H/L = 1.5 in a periodic slot
# and fits the heap's flank. In a quasi-2-D collapse above an aspect ratio of about 0.7 the whole
# column flows and the deposit's slope is a runout profile, not the static angle of repose; below
# it the top of the column stays in place and the flank fails at the angle of repose (Lajeunesse,
# Monnier & Homsy 2005, Phys. Fluids 17, 103302; Balmforth & Kerswell 2005, J. Fluid Mech. 538,
# 399). This study measures both geometries on the same grains, with replica seeds, and one
# column twice as large (the heap's size in grains):
#
#   cal-a1.5-sS      the calibrated grains (data/resolved/sand-calibration-1.5e9.json, E_grain
#                    1.5e9 Pa), the deck's column (L 0.08 m, H 0.12 m), replica seed S
#   cal-a0.375-sS    the same grains, a low column (L 0.16 m, H 0.06 m): the same grain count
#   cal-a0.375-x2    the low column at twice the size (L 0.32 m, H 0.12 m, floor 0.6 m)
#   def-a0.375-sS    the decks' default grains at 1.5e9 Pa in the low column (their deck value,
#                    26.3 deg, is data/resolved/sphere-drop-1.5e9.repose.json)
#
# About 3-4 min of one core per run at the deck's size, about 15 min for x2: 10 runs, under an
# hour. Resumable: a run whose JSON exists is skipped.
#
#   scripts/repose-study.sh [RICOCHET]        # writes results/repose-study/NAME.json, table.md
#
# REPOSE_OUT (default results/repose-study) is where it goes; the shipped copy is
# data/resolved/repose-study/ (the JSONs and table.md). Exit 1 when a run fails (the others
# still run), 2 on a missing file.
set -uo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
BIN=${1:-$ROOT/build/cli/ricochet}
OUT=${REPOSE_OUT:-$ROOT/results/repose-study}
CALIBRATION=$ROOT/data/resolved/sand-calibration-1.5e9.json
SAMPLED=$ROOT/liggghts-inputs/campaigns/sand-calibration-1.5e9.toml
for f in "$BIN" "$CALIBRATION" "$SAMPLED"; do
  [ -e "$f" ] || { echo "$0: no such file: $f" >&2; exit 2; }
done
mkdir -p "$OUT"
# The calibrated grains: the bed.* settings of the verification campaign (the repose deck has no
# block).
SETS=$(python3 "$ROOT/scripts/verification-campaign.py" "$SAMPLED" "$CALIBRATION" --sets) || exit 2
CAL=()
while read -r s; do
  [[ $s == bed.* ]] && CAL+=(--set "$s")
done <<< "$SETS"
DEF=(--set bed.E_grain_Pa=1.5e9)
LOW=(--set repose.L_col_m=0.16 --set repose.H_col_m=0.06)
LOW2=(--set repose.L_col_m=0.32 --set repose.H_col_m=0.12 --set repose.L_floor_m=0.6)

status=0
run() {  # NAME ARGS...: one repose run into OUT/NAME.json unless it is there
  local name=$1
  shift
  [ -f "$OUT/$name.json" ] && return 0
  echo "== $(date '+%F %T') $name"
  # The file is written whole (through a temporary file); a run without a slope to fit keeps its
  # JSON as NAME.failed.json, for the reader, and is tried again on the next start.
  if ! "$BIN" dem repose "$@" --work "$OUT/work/$name" --out "$OUT/$name.json"; then
    echo "$0: $name failed (log: $OUT/work/$name/repose)" >&2
    [ -f "$OUT/$name.json" ] && mv "$OUT/$name.json" "$OUT/$name.failed.json"
    status=1
  fi
}
for s in 0 1 2; do
  run "cal-a0.375-s$s" "${CAL[@]}" "${LOW[@]}" --seed "$s"
  run "cal-a1.5-s$s" "${CAL[@]}" --seed "$s"
  run "def-a0.375-s$s" "${DEF[@]}" "${LOW[@]}" --seed "$s"
done
run cal-a0.375-x2 "${CAL[@]}" "${LOW2[@]}"

# The table: one row per run, then the mean and sd over the seeds of each configuration.
python3 - "$OUT" > "$OUT/table.md" <<'PY'
import glob, json, os, statistics, sys
out = sys.argv[1]
rows = []
for path in sorted(p for p in glob.glob(os.path.join(out, "*.json")) if not p.endswith(".failed.json")):
    j = json.load(open(path))
    o = j.get("repose_overrides", {})
    L, H = float(o.get("L_col_m", 0.08)), float(o.get("H_col_m", 0.12))
    name = os.path.basename(path)[:-5]
    rows.append((name, name.rsplit("-s", 1)[0] if "-s" in name else name, L, H, j))
print("| run | column L x H [m] | a = H/L | grains | angle [deg] | fitted x [m] | status |")
print("| :-- | :-- | --: | --: | --: | :-- | :-- |")
for name, _, L, H, j in rows:
    x = j.get("fitted_x_m") or []
    fitted = f"{x[0]:.3f}-{x[1]:.3f}" if len(x) == 2 and None not in x else ""
    print(f"| {name} | {L:g} x {H:g} | {H / L:.3g} | {j['grains']} | "
          f"{j['angle_deg']:.1f} +- {j['angle_se_deg']:.1f} | {fitted} | {j['status']} |")
print()
print("| configuration | runs | mean angle [deg] | sd over seeds [deg] |")
print("| :-- | --: | --: | --: |")
groups = {}
for name, group, *_ , j in rows:
    groups.setdefault(group, []).append(j["angle_deg"])
for group, angles in groups.items():
    sd = f"{statistics.stdev(angles):.1f}" if len(angles) > 1 else ""
    print(f"| {group} | {len(angles)} | {statistics.mean(angles):.1f} | {sd} |")
PY
echo "table: $OUT/table.md"
exit $status
