#!/usr/bin/env bash
# Ricochet's two entry points (see README.md):
#   ./run.sh main   install what is missing (apt), build, run the main job on the embedded data
#   ./run.sh test   the same, then run every test through ctest
# Both are idempotent: packages already installed and an up-to-date build cost a few seconds.
set -euo pipefail
cd "$(dirname "$0")"
ROOT=$(pwd)
BUILD=${RICOCHET_BUILD_DIR:-$ROOT/build}
JOBS=${RICOCHET_JOBS:-$(nproc)}

usage() { echo "usage: ./run.sh main|test|build [TARGET...]|bench [args]" >&2; exit 2; }
[ $# -ge 1 ] || usage
what=$1; shift

# install_missing LIST...: the Debian packages of the lists (scripts/packages*.txt) not yet
# installed. `main` needs only scripts/packages.txt (the program and its job); `test` and `bench`
# add scripts/packages-test.txt (GoogleTest, Google Benchmark, clang for the fuzz target, Chromium
# for the report's reading test, perf): about half of a fresh machine's download (issue 34).
install_missing() {
  local missing=() list pkg
  for list in "$@"; do
    while read -r pkg; do
      [[ -z "$pkg" || "$pkg" == \#* ]] && continue
      dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null | grep -q "install ok installed" || missing+=("$pkg")
    done < "$list"
  done
  if [ ${#missing[@]} -gt 0 ]; then
    echo "run.sh: installing ${missing[*]}" >&2
    local sudo=""
    [ "$(id -u)" -eq 0 ] || sudo=sudo
    $sudo apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >&2
  fi
}
MAIN_PACKAGES=(scripts/packages.txt)
ALL_PACKAGES=(scripts/packages.txt scripts/packages-test.txt)

# build WITH_TESTS [TARGET...]: configure (tests, benchmarks and fuzz targets ON or OFF: `main`
# configures without them, so that it needs neither their packages nor their build; `test` turns
# them on in the same tree), then build every target, or only those named.
build() {
  local with_tests=$1; shift
  if [ ! -f "$BUILD/CMakeCache.txt" ]; then
    cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release -DRICOCHET_BUILD_TESTS="$with_tests" \
      -DRICOCHET_BUILD_BENCHMARKS="$with_tests" -DRICOCHET_BUILD_FUZZ="$with_tests" >&2
  elif [ "$with_tests" = ON ] && ! grep -q '^RICOCHET_BUILD_TESTS:BOOL=ON' "$BUILD/CMakeCache.txt"; then
    cmake -S "$ROOT" -B "$BUILD" -DRICOCHET_BUILD_TESTS=ON -DRICOCHET_BUILD_BENCHMARKS=ON \
      -DRICOCHET_BUILD_FUZZ=ON >&2
  fi
  local targets=()
  for t in "$@"; do targets+=(--target "$t"); done
  cmake --build "$BUILD" -j "$JOBS" "${targets[@]}" >&2
}

case "$what" in
  # build [TARGET...]: every package and target, or only the targets named (e.g. `ricochet`, so
  # that a background campaign starts on a new machine before the tests are compiled).
  build) install_missing "${ALL_PACKAGES[@]}"; build ON "$@" ;;
  main)
    install_missing "${MAIN_PACKAGES[@]}"; build OFF ricochet
    exec "$ROOT/scripts/main-job.sh" "$BUILD" "$@"
    ;;
  test)
    install_missing "${ALL_PACKAGES[@]}"; build ON
    "$ROOT/scripts/main-job.sh" "$BUILD" --quick
    cd "$BUILD"
    exec ctest --no-tests=error --output-on-failure -j "$JOBS" "$@"
    ;;
  bench)
    install_missing "${ALL_PACKAGES[@]}"; build ON
    exec "$ROOT/scripts/bench.sh" "$BUILD" "$@"
    ;;
  *) usage ;;
esac
