#!/usr/bin/env bash
# The no-LIGGGHTS configuration (issue 12: "a CI job builds the no-LIGGGHTS configuration"): a
# fresh tree configured with -DRICOCHET_WITH_LIGGGHTS=OFF (benchmarks and fuzz targets off), its
# program built, and the CLI contract run against it. The resolved model's subcommands must say
# how to get LIGGGHTS (docs/building.md, "Without LIGGGHTS").
# Only the program and the CLI tests are built and run here: LIGGGHTS changes nothing else. The
# libraries compile the same sources with the same flags in both configurations (only cli/ and
# tests/cli/ read RICOCHET_HAVE_LIGGGHTS), and the main tree's ctest already runs every library
# test; building and running them all again cost CI 10 of its minutes (issue 34).
#   usage: scripts/ci-nodeps.sh [BUILD_DIR]      (default build-nodeps; .ci/run calls it)
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$(pwd)
BUILD=${1:-$ROOT/build-nodeps}
JOBS=${RICOCHET_JOBS:-$(nproc)}
if [ ! -f "$BUILD/CMakeCache.txt" ]; then
  cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release -DRICOCHET_WITH_LIGGGHTS=OFF \
    -DRICOCHET_BUILD_BENCHMARKS=OFF -DRICOCHET_BUILD_FUZZ=OFF >&2
fi
grep -q '^RICOCHET_WITH_LIGGGHTS:[A-Z]*=OFF' "$BUILD/CMakeCache.txt" ||
  { echo "ci-nodeps: $BUILD is not a no-LIGGGHTS tree" >&2; exit 2; }
cmake --build "$BUILD" -j "$JOBS" --target ricochet ricochet_cli_tests >&2
"$BUILD/cli/ricochet" --help | grep -q "no LIGGGHTS" ||
  { echo "ci-nodeps: the program of $BUILD does not say it has no LIGGGHTS" >&2; exit 1; }
# The CLI tests' suites, as ctest knows them (two at a time, as on the main tree).
suites=$("$BUILD/tests/cli/ricochet_cli_tests" --gtest_list_tests |
  sed -n 's/^\([A-Za-z0-9_/]*\)\..*/\1/p' | sort -u | paste -sd'|')
cd "$BUILD"
exec ctest --no-tests=error --output-on-failure -j "$JOBS" -R "^($suites)\."
