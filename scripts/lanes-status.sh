#!/usr/bin/env bash
# What each long DEM run of scripts/dem-lanes.sh was doing when it last wrote its log, and whether
# its pinned program may be replaced (rm -rf its pinned/ folder) before the lanes start again.
#
#   scripts/lanes-status.sh            (from the repository root, lanes stopped or running)
#
# Per campaign folder under results/ (a campaign.log and a pinned/ folder): whether it runs now
# (its lock is held), the last impact started and whether its bed build (with its latest
# checkpoint) or the impact itself was in flight, how many of the design's impacts its file holds,
# and whether the pinned decks predate the tree's bed decks. Re-pinning gives a
# campaign the tree's program and decks (e.g. bed builds that resume after a kill, since
# 2026-12-07), but the decks' text is part of every bed's key: the pending impacts then get new
# beds, and an impact that was cut in flight loses its checkpoint. So it is safe only while the
# campaign is stopped with nothing in flight or with a bed build in flight (a build of pinned
# decks older than 2026-12-07 restarts from zero anyway). Prints one block per folder; exit 0.
set -uo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
cd "$ROOT" || exit 1
bed_decks_differ() {  # PIN: 0 when the pinned bed decks equal the tree's
  ! diff -rq "$1/liggghts-inputs/bed" liggghts-inputs/bed > /dev/null 2>&1 ||
    ! diff -rq "$1/liggghts-inputs/common" liggghts-inputs/common > /dev/null 2>&1
}
for log in results/*/campaign.log; do
  dir=$(dirname "$log")
  [ -d "$dir/pinned" ] || continue
  running=no
  if [ -e "$dir/campaign.lock" ]; then
    exec 8< "$dir/campaign.lock"
    flock -n 8 || running=yes
    exec 8<&-
  fi
  start=$(grep -n '^\[dem\] starting ' "$log" | tail -1)
  line=${start%%:*}
  state="nothing started"
  if [ -n "$start" ]; then
    id=$(sed -E 's/^[0-9]+:\[dem\] starting ([^ ]+) .*/\1/' <<< "$start")
    after=$(tail -n +"$line" "$log")
    if grep -qE "^\[dem\] [0-9]+/[0-9]+ $id " <<< "$after"; then
      state="$id ended: nothing in flight"
    elif grep -q 'building it first' <<< "$start" && ! grep -q 'grains built in' <<< "$after"; then
      state="$id: its bed build in flight"
      key=$(sed -E 's/.*bed ([0-9a-f]+): building.*/\1/' <<< "$start")
      # The build's latest checkpoint (src-ext/bed.hpp: ckpt-PHASE-CHUNK-SETTLED), if any.
      ckpt=$(find "$dir/dem-cache" -maxdepth 1 -name "bed-$key.building.ckpt-*.restart" \
        -printf '%TY-%Tm-%Td %TH:%TM %f\n' 2> /dev/null | sort | tail -1)
      [ -n "$ckpt" ] && state+=" (checkpoint $(sed -E 's/^(.*) bed-.*ckpt-([0-9]+)-([0-9]+)-.*/phase \2, chunk \3, written \1/' <<< "$ckpt"))"
    else
      state="$id: the impact in flight (checkpointed)"
      # Where it is: the last thermo line of its LIGGGHTS screen (liggghts-inputs/impact/
      # setup.in's thermo_style: step, atoms, t [s], ..., fc [N] the block's contact force) and
      # the wall time of the last 100 steps.
      screen=$(find "$dir/dem-work" -path "*/$id/screen.txt" 2> /dev/null | head -1)
      if [ -n "$screen" ]; then
        where=$(awk '$1 == "Step" { for (i = 1; i <= NF; ++i) col[$i] = i; next }
          $1 ~ /^[0-9]+$/ && NF > 10 && ("t" in col) { last = $0 }
          /^Loop time of/ { loop = $4; per = $9 }
          END { if (last == "") exit; split(last, f)
            printf "step %d, t = %.4f s simulated, contact force %.0f N", f[col["Step"]],
              f[col["t"]], ("fc" in col) ? f[col["fc"]] : 0
            if (loop != "" && per > 0) printf ", %.1f s of wall per 100 steps", 100 * loop / per }' \
          "$screen")
        [ -n "$where" ] && state+=" [$where]"
      fi
    fi
  fi
  # Progress: the last "[dem] N/M ID" line (the impacts its file holds; the last run's design,
  # which may be part of the file's, e.g. a run of --only states).
  done_line=$(grep -oE '^\[dem\] [0-9]+/[0-9]+ ' "$log" | tail -1)
  [ -n "$done_line" ] && state+="; $(sed -E 's/^\[dem\] ([0-9]+)\/([0-9]+) /its file holds \1 impacts (the last run: \2 in its design)/' <<< "$done_line")"
  # Beds shipped for a campaign still to run, keyed by this folder's pinned decks
  # (scripts/ship-beds.sh writes pinned-in): a re-pin would orphan them.
  shipped_for=$(grep -lx "$(basename "$dir")" data/resolved/beds/*/pinned-in 2> /dev/null |
    xargs -r -n1 dirname | paste -sd' ')
  if bed_decks_differ "$dir/pinned"; then decks="older than the tree's"; else decks="the tree's"; fi
  case "$running/$state" in
    yes/*) advice="running: leave it" ;;
    */*"impact in flight"*) advice="keep the pin (re-pinning loses the impact's checkpoint and bed)" ;;
    *) if [ -n "$shipped_for" ]; then
         advice="keep the pin: $shipped_for holds beds keyed by its pinned decks"
       elif [ "$decks" = "the tree's" ]; then advice="pin is current"; else
         advice="may be re-pinned: rm -rf $dir/pinned"; fi ;;
  esac
  printf '%s\n  last: %s\n  pinned bed decks: %s\n  %s\n' "$dir" "$state" "$decks" "$advice"
done
# Beds shipped for a campaign still to run are keyed by its pinned decks: a re-pin orphans them.
# So are the checkpoints in flight shipped beside them (scripts/ship-beds.sh), which the next start
# resumes from (scripts/seed-shipped.sh).
for b in data/resolved/beds/*/; do
  beds=$(find "$b" -maxdepth 1 -name 'bed-*.params' | wc -l)
  ckpts=$(find "$b" -maxdepth 1 -name 'bed-*.building.ckpt-*.restart.xz' -printf '%f ' |
    sed -E 's/bed-([0-9a-f]+)\.building\.ckpt-([0-9]+)-([0-9]+)-[0-9]+\.restart\.xz/\1 (phase \2, chunk \3)/g')
  impacts=$(find "$b" -maxdepth 1 -name 'impact-*.tar.xz' -printf '%f ' |
    sed -E 's/impact-(.+)\.gen-([0-9]+)\.tar\.xz/\1 (checkpoint \2)/g')
  [ "$beds" -gt 0 ] || [ -n "$ckpts" ] || [ -n "$impacts" ] || continue
  echo "note: $b holds for a campaign still to run, keyed by the pinned decks of" \
    "results/$(cat "$b/pinned-in" 2> /dev/null || echo '(unknown: ship-beds.sh writes pinned-in)'):" \
    "$beds beds${ckpts:+; bed builds in flight: $ckpts}${impacts:+; impacts in flight: $impacts}"
done
# Sphere drops (scripts/plateau-drop.sh): not checkpointed; a folder without a pinned program
# takes the tree's at its next start.
for log in results/*/drop.log; do
  dir=$(dirname "$log")
  if [ -x "$dir/pinned/ricochet" ]; then pin="pinned"; else pin="pins the tree's program at its next start"; fi
  printf '%s\n  last: %s\n  %s\n' "$dir" "$(tail -1 "$log")" "$pin"
done
exit 0
