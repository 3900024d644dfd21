#!/usr/bin/env bash
# Issue 32, item 3: the sphere drop on the stiff bed (docs/granular-impact-checks.md, "On the
# stiff bed (issue 32)": the design and the reading were fixed there before the run). A 10 cm
# steel sphere (D/d = 13 on the default grains of 3-4.5 mm radius) dropped from five heights
# (h = 0.02-0.5 m, H over a factor of about 13) into a 3-D box bed 0.40 x 0.40 x 0.20 m of the
# decks' grains at E_grain = 1.5e9 Pa (the level of item 2's calibration), walls E_WALL_PA.
# Hours of one core: run it in the background; it resumes after any interruption (the drops in
# the output file are skipped, the bed and the repose run are cached).
#
#   E_WALL_PA=1.5e9 nohup setsid scripts/plateau-drop.sh > /dev/null 2>&1 &
#   tail -f results/plateau-drop/drop.log
#
# - One MPI rank (the other core runs the plateau campaign); one copy at a time (flock).
# - Pinned program and decks, as scripts/stiffness-plateau.sh: the first start copies
#   build/cli/ricochet and liggghts-inputs/ into results/plateau-drop/pinned/.
# - E_WALL_PA (default 5e7, the decks'): the box walls' modulus, by item 2's rule (the floor check
#   of docs/resolved-model.md decides it); it is part of the bed, so changing it makes a new bed.
# Writes results/plateau-drop/sphere-drop-1.5e9.{csv,tracks.csv,repose.json} and the summary
# sphere-drop-1.5e9.json at the end; the shipped copy goes to data/resolved/.
#
# The same drops on a calibration's grains (issue 33's Katsuragi-Durian comparison on the bed of
# its force campaign; docs/granular-impact-checks.md, "On the sand-calibrated grains"):
#   DROP_GRAINS_FROM="SAMPLED.toml CALIBRATION.json"  the grains of scripts/verification-campaign.py
#                                                     --sets, added after the stiff bed's --set
#   DROP_OUT (default results/plateau-drop), DROP_FILE (default sphere-drop-1.5e9): where it goes.
set -uo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
# shellcheck source=pin-program.sh
source "$ROOT/scripts/pin-program.sh"
OUT=${DROP_OUT:-$ROOT/results/plateau-drop}
FILE=${DROP_FILE:-sphere-drop-1.5e9}
E_WALL=${E_WALL_PA:-5e7}
GRAINS=()
if [ -n "${DROP_GRAINS_FROM:-}" ]; then
  # shellcheck disable=SC2086  # two paths, split on purpose
  SETS=$(python3 "$ROOT/scripts/verification-campaign.py" $DROP_GRAINS_FROM --sets) || exit 2
  while read -r s; do GRAINS+=(--set "$s"); done <<< "$SETS"
fi
mkdir -p "$OUT"
LOG=$OUT/drop.log
exec 9> "$OUT/drop.lock"
if ! flock -n 9; then
  echo "$(date '+%F %T') another plateau-drop run holds $OUT/drop.lock: not started" >> "$LOG"
  exit 1
fi
{
  echo "== $(date '+%F %T') plateau-drop: start (pid $$, E_wall $E_WALL Pa, $FILE${GRAINS[*]:+, ${GRAINS[*]}})"
  PIN=$OUT/pinned
  pin_program "$ROOT" "$PIN"
  SHIPPED=$ROOT/data/resolved/$FILE.csv
  if [ ! -f "$OUT/$FILE.csv" ] && [ -f "$SHIPPED" ]; then
    cp "$SHIPPED" "$OUT/"
    [ -f "${SHIPPED%.csv}.tracks.csv" ] && cp "${SHIPPED%.csv}.tracks.csv" "$OUT/"
    [ -f "${SHIPPED%.csv}.repose.json" ] && cp "${SHIPPED%.csv}.repose.json" "$OUT/"
    [ -f "${SHIPPED%.csv}.json" ] && cp "${SHIPPED%.csv}.json" "$OUT/"
    echo "resuming from the shipped $SHIPPED"
  fi
  # The summary is written only after every drop ended well: with it, nothing is left to run.
  # (`dem drop` itself would build the bed again for its summary, an hour of a core on a new
  # machine, as it did on 2026-12-07.)
  if [ -f "$OUT/$FILE.json" ]; then
    echo "== $(date '+%F %T') plateau-drop: every drop and the summary $OUT/$FILE.json are in: nothing to run"
    exit 0
  fi
  cd "$OUT" || exit 1
  BED=(--set bed.mode=box --set bed.Lx_m=0.4 --set bed.Ly_m=0.4 --set bed.H_m=0.2
       --set bed.headroom_m=0.15 --set bed.E_grain_Pa=1.5e9 --set bed.E_wall_Pa="$E_WALL"
       --set drop.D_sphere_m=0.1 --set drop.t_max_s=1.0 "${GRAINS[@]}")
  mpirun --oversubscribe --allow-run-as-root --bind-to none -np 1 "$PIN/ricochet" dem drop \
    --decks "$PIN/liggghts-inputs" --cache dem-cache --work dem-work "${BED[@]}" \
    --heights 0.02,0.05,0.1,0.2,0.5 --out "$OUT/$FILE.csv"
  rc=$?
  echo "== $(date '+%F %T') plateau-drop: drops ended with status $rc"
  if [ "$rc" -eq 0 ]; then
    "$PIN/ricochet" dem drop --decks "$PIN/liggghts-inputs" --cache dem-cache --work dem-work \
      "${BED[@]}" --heights 0.02,0.05,0.1,0.2,0.5 --out "$OUT/$FILE.csv" --json \
      > "$OUT/$FILE.json"
    echo "summary: $OUT/$FILE.json"
  fi
} >> "$LOG" 2>&1
