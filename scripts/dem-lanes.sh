#!/usr/bin/env bash
# Issue 32's background campaigns on this 2-core machine, one rank per lane, each resumable (a
# finished step returns at once, an interrupted one resumes from its file):
#   lane A: the stiffness plateau's 1.5e10 Pa level (scripts/stiffness-plateau.sh), then the floor
#           check at that level (liggghts-inputs/campaigns/wall-stiffness-1.5e10.toml, into
#           results/wall-stiffness-1.5e10/), then the convergence at 1.5e9 Pa (width, depth, grain
#           size: liggghts-inputs/campaigns/convergence-1.5e9.toml, into results/convergence-1.5e9/);
#   lane B: the sphere drop on the 1.5e9 Pa bed (scripts/plateau-drop.sh), then the sand-only
#           recalibration at 1.5e9 Pa (liggghts-inputs/campaigns/sand-calibration-1.5e9.toml,
#           into results/sand-calibration/, the plan of docs/resolved-model.md).
# Start it at the beginning of a session and let it run; a session's end stops it, the next
# start resumes it:
#
#   nohup setsid scripts/dem-lanes.sh > /dev/null 2>&1 &
#   tail results/plateau/campaign.log results/plateau-drop/drop.log \
#        results/sand-calibration/campaign.log results/wall-stiffness-1.5e10/campaign.log
set -uo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
cd "$ROOT" || exit 1
{
  # The plateau campaign may already run (started by hand): wait for its lock, then let the
  # script return at once or resume what is left.
  mkdir -p results/plateau
  flock results/plateau/campaign.lock true
  PLATEAU_DESIGN=stiffness-plateau-1.5e10 scripts/stiffness-plateau.sh
  PLATEAU_DESIGN=wall-stiffness-1.5e10 PLATEAU_OUT=results/wall-stiffness-1.5e10 \
    PLATEAU_FILE=wall-stiffness-1.5e10 scripts/stiffness-plateau.sh
  PLATEAU_DESIGN=convergence-1.5e9 PLATEAU_OUT=results/convergence-1.5e9 \
    PLATEAU_FILE=convergence-1.5e9 scripts/stiffness-plateau.sh
} &
lane_a=$!
{
  # A drop already running (started by hand) holds its lock: wait for it, then run the script,
  # which returns at once when every drop is in. The calibration does not need the drop.
  mkdir -p results/plateau-drop
  flock results/plateau-drop/drop.lock true
  scripts/plateau-drop.sh
  PLATEAU_DESIGN=sand-calibration-1.5e9 PLATEAU_OUT=results/sand-calibration \
      PLATEAU_FILE=sand-calibration-1.5e9 scripts/stiffness-plateau.sh
} &
lane_b=$!
wait "$lane_a" "$lane_b"
