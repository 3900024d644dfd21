#!/usr/bin/env bash
# Issue 32's background campaigns on this 2-core machine, each resumable (a finished step returns
# at once, an interrupted one resumes from its file), in the order of what the issue needs most:
#   1. the sand-only recalibration at 1.5e9 Pa on both cores (two impacts at a time;
#      liggghts-inputs/campaigns/sand-calibration-1.5e9.toml into results/sand-calibration/, the
#      plan of docs/resolved-model.md): everything after it (the held-out check, the blind
#      triangles and the main job on the calibrated bed) waits for it;
#   1b. then the calibration itself (calibrate-grains with the solid-fraction band), the active
#      zone's paired check at its grains (scripts/active-zone-verdict.sh: the zone is used below
#      only if it passed), its verification campaign (every lab state on three 1.5 m beds of the calibrated grains, into
#      results/sand-verification/) and the blind triangles on those grains, on both cores (after
#      their own active-zone check, amended on 2026-12-06: the zone when it passes), and
#      the design of issue 33's force campaign (the speed campaign's states on those grains);
#   2. then two lanes of one core each:
#      lane A: the convergence at 1.5e9 Pa (width, depth, grain size: convergence-1.5e9.toml,
#              into results/convergence-1.5e9/; issue 32, item 3), then issue 33's force campaign
#              (its design from 1b, on one core), then whatever of the stiffness plateau's 1.5e10
#              Pa level lane B has not taken (below);
#      lane B: the sphere drop on the 1.5e9 Pa box bed (scripts/plateau-drop.sh), then the
#              floor check of the stiffness plateau's 1.5e10 Pa level (wall-stiffness-1.5e10.toml,
#              into results/wall-stiffness-1.5e10/), the level up to its pre-registered minimum
#              (the cylinder and the triangle states T18, T02, T10: the design's first 75
#              impacts, 12 pairs), the same drops on the calibrated grains (issue 33's
#              Katsuragi-Durian comparison, into results/sand-drop/), the level's other three
#              triangle states, then the packing-scatter beds' solid fractions
#              (scripts/packing-scatter-beds.sh).
#      (Reordered on 2026-12-06, evening, before any 1.5e10 Pa result beyond the cylinder's three
#      pairs: the plateau decides at which stiffness everything else of issue 32 is read, and the
#      drops free lane B within a session, while the convergence holds lane A for about five; so
#      the level goes to lane B ahead of issue 33's drops, by the lowest issue first. A campaign
#      holds its folder's lock, so the lane that reaches a campaign the other one runs skips it
#      and goes on: stiffness-plateau.sh exits at once, saying so in that campaign's log.
#      Reordered again on 2026-12-07, with 4 of the minimum's 12 pairs in: the floor check before
#      the rest of the minimum. The 1.5e10 Pa cylinder's move cannot be told from the soft
#      walls' until the check answers, and if the walls made it, the level's remaining
#      soft-wall triangle impacts would have to be run again with stiff walls: the check is 3
#      impacts, the minimum's rest 8. Both readings stay as fixed before their runs.)
# Start it at the beginning of a session and let it run; a session's end stops it, the next
# start resumes it (an impact that was running resumes from its last checkpoint, every
# run.checkpoint_steps steps, in every campaign pinned since 2026-12-05: docs/commands/dem.md). On a new machine, build the program alone first, start the campaigns, then
# build the rest (the program is pinned when a campaign starts, so the rest never relinks it):
#
#   ./run.sh build ricochet && (nohup setsid scripts/dem-lanes.sh > /dev/null 2>&1 &) && ./run.sh build
#   nohup setsid scripts/dem-lanes.sh > /dev/null 2>&1 &      # on a machine already built
#   scripts/ship-session.sh     # at the session's end, lanes running: what the next machine
#                               # resumes from (then commit data/resolved/)
#   tail results/sand-calibration/campaign.log results/plateau/campaign.log \
#        results/plateau-drop/drop.log
#
# Where the results live: results/ of the work tree, which a new session may lay anew (beds and
# campaign files lost). Unless results/ exists already, it is made a link to RICOCHET_RESULTS
# (default: ricochet-results beside the checkout), which outlives the work tree on a machine that
# is kept; on a new machine the campaigns resume from the impacts shipped in data/resolved/ and
# from the beds shipped for them (data/resolved/beds/, scripts/ship-beds.sh).
set -uo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
# Two single-rank MPI jobs run at once: Open MPI would bind both to core 0 (it did until
# 2026-12-07, docs/resolved-model.md "Cost"); no binding for any mpirun below.
export OMPI_MCA_hwloc_base_binding_policy=none
cd "$ROOT" || exit 1
if [ ! -e results ]; then
  KEEP=${RICOCHET_RESULTS:-$(dirname "$ROOT")/ricochet-results}
  mkdir -p "$KEEP" && ln -s "$KEEP" results
fi
# Whether a campaign of scripts/stiffness-plateau.sh has nothing left to run: its pinned program's
# dry run of its pinned design (the design's impacts and the end-wall reruns the file calls for,
# docs/commands/dem.md) finds no impact to run. DIR: its folder; NAME: its design's; FILE: its
# campaign file's. False while it was never started.
campaign_done() {
  [ -x "$1/pinned/ricochet" ] && [ -f "$1/pinned/$2.toml" ] && [ -f "$1/$3.h5" ] || return 1
  (cd "$1" && pinned/ricochet dem campaign "pinned/$2.toml" --decks pinned/liggghts-inputs \
     --out "$3.h5" --dry-run --json 2>/dev/null) |
    python3 -c 'import json, sys; sys.exit(0 if json.load(sys.stdin)["to_run"] == 0 else 1)'
}
# Runs started by hand hold their locks: wait for them before taking both cores.
mkdir -p results/plateau results/plateau-drop results/sand-calibration
flock results/sand-calibration/campaign.lock true
flock results/plateau/campaign.lock true
flock results/plateau-drop/drop.lock true
PLATEAU_DESIGN=sand-calibration-1.5e9 PLATEAU_OUT=results/sand-calibration \
  PLATEAU_FILE=sand-calibration-1.5e9 PLATEAU_RANKS=2 scripts/stiffness-plateau.sh
CAL=results/sand-calibration
# A campaign that ended with impacts still to run failed (its log says how): stop here rather
# than spend the cores on the lanes below, which would hide the failure behind hours of their runs.
if ! campaign_done "$CAL" sand-calibration-1.5e9 sand-calibration-1.5e9; then
  echo "== $(date '+%F %T') the sand calibration's campaign ended with impacts still to run:" \
    "nothing else started (see the lines above)" >> "$CAL/campaign.log"
  exit 1
fi
# 1b. As soon as its 40 impacts and the reruns of those that reached the end wall (on 1.5 m beds,
#     the design's end_wall_rerun_Lx_m, amended on 2026-12-02) are in: the calibration by the plan (the calibration half's
#     target, the six sampled parameters (block.mur_gb is tied to bed.mur_gg, a copy, not an
#     input), the solid-fraction band [0.56, 0.62] measured on the design's own beds, seed 4),
#     then its verification campaign (scripts/verification-campaign.py: every lab state on three
#     beds) on both cores, before the lanes. The calibration runs the tree's program (a minute of
#     analysis; --bed-cache is newer than the campaign's pinned program) under the build lock.
if [ ! -f "$CAL/calibrate-grains.json" ]; then
  # The solid-fraction band needs every design point's packing: the file records the beds built
  # since 2026-12-02 (/dem/beds); the earlier ones (p00-p10, lost with their machines) get theirs
  # from their grain count and the recorded beds of the same geometry (--packing-from-grain-count,
  # amended on 2026-12-02 before the calibration ran, docs/resolved-model.md: it replaces
  # rebuilding them, about 2.5 h of both cores; `dem campaign --record-beds` still does that).
  # shellcheck source=sand-calibration-args.sh
  source scripts/sand-calibration-args.sh
  mkdir -p "$CAL/dem-cache"  # a new machine's cache is empty; the option wants the folder
  flock /tmp/ricochet-build.lock build/cli/ricochet calibrate-grains "$CAL/sand-calibration-1.5e9.h5" \
    "${SAND_CALIBRATION_ARGS[@]}" --bed-cache "$CAL/dem-cache" --decks "$CAL/pinned/liggghts-inputs" \
    --figures "$CAL/figures" --out "$CAL/calibrate-grains.json" > "$CAL/calibrate-grains.txt" 2>&1
  rc=$?
  echo "== $(date '+%F %T') calibrate-grains ended with status $rc" >> "$CAL/campaign.log"
  # Everything of 1b needs the calibration: stop rather than hide its failure behind the lanes.
  if [ ! -f "$CAL/calibrate-grains.json" ]; then
    echo "== $(date '+%F %T') no calibration ($CAL/calibrate-grains.txt): nothing else started" \
      >> "$CAL/campaign.log"
    exit 1
  fi
fi
if [ -f "$CAL/calibrate-grains.json" ]; then
  # 1b'. The active zone's paired check at the calibrated grains (amended on 2026-12-05, before the
  #      calibration ran; the rule is in docs/resolved-model.md, "Active zone"): four lab states on
  #      the verification's first bed, the whole bed against run.active_zone_m = 0.3 m (8 impacts,
  #      about 2.5 h of both cores; the bed it builds is the verification's). The verification and
  #      the force campaign integrate only that zone when the check passed (about 0.55 of an
  #      impact's cost), the whole bed otherwise; the blind triangles, which it does not check,
  #      always run on the whole bed.
  ZONE_VERDICT=$CAL/active-zone-check.json
  if [ ! -f "$ZONE_VERDICT" ]; then
    [ -f "$CAL/sand-zone-check-1.5e9.toml" ] ||
      scripts/verification-campaign.py liggghts-inputs/campaigns/sand-calibration-1.5e9.toml \
        "$CAL/calibrate-grains.json" data/lab/cylinders.csv --beds 3 --bed-length-m 1.5 \
        --zone-check 0.3 --name sand-zone-check-1.5e9 --out "$CAL/sand-zone-check-1.5e9.toml" \
        >> "$CAL/campaign.log" 2>&1
    PLATEAU_DESIGN=sand-zone-check-1.5e9 PLATEAU_DESIGN_PATH="$CAL/sand-zone-check-1.5e9.toml" \
      PLATEAU_OUT=results/sand-verification PLATEAU_FILE=sand-zone-check-1.5e9 PLATEAU_RANKS=2 \
      scripts/stiffness-plateau.sh
    if flock /tmp/ricochet-build.lock scripts/active-zone-verdict.sh results/sand-verification \
        sand-zone-check-1.5e9 "$ROOT/results/sand-verification/sand-zone-check-1.5e9.h5" 0.3 \
        > "$ZONE_VERDICT.tmp" 2>> "$CAL/campaign.log"; then
      mv "$ZONE_VERDICT.tmp" "$ZONE_VERDICT"
      echo "== $(date '+%F %T') the active zone's check: $(jq -c 'del(.statuses)' "$ZONE_VERDICT")" \
        >> "$CAL/campaign.log"
    else
      rm -f "$ZONE_VERDICT.tmp"
      echo "== $(date '+%F %T') the active zone's check has no verdict (see the lines above):" \
        "nothing else started" >> "$CAL/campaign.log"
      exit 1
    fi
  fi
  ZONE_ARGS=()
  ZONE=$(jq -r .active_zone_m "$ZONE_VERDICT")
  [ "$ZONE" != 0 ] && ZONE_ARGS=(--active-zone-m "$ZONE")
  [ -f "$CAL/sand-verification-1.5e9.toml" ] ||
    scripts/verification-campaign.py liggghts-inputs/campaigns/sand-calibration-1.5e9.toml \
      "$CAL/calibrate-grains.json" data/lab/cylinders.csv --beds 3 --bed-length-m 1.5 "${ZONE_ARGS[@]}" \
      --name sand-verification-1.5e9 --out "$CAL/sand-verification-1.5e9.toml" >> "$CAL/campaign.log" 2>&1
  PLATEAU_DESIGN=sand-verification-1.5e9 PLATEAU_DESIGN_PATH="$CAL/sand-verification-1.5e9.toml" \
    PLATEAU_OUT=results/sand-verification PLATEAU_FILE=sand-verification-1.5e9 PLATEAU_RANKS=2 \
    scripts/stiffness-plateau.sh
  # The held-out check as fixed in docs/resolved-model.md (Targets), and the calibration half beside
  # it as in-sample, once the 28 impacts are in (a minute of analysis, the tree's program).
  VER=results/sand-verification/sand-verification-1.5e9.h5
  if campaign_done results/sand-verification sand-verification-1.5e9 sand-verification-1.5e9; then
    # shellcheck source=sand-calibration-args.sh
    source scripts/sand-calibration-args.sh
    for half in held-out calibration; do
      [ -f "results/sand-verification/check-$half.json" ] && continue
      W=$(sand_half "$half")
      flock /tmp/ricochet-build.lock build/cli/ricochet upscale "$VER" --lab data/lab/cylinders.csv \
        --where "$W" --lab-where "$W" --lab-noise 0.1,0.1,3.4 --seed 3202 --json \
        > "results/sand-verification/check-$half.json.tmp" 2>> "$CAL/campaign.log" &&
        mv "results/sand-verification/check-$half.json.tmp" "results/sand-verification/check-$half.json"
      rc=$?
      echo "== $(date '+%F %T') the verification's $half half checked (status $rc)" >> "$CAL/campaign.log"
    done
    [ -f results/sand-verification/check-held-out.json ] &&
      [ -f results/sand-verification/check-calibration.json ] &&
      scripts/verification-table.py held-out=results/sand-verification/check-held-out.json \
        calibration=results/sand-verification/check-calibration.json \
        > results/sand-verification/table.md 2>> "$CAL/campaign.log"
    # The diagnosis fixed on 2026-12-02 for a bed that misses the lab (docs/resolved-model.md,
    # "If no sand-like setting reaches the lab"): the verification's equivalent law over the
    # held-out half, held fixed while each candidate effect fits its own parameters on the lab's
    # held-out half, and beside it the paper's law refitted there. A few minutes of the tree's
    # program, run whatever the check found; the docs read it only as the plan says.
    H=$(sand_half held-out)
    D=results/sand-verification
    if [ ! -f "$D/diagnose-held-out.json" ]; then
      flock /tmp/ricochet-build.lock build/cli/ricochet upscale "$VER" --where "$H" \
          --write-model "$D/bed-law.toml" --json > "$D/upscale-held-out.json" 2>> "$CAL/campaign.log" &&
        flock /tmp/ricochet-build.lock build/cli/ricochet compare data/lab/cylinders.csv --where "$H" \
          --json > "$D/compare-held-out.json" 2>> "$CAL/campaign.log" &&
        flock /tmp/ricochet-build.lock build/cli/ricochet diagnose data/lab/cylinders.csv --where "$H" \
          --model "$D/bed-law.toml" --json > "$D/diagnose-held-out.json.tmp" 2>> "$CAL/campaign.log" &&
        mv "$D/diagnose-held-out.json.tmp" "$D/diagnose-held-out.json"
      rc=$?
      echo "== $(date '+%F %T') the held-out half's diagnosis (status $rc)" >> "$CAL/campaign.log"
    fi
  fi
  # 1c. The blind triangles on the same grains (the verification's first bed, its cache).
  # blind_design NAME [ARGS...]: a design of the blind triangles (verification-campaign.py
  # --blind-triangles on the 1.5 m bed, and ARGS), written once into $CAL/NAME.toml.
  blind_design() {
    local name=$1
    shift
    [ -f "$CAL/$name.toml" ] ||
      scripts/verification-campaign.py liggghts-inputs/campaigns/sand-calibration-1.5e9.toml \
        "$CAL/calibrate-grains.json" data/lab/triangles.csv --blind-triangles --bed-length-m 1.5 \
        "$@" --name "$name" --out "$CAL/$name.toml" >> "$CAL/campaign.log" 2>&1
  }
  # blind_run NAME [ONLY]: design NAME run on both cores into the blind triangles' one file, only
  # its impacts ONLY (comma-separated) when given.
  blind_run() {
    PLATEAU_DESIGN=$1 PLATEAU_DESIGN_PATH="$CAL/$1.toml" PLATEAU_ONLY=${2:-} \
      PLATEAU_OUT=results/sand-verification PLATEAU_FILE=sand-blind-triangles-1.5e9 PLATEAU_RANKS=2 \
      scripts/stiffness-plateau.sh
  }
  # blind_file NAME ARGS...: the pinned program's `dem campaign` of pinned design NAME on the
  # blind triangles' file (a dry run, --only, --forget: ARGS).
  blind_file() {
    local name=$1
    shift
    (cd results/sand-verification && pinned/ricochet dem campaign "pinned/$name.toml" \
      --decks pinned/liggghts-inputs --out sand-blind-triangles-1.5e9.h5 "$@")
  }
  blind_design sand-blind-triangles-1.5e9
  # 1c'. The active zone's check on the triangles (amended on 2026-12-06, when T02 alone had run,
  #      on the whole bed; docs/resolved-model.md, "Active zone", "The check on the triangles"):
  #      the blind design's states in its order on the whole bed (its own impacts, `--only`), T01-T04
  #      first, then two at a time until three of them have rebounded (at most T10), and each of
  #      those states in a 0.30 m zone (the same design under the prefix zone0.3-: the same
  #      orientations); the cylinders' rule (scripts/active-zone-verdict.sh) in the lab triangles'
  #      sd. The other triangles run in the zone when it passes (about half an impact's cost), on
  #      the whole bed otherwise. (The states grew twice on that day, each time before any zone
  #      arm had a result and on the whole bed's statuses alone, never on a zone-whole difference:
  #      T01-T03 became T01-T04 when T01 was seen ploughing towards a timeout, and the batches of
  #      two were added when T01 and T04 timed out, captured by the bed, leaving two rebounds.)
  TRI_VERDICT=$CAL/triangle-zone-check.json
  TRI_DESIGN=sand-blind-triangles-1.5e9
  TRI_STATES=(T01 T02 T03 T04)
  # The rebounds among the whole bed's check states, by the pinned program's dry run.
  tri_rebounds() {
    blind_file sand-blind-triangles-1.5e9 --only "$1" --dry-run --json 2>/dev/null |
      jq '[.impacts[] | select(.status == "rebound")] | length'
  }
  if [ ! -f "$TRI_VERDICT" ]; then
    while :; do
      TRI_WHOLE=$(IFS=,; echo "${TRI_STATES[*]}")
      blind_run sand-blind-triangles-1.5e9 "$TRI_WHOLE"
      rebounds=$(tri_rebounds "$TRI_WHOLE")
      echo "== $(date '+%F %T') the triangles' zone check: ${rebounds:-?} rebounds on the whole bed" \
        "among $TRI_WHOLE" >> "$CAL/campaign.log"
      if [ "${rebounds:-0}" -ge 3 ] || [ "${#TRI_STATES[@]}" -ge 10 ]; then break; fi
      n=${#TRI_STATES[@]}
      TRI_STATES+=("$(printf 'T%02d' $((n + 1)))" "$(printf 'T%02d' $((n + 2)))")
    done
    TRI_ZONE=$(printf 'zone0.3-%s,' "${TRI_STATES[@]}")
    TRI_ZONE=${TRI_ZONE%,}
    blind_design sand-triangle-zone-check-1.5e9 --active-zone-m 0.3 --id-prefix zone0.3-
    blind_run sand-triangle-zone-check-1.5e9 "$TRI_ZONE"
    if ZONE_BASE=T ZONE_BASE_NAME=sand-blind-triangles-1.5e9 ZONE_BASE_ONLY=$TRI_WHOLE \
        ZONE_ONLY=$TRI_ZONE flock /tmp/ricochet-build.lock scripts/active-zone-verdict.sh \
        results/sand-verification sand-triangle-zone-check-1.5e9 \
        "$ROOT/results/sand-verification/sand-blind-triangles-1.5e9.h5" 0.3 > "$TRI_VERDICT.tmp" \
        2>> "$CAL/campaign.log"; then
      mv "$TRI_VERDICT.tmp" "$TRI_VERDICT"
      echo "== $(date '+%F %T') the triangles' active-zone check: $(jq -c 'del(.statuses)' "$TRI_VERDICT")" \
        >> "$CAL/campaign.log"
    else
      rm -f "$TRI_VERDICT.tmp"
      echo "== $(date '+%F %T') the triangles' active-zone check has no verdict (see above):" \
        "the blind triangles go on on the whole bed" >> "$CAL/campaign.log"
    fi
  fi
  if [ -f "$TRI_VERDICT" ] && [ "$(jq -r .active_zone_m "$TRI_VERDICT")" != 0 ]; then
    TRI_DESIGN=sand-blind-triangles-zone-1.5e9
    blind_design "$TRI_DESIGN" --active-zone-m 0.3
  fi
  # The rest of the blind triangles (the ids already in the file, the check's on the whole bed, are
  # skipped: every impact records its own run.active_zone_m).
  blind_run "$TRI_DESIGN"
  # 1c''. The blind triangles' fast states (amended on 2026-12-06, when the driver refused T08
  #       before LIGGGHTS, and before any of them had run; docs/resolved-model.md, "The blind
  #       triangles' fast states"): the lab's four fastest releases (V_in^x 5.31-5.69 m/s) would
  #       start their 25 ms run-up behind the back wall's margin (status invalid). They run with
  #       the free flight shortened to fit (scripts/short-runup-design.py: everything else as the
  #       blind design gives it), under their own ids: each refusal recorded in the file is
  #       forgotten first, so the blind design above, resumed, finds them done.
  RUNUP=sand-blind-triangles-runup-1.5e9
  [ -f "$CAL/$RUNUP.toml" ] ||
    (cd results/sand-verification && "$ROOT/scripts/short-runup-design.py" "$ROOT/build/cli/ricochet" \
      "pinned/$TRI_DESIGN.toml" pinned/liggghts-inputs sand-blind-triangles-1.5e9.h5 \
      --name "$RUNUP" --out "$ROOT/$CAL/$RUNUP.toml") >> "$CAL/campaign.log" 2>&1
  if [ -f "$CAL/$RUNUP.toml" ]; then
    runup_ids=$(grep -oP '^id = "\K[^"]+' "$CAL/$RUNUP.toml" | paste -sd,)
    refused=$(blind_file "$TRI_DESIGN" --only "$runup_ids" --dry-run --json 2>/dev/null |
      jq -r '[.impacts[] | select(.status == "invalid") | .id] | join(",")')
    if [ -n "$refused" ]; then
      echo "== $(date '+%F %T') forgetting the refused $refused to run them with a shorter run-up" \
        >> "$CAL/campaign.log"
      blind_file "$TRI_DESIGN" --forget "$refused" >> "$CAL/campaign.log" 2>&1
    fi
    blind_run "$RUNUP"
  fi
  # 1d. Issue 33's force campaign on the same grains and bed: the speed campaign's 9 states x 3
  #     positions (verification-campaign.py --states-from), tracks kept, for the force-residual
  #     discovery on the plateau bed. Its design is written here; it runs in lane A below, after
  #     the convergence that issue 32 needs.
  [ -f "$CAL/sand-speeds-1.5e9.toml" ] ||
    scripts/verification-campaign.py liggghts-inputs/campaigns/sand-calibration-1.5e9.toml \
      "$CAL/calibrate-grains.json" --bed-length-m 1.5 "${ZONE_ARGS[@]}" \
      --states-from liggghts-inputs/campaigns/speeds-calibrated-long.toml \
      --name sand-speeds-1.5e9 --out "$CAL/sand-speeds-1.5e9.toml" >> "$CAL/campaign.log" 2>&1
fi
# The 1.5e10 Pa level's steps, in their order (since 2026-12-07): the floor check at that level,
# the pre-registered minimum, and the rest of the level. Either lane runs them; a step the other
# lane holds is skipped.
level_minimum() { PLATEAU_DESIGN=stiffness-plateau-1.5e10 PLATEAU_FIRST=75 scripts/stiffness-plateau.sh; }
level_floor() {
  PLATEAU_DESIGN=wall-stiffness-1.5e10 PLATEAU_OUT=results/wall-stiffness-1.5e10 \
    PLATEAU_FILE=wall-stiffness-1.5e10 scripts/stiffness-plateau.sh
}
level_rest() { PLATEAU_DESIGN=stiffness-plateau-1.5e10 scripts/stiffness-plateau.sh; }
{
  PLATEAU_DESIGN=convergence-1.5e9 PLATEAU_OUT=results/convergence-1.5e9 \
    PLATEAU_FILE=convergence-1.5e9 scripts/stiffness-plateau.sh
  [ -f "$CAL/sand-speeds-1.5e9.toml" ] &&
    PLATEAU_DESIGN=sand-speeds-1.5e9 PLATEAU_DESIGN_PATH="$CAL/sand-speeds-1.5e9.toml" \
      PLATEAU_OUT=results/sand-verification PLATEAU_FILE=sand-speeds-1.5e9 \
      scripts/stiffness-plateau.sh
  level_floor
  level_minimum
  level_rest
} &
lane_a=$!
{
  scripts/plateau-drop.sh
  level_floor
  level_minimum
  # Issue 33: the same sphere drops on the calibrated grains, the bed of its force campaign (the
  # Katsuragi-Durian comparison of docs/granular-impact-checks.md, "On the sand-calibrated grains").
  [ -f "$CAL/calibrate-grains.json" ] &&
    DROP_GRAINS_FROM="liggghts-inputs/campaigns/sand-calibration-1.5e9.toml $CAL/calibrate-grains.json" \
      DROP_OUT="$ROOT/results/sand-drop" DROP_FILE=sphere-drop-sand-1.5e9 scripts/plateau-drop.sh
  level_rest
  mkdir -p results/packing-scatter
  scripts/packing-scatter-beds.sh > results/packing-scatter/table.md 2> results/packing-scatter/error.log
} &
lane_b=$!
wait "$lane_a" "$lane_b"
