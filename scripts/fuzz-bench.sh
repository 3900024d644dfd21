#!/usr/bin/env bash
# The fuzz bench (issue 12): each libFuzzer target for RUNS inputs (default 1,000,000) from its
# seed corpus, one target at a time, printing inputs, exec/s, wall time and findings as a
# Markdown table (fuzz/README.md, "Results").
#   usage: scripts/fuzz-bench.sh BUILD_DIR [RUNS] [TARGET...]     (also: ./run.sh bench fuzz)
# The seed corpora stay read-only: each run works on a copy in a temporary folder, which also
# receives the reproducers of any finding (crash-*, leak-*, timeout-*, oom-*), kept and listed.
set -euo pipefail
BUILD=$(cd "$1" && pwd)
RUNS=${2:-1000000}
shift $(($# < 2 ? $# : 2))
ROOT=$(cd "$(dirname "$0")/.." && pwd)
TARGETS=("$@")
[ ${#TARGETS[@]} -gt 0 ] ||
  TARGETS=(impact_csv impact_h5 impact_h5_schema model_toml shape_toml campaign_toml track_csv where)
WORK=$(mktemp -d "${TMPDIR:-/tmp}/ricochet-fuzz-bench.XXXXXX")
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1

echo "fuzz bench: $RUNS inputs per target, $(nproc) cores, $(date -u +%F), work dir $WORK"
echo
echo "| target | inputs | exec/s | wall time | coverage edges | findings (Ricochet) |"
echo "|---|---:|---:|---:|---:|---:|"
total_findings=0
for t in "${TARGETS[@]}"; do
  exe=$BUILD/fuzz/fuzz_$t
  if [ ! -x "$exe" ]; then
    echo "| $t | not built | | | | |"
    continue
  fi
  mkdir -p "$WORK/$t/corpus" "$WORK/$t/artifacts" "$WORK/$t/tmp"
  # fuzz_impact_h5 writes each input there; a crashed input's file goes with the folder below.
  export RICOCHET_FUZZ_TMPDIR=$WORK/$t/tmp
  flags=
  if [ "$t" = impact_h5 ]; then
    # HDF5 1.10.8 crashes, loops or runs out of memory on damaged variable-length strings
    # (fuzz/README.md, "HDF5 findings"): fork mode records those inputs and goes on, for at most
    # H5_SECONDS; every reproducer is triaged below (HDF5 frame on top, or Ricochet code).
    flags="-fork=1 -ignore_crashes=1 -ignore_ooms=1 -ignore_timeouts=1 -max_total_time=${H5_SECONDS:-600}"
  fi
  start=$(date +%s.%N)
  status=0
  # shellcheck disable=SC2086
  "$exe" -runs="$RUNS" -seed=1 -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 $flags \
    -dict="$ROOT/fuzz/$t.dict" -artifact_prefix="$WORK/$t/artifacts/" \
    "$WORK/$t/corpus" "$ROOT/fuzz/corpus-$t" >"$WORK/$t/log.txt" 2>&1 || status=$?
  end=$(date +%s.%N)
  runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$WORK/$t/log.txt" | tail -1)
  speed=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$WORK/$t/log.txt" | tail -1)
  edges=$(grep -o 'cov: [0-9]*' "$WORK/$t/log.txt" | tail -1 | cut -d' ' -f2)
  findings=0
  hdf5=0
  for a in "$WORK/$t"/artifacts/*; do
    [ -f "$a" ] || continue
    # Replay: an HDF5 finding has a frame of libhdf5 above the first frame of Ricochet code.
    first=$("$exe" -timeout=10 -rss_limit_mb=2048 "$a" 2>&1 |
      grep -m1 -oE 'libhdf5[^ ]*|calibration/[a-z_/0-9]+\.[ch]pp|fuzz/fuzz_[a-z_0-9]+\.[ch]pp' || true)
    if [ "$t" = impact_h5 ] && [[ "$first" == libhdf5* ]]; then
      hdf5=$((hdf5 + 1))
    else
      findings=$((findings + 1))
    fi
  done
  if [ "$t" = impact_h5 ]; then
    # Fork mode: the last status line counts every job's inputs.
    line=$(grep -E '^#[0-9]+: cov:' "$WORK/$t/log.txt" | tail -1)
    runs=$(sed -E 's/^#([0-9]+):.*/\1/' <<<"$line")
    wall_s=$(sed -E 's/.* time: ([0-9]+)s.*/\1/' <<<"$line")
    speed=$((runs / (wall_s > 0 ? wall_s : 1)))
    echo "impact_h5: $(sed -E 's/.*(oom\/timeout\/crash: [0-9\/]+).*/\1/' <<<"$line") in HDF5 or" \
      "Ricochet; $hdf5 reproducer(s) stop in libhdf5 (HDF5 findings), $findings in Ricochet" >&2
  elif [ "$status" -ne 0 ] && [ "$findings" -eq 0 ]; then
    findings=1 # failed without a reproducer file
  fi
  total_findings=$((total_findings + findings))
  rm -rf "$WORK/$t/tmp"
  wall=$(python3 -c "import sys; s=float(sys.argv[2])-float(sys.argv[1]); print(f'{s:.0f} s')" \
    "$start" "$end")
  printf '| %s | %s | %s | %s | %s | %s |\n' "$t" "$(printf "%'d" "${runs:-0}")" \
    "$(printf "%'d" "${speed:-0}")" "$wall" "${edges:-?}" "$findings"
done
echo
if [ "$total_findings" -eq 0 ]; then
  echo "no findings; logs in $WORK"
else
  echo "$total_findings finding(s): reproducers and logs in $WORK/*/artifacts, $WORK/*/log.txt"
  exit 1
fi
