#!/usr/bin/env bash
# Issue 32, item 1: the stiffness-plateau campaign (liggghts-inputs/campaigns/stiffness-plateau.toml;
# the design, the rule fixed before the run and the cost estimate are in its header and in
# docs/resolved-model.md, "Stiffness plateau (issue 32)"). Days of one core: run it in the
# background, it survives the session and resumes after any interruption.
#
#   nohup setsid scripts/stiffness-plateau.sh > /dev/null 2>&1 &
#   tail -f results/plateau/campaign.log
#
# - One MPI rank (the machine has two cores; the other one is for other work).
# - Fixed working directory results/plateau/: the design's cache_dir (dem-cache) and work_dir
#   (dem-work/stiffness-plateau) are relative to it.
# - Resumable: the campaign skips the impacts already in results/plateau/stiffness-plateau.h5 and
#   reruns the one a kill interrupted (`--retry-crashed` also reruns one during which LIGGGHTS
#   stopped the process). Start the script again after a reboot or a kill.
# - One copy at a time: a second start while one runs exits at once (flock on
#   results/plateau/campaign.lock), saying so in the log.
# - Pinned program and decks (scripts/pin-program.sh): the first start copies build/cli/ricochet and liggghts-inputs/ into
#   results/plateau/pinned/ (taking the shared build lock, so that it never copies a binary being
#   linked) and every later start uses that copy, so that a campaign of several days runs one
#   program on one set of decks (a deck edited meanwhile would change the bed cache key and
#   rebuild beds). Delete results/plateau/pinned/ to take the tree's current ones on the next start.
#
# - Across sessions: a session copies the file so far to data/resolved/stiffness-plateau.h5 and
#   commits it; a new work tree without results/plateau/ resumes from that copy. The beds that
#   the impacts still to run need are shipped beside it (scripts/ship-beds.sh, into
#   data/resolved/beds/FILE/) and seeded into the cache here; the others are built again from
#   their seeds.
# - PLATEAU_DESIGN (environment, default stiffness-plateau): the design's name in
#   liggghts-inputs/campaigns/. stiffness-plateau-1.5e10 is the first design plus the 1.5e10 Pa
#   level (the rule's pre-registered consequence): it continues the same campaign file, its first
#   63 impacts found done. A design not pinned yet is pinned beside the program on its first start.
# - PLATEAU_OUT and PLATEAU_FILE (environment, defaults results/plateau and stiffness-plateau):
#   the folder and the campaign file's name, for a side study run beside the plateau campaign with
#   its own lock, pins, cache and log, e.g. the floor check (docs/resolved-model.md):
#     PLATEAU_DESIGN=wall-stiffness-1.5e9 PLATEAU_OUT=results/wall-stiffness \
#       PLATEAU_FILE=wall-stiffness nohup setsid scripts/stiffness-plateau.sh > /dev/null 2>&1 &
# When the campaign ends the script prints the status counts; the table and figure of
# docs/resolved-model.md are made from the file afterwards.
# - PLATEAU_DESIGN_PATH (environment, optional): a design file elsewhere than
#   liggghts-inputs/campaigns/ (a generated one: scripts/verification-campaign.py).
# - PLATEAU_RANKS (environment, default 1): MPI ranks; with the design's ranks_per_impact = 1,
#   2 ranks run two impacts at a time (both cores of this machine).
# - PLATEAU_FIRST=N (environment, optional): run only the design's first N impacts (a campaign
#   stopped early by design, e.g. the 1.5e10 Pa level's pre-registered minimum: its cylinder and
#   first three triangle states, PLATEAU_FIRST=75); the same campaign file, so a later run of the
#   whole design resumes after them.
# - PLATEAU_ONLY=ID,... (environment, optional): run only these impacts of the design
#   (`dem campaign --only`: the specs the whole design gives them, e.g. a generated design's
#   sampled orientations), into the same campaign file (the triangles' active-zone check of
#   scripts/dem-lanes.sh).
set -uo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
# shellcheck source=pin-program.sh
source "$ROOT/scripts/pin-program.sh"
OUT=$ROOT/${PLATEAU_OUT:-results/plateau}
FILE=${PLATEAU_FILE:-stiffness-plateau}
NAME=${PLATEAU_DESIGN:-stiffness-plateau}
DESIGN=${PLATEAU_DESIGN_PATH:-$ROOT/liggghts-inputs/campaigns/$NAME.toml}
[ -f "$DESIGN" ] || { echo "no design $DESIGN" >&2; exit 2; }
mkdir -p "$OUT"
LOG=$OUT/campaign.log

exec 9> "$OUT/campaign.lock"
if ! flock -n 9; then
  echo "$(date '+%F %T') another $NAME run holds $OUT/campaign.lock: not started" >> "$LOG"
  exit 1
fi

{
  echo "== $(date '+%F %T') $NAME: start (pid $$, host $(hostname))"
  PIN=$OUT/pinned
  pin_program "$ROOT" "$PIN"
  if [ ! -f "$PIN/$NAME.toml" ]; then
    cp "$DESIGN" "$PIN/$NAME.toml"
    echo "pinned the design $NAME"
  elif ! cmp -s "$DESIGN" "$PIN/$NAME.toml"; then
    echo "note: $DESIGN differs from the pinned copy; running the pinned design"
  fi
  # A new work tree (the next session's) resumes from the impacts shipped so far.
  SHIPPED=$ROOT/data/resolved/$FILE.h5
  if [ ! -f "$OUT/$FILE.h5" ] && [ -f "$SHIPPED" ]; then
    cp "$SHIPPED" "$OUT/$FILE.h5"
    echo "resuming from the shipped $SHIPPED"
  fi
  # ... and from what scripts/ship-beds.sh shipped beside it: beds, and a bed build's or an
  # impact's checkpoint in flight (scripts/seed-shipped.sh). The cache folder as the program
  # reads the design (its dry run), not a second parser of it.
  CACHE=$("$PIN/ricochet" dem campaign "$PIN/$NAME.toml" --decks "$PIN/liggghts-inputs" --dry-run \
    --json 2>/dev/null | python3 -c 'import json, sys; print(json.load(sys.stdin)["cache_dir"])')
  case $CACHE in /*) ;; *) CACHE=$OUT/$CACHE ;; esac
  "$ROOT/scripts/seed-shipped.sh" "$ROOT/data/resolved/beds/$FILE" "$OUT" "$CACHE"
  RUN_DESIGN=$PIN/$NAME.toml
  if [ -n "${PLATEAU_FIRST:-}" ]; then
    RUN_DESIGN=$PIN/$NAME.first$PLATEAU_FIRST.toml
    awk -v n="$PLATEAU_FIRST" '/^\[\[impact\]\]/ { k++ } k <= n' "$PIN/$NAME.toml" > "$RUN_DESIGN"
    echo "running the first $PLATEAU_FIRST impacts of the design ($RUN_DESIGN)"
  fi
  ONLY=()
  if [ -n "${PLATEAU_ONLY:-}" ]; then
    ONLY=(--only "$PLATEAU_ONLY")
    echo "running only $PLATEAU_ONLY of the design"
  fi
  # What scripts/ship-session.sh ships at a session's end: this folder's design and file.
  echo "$NAME $FILE" > "$OUT/running"
  cd "$OUT" || exit 1   # cache_dir and work_dir of the design are relative to this folder
  mpirun --oversubscribe --allow-run-as-root --bind-to none -np "${PLATEAU_RANKS:-1}" "$PIN/ricochet" dem campaign \
    "$RUN_DESIGN" --decks "$PIN/liggghts-inputs" "${ONLY[@]}" \
    --out "$OUT/$FILE.h5" --retry-crashed
  rc=$?
  echo "== $(date '+%F %T') $NAME: campaign command ended with status $rc"
  if [ "$rc" -eq 0 ]; then
    "$PIN/ricochet" dem campaign "$RUN_DESIGN" --decks "$PIN/liggghts-inputs" "${ONLY[@]}" \
      --out "$OUT/$FILE.h5" --json 2>/dev/null \
      | python3 -c "import json,sys; d=json.load(sys.stdin); print('status counts:', d['status_counts'])" \
      || true
  fi
} >> "$LOG" 2>&1
