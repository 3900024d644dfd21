#!/usr/bin/env bash
# The no-LIGGGHTS configuration (issue 12: "a CI job builds the no-LIGGGHTS configuration"): a
# fresh tree configured with -DRICOCHET_WITH_LIGGGHTS=OFF (benchmarks and fuzz targets off), its
# program built, and the CLI contract run against it. The resolved model's subcommands must say
# how to get LIGGGHTS (docs/building.md, "Without LIGGGHTS").
# Only the program is built there, and the CLI contract (tests/cli: bad options, good exits) of
# the main tree is run against it (RICOCHET_TEST_EXE, as the main tree's nodeps.cli does with its
# own no-LIGGGHTS link): LIGGGHTS changes nothing else. The libraries compile the same sources
# with the same flags in both configurations (only cli/ and tests/cli/ read
# RICOCHET_HAVE_LIGGGHTS), and the main tree's ctest runs every library test; building and running
# them all again cost CI 10 of its minutes (issue 34).
#   usage: scripts/ci-nodeps.sh [NODEPS_DIR [MAIN_BUILD_DIR]]   (default build-nodeps, build;
#          .ci/run calls it after ./run.sh test has built and tested the main tree)
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$(pwd)
BUILD=${1:-$ROOT/build-nodeps}
MAIN=${2:-${RICOCHET_BUILD_DIR:-$ROOT/build}}
JOBS=${RICOCHET_JOBS:-$(nproc)}
if [ ! -f "$BUILD/CMakeCache.txt" ]; then
  cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release -DRICOCHET_WITH_LIGGGHTS=OFF \
    -DRICOCHET_BUILD_BENCHMARKS=OFF -DRICOCHET_BUILD_FUZZ=OFF >&2
fi
grep -q '^RICOCHET_WITH_LIGGGHTS:[A-Z]*=OFF' "$BUILD/CMakeCache.txt" ||
  { echo "ci-nodeps: $BUILD is not a no-LIGGGHTS tree" >&2; exit 2; }
cmake --build "$BUILD" -j "$JOBS" --target ricochet >&2
"$BUILD/cli/ricochet" --help | grep -q "no LIGGGHTS" ||
  { echo "ci-nodeps: the program of $BUILD does not say it has no LIGGGHTS" >&2; exit 1; }
[ -x "$MAIN/tests/cli/ricochet_cli_tests" ] ||
  { echo "ci-nodeps: no CLI tests in $MAIN (run ./run.sh test first)" >&2; exit 2; }
# The CLI contract's suites (every subcommand's bad options exit 2 naming the option; help,
# version, JSON stamp; the resolved model's subcommands say how to get LIGGGHTS), as the main
# tree's ctest knows them, two at a time: the main tree's nodeps.cli runs the same suites against
# its own no-LIGGGHTS link. The rest of tests/cli checks what the libraries compute, which the
# no-LIGGGHTS tree compiles from the same sources with the same flags (with ccache, the same
# objects); running all 138 of them against this program cost CI 87 s (2026-12-02) and exercised
# the same library code again.
cd "$MAIN"
RICOCHET_TEST_EXE="$BUILD/cli/ricochet" RICOCHET_TEST_HAVE_LIGGGHTS=0 \
  exec ctest --no-tests=error --output-on-failure -j "$JOBS" \
  -R "^(EverySubcommand/)?(BadOptions|GoodExits)\."
