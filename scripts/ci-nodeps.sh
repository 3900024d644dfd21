#!/usr/bin/env bash
# The no-LIGGGHTS configuration (issue 12: "a CI job builds the no-LIGGGHTS configuration"): a
# fresh tree configured with -DRICOCHET_WITH_LIGGGHTS=OFF (benchmarks and fuzz targets off), its
# program built, and the CLI contract run against it. The resolved model's subcommands must say
# how to get LIGGGHTS (docs/building.md, "Without LIGGGHTS").
# Only the program is built there, and the CLI contract (tests/cli) of the main tree is run
# against it (RICOCHET_TEST_EXE, as the main tree's nodeps.cli does with its own no-LIGGGHTS
# link): LIGGGHTS changes nothing else. The libraries compile the same sources with the same
# flags in both configurations (only cli/ and tests/cli/ read RICOCHET_HAVE_LIGGGHTS), and the
# main tree's ctest runs every library test; building and running them all again cost CI 10 of
# its minutes (issue 34). The one CLI test that needs the LIGGGHTS libraries' option structs
# (OptionDefaults.ResolvedModelCommandsShowTheirLibraryDefaults) is left out.
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
# The CLI tests' suites, as the main tree's ctest knows them (two at a time).
suites=$("$MAIN/tests/cli/ricochet_cli_tests" --gtest_list_tests |
  sed -n 's/^\([A-Za-z0-9_/]*\)\..*/\1/p' | sort -u | paste -sd'|')
cd "$MAIN"
RICOCHET_TEST_EXE="$BUILD/cli/ricochet" RICOCHET_TEST_HAVE_LIGGGHTS=0 \
  exec ctest --no-tests=error --output-on-failure -j "$JOBS" -R "^($suites)\." \
  -E "ResolvedModelCommandsShowTheirLibraryDefaults"
