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

usage() { echo "usage: ./run.sh main|test|build|bench [args]" >&2; exit 2; }
[ $# -ge 1 ] || usage
what=$1; shift

install_missing() {
  local missing=()
  while read -r pkg; do
    [[ -z "$pkg" || "$pkg" == \#* ]] && continue
    dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null | grep -q "install ok installed" || missing+=("$pkg")
  done < scripts/packages.txt
  if [ ${#missing[@]} -gt 0 ]; then
    echo "run.sh: installing ${missing[*]}" >&2
    local sudo=""
    [ "$(id -u)" -eq 0 ] || sudo=sudo
    $sudo apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >&2
  fi
}

# build [TARGET...]: every target, or only those named (the main job needs only the program:
# not the tests, benchmarks and fuzz targets, about half the build; issue 34).
build() {
  if [ ! -f "$BUILD/CMakeCache.txt" ]; then
    cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release >&2
  fi
  local targets=()
  for t in "$@"; do targets+=(--target "$t"); done
  cmake --build "$BUILD" -j "$JOBS" "${targets[@]}" >&2
}

case "$what" in
  build) install_missing; build ;;
  main)
    install_missing; build ricochet
    exec "$ROOT/scripts/main-job.sh" "$BUILD" "$@"
    ;;
  test)
    install_missing; build
    "$ROOT/scripts/main-job.sh" "$BUILD" --quick
    cd "$BUILD"
    exec ctest --no-tests=error --output-on-failure -j "$JOBS" "$@"
    ;;
  bench)
    install_missing; build
    exec "$ROOT/scripts/bench.sh" "$BUILD" "$@"
    ;;
  *) usage ;;
esac
