#!/usr/bin/env bash
# The no-LIGGGHTS configuration, built and tested whole (issue 12: "a CI job builds the
# no-LIGGGHTS configuration"): a fresh tree configured with -DRICOCHET_WITH_LIGGGHTS=OFF (the
# benchmarks and fuzz targets off: they do not depend on it), built, and its ctest run. The
# resolved model's tests are not registered there; its subcommands must say how to get LIGGGHTS
# (docs/building.md, "Without LIGGGHTS").
#   usage: scripts/ci-nodeps.sh [BUILD_DIR]      (default build-nodeps; .ci/run calls it)
# Cost on the 2-core machine: about 7 min to build, 3 min of tests.
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
cmake --build "$BUILD" -j "$JOBS" >&2
"$BUILD/cli/ricochet" --help | grep -q "no LIGGGHTS" ||
  { echo "ci-nodeps: the program of $BUILD does not say it has no LIGGGHTS" >&2; exit 1; }
cd "$BUILD"
exec ctest --no-tests=error --output-on-failure -j "$JOBS"
