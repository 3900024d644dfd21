# shellcheck shell=bash
# Sourced by the detection studies (scripts/*-study.sh, power-calibration.sh) with their
# arguments BUILD_DIR OUT_DIR: the programs they run and where they write.
#   R  the built `ricochet`;  T  the independent simulator (tests/detection/truth_sim.hpp);
#   OUT/sets  the sets and their diagnoses;  PYTHONPATH  scripts/ (study_stats.py).
set -euo pipefail
[ $# -ge 2 ] || { echo "usage: $0 BUILD_DIR OUT_DIR" >&2; exit 2; }
BUILD=$(cd "$1" && pwd)
OUT=$2
# shellcheck disable=SC2034  # R and T are the sourcing study's
R="$BUILD/cli/ricochet"
# shellcheck disable=SC2034
T="$BUILD/tests/detection/independent_truth"
mkdir -p "$OUT/sets"
SCRIPTS_DIR=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
export PYTHONPATH="$SCRIPTS_DIR${PYTHONPATH:+:$PYTHONPATH}"
