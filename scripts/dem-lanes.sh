#!/usr/bin/env bash
# Issue 32's background campaigns on this 2-core machine, each resumable (a finished step returns
# at once, an interrupted one resumes from its file), in the order of what the issue needs most:
#   1. the sand-only recalibration at 1.5e9 Pa on both cores (two impacts at a time;
#      liggghts-inputs/campaigns/sand-calibration-1.5e9.toml into results/sand-calibration/, the
#      plan of docs/resolved-model.md): everything after it (the held-out check, the blind
#      triangles and the main job on the calibrated bed) waits for it;
#   2. then two lanes of one core each:
#      lane A: the stiffness plateau's 1.5e10 Pa level up to its pre-registered minimum (the
#              cylinder and the triangle states T18, T02, T10: the design's first 75 impacts,
#              12 pairs), the floor check at that level (wall-stiffness-1.5e10.toml, into
#              results/wall-stiffness-1.5e10/), the convergence at 1.5e9 Pa (width, depth, grain
#              size: convergence-1.5e9.toml, into results/convergence-1.5e9/), then the level's
#              other three triangle states;
#      lane B: the sphere drop on the 1.5e9 Pa box bed (scripts/plateau-drop.sh).
# Start it at the beginning of a session and let it run; a session's end stops it, the next
# start resumes it:
#
#   nohup setsid scripts/dem-lanes.sh > /dev/null 2>&1 &
#   tail results/sand-calibration/campaign.log results/plateau/campaign.log \
#        results/plateau-drop/drop.log
set -uo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
cd "$ROOT" || exit 1
# Runs started by hand hold their locks: wait for them before taking both cores.
mkdir -p results/plateau results/plateau-drop
flock results/plateau/campaign.lock true
flock results/plateau-drop/drop.lock true
PLATEAU_DESIGN=sand-calibration-1.5e9 PLATEAU_OUT=results/sand-calibration \
  PLATEAU_FILE=sand-calibration-1.5e9 PLATEAU_RANKS=2 scripts/stiffness-plateau.sh
{
  PLATEAU_DESIGN=stiffness-plateau-1.5e10 PLATEAU_FIRST=75 scripts/stiffness-plateau.sh
  PLATEAU_DESIGN=wall-stiffness-1.5e10 PLATEAU_OUT=results/wall-stiffness-1.5e10 \
    PLATEAU_FILE=wall-stiffness-1.5e10 scripts/stiffness-plateau.sh
  PLATEAU_DESIGN=convergence-1.5e9 PLATEAU_OUT=results/convergence-1.5e9 \
    PLATEAU_FILE=convergence-1.5e9 scripts/stiffness-plateau.sh
  PLATEAU_DESIGN=stiffness-plateau-1.5e10 scripts/stiffness-plateau.sh
} &
lane_a=$!
scripts/plateau-drop.sh &
lane_b=$!
wait "$lane_a" "$lane_b"
