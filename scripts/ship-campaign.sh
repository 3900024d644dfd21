#!/usr/bin/env bash
# Ships a running campaign's file into data/resolved/ and prints the numbers that the shipped-data
# test, the README row of data/resolved/ and the campaign's status line quote: the impacts in the
# file by status, the rebounds in its impact set (`ricochet stats`), and what the design's dry run
# still lists. The copy is taken under the campaign file's shared lock (campaign_store.cpp writes
# under an exclusive one), so a running campaign can be shipped at any moment.
#
#   scripts/ship-campaign.sh DESIGN.toml RESULTS/FILE.h5 [RICOCHET]
#   e.g. scripts/ship-campaign.sh liggghts-inputs/campaigns/sand-calibration-1.5e9.toml \
#          results/sand-calibration/sand-calibration-1.5e9.h5
#
# Writes data/resolved/FILE.h5 (same name), unless that file already holds the same impacts;
# exit 2 on a missing file, 1 when a step fails. Then
# scripts/ship-beds.sh (same arguments) ships the built beds that the impacts still to run need.
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
if [ $# -lt 2 ]; then
  echo "usage: $0 DESIGN.toml RESULTS/FILE.h5 [RICOCHET]" >&2
  exit 2
fi
DESIGN=$1
SRC=$2
BIN=${3:-$ROOT/build/cli/ricochet}
for f in "$DESIGN" "$SRC" "$BIN"; do
  [ -e "$f" ] || { echo "$0: no such file: $f" >&2; exit 2; }
done
DEST=$ROOT/data/resolved/$(basename "$SRC")
tmp=$(mktemp "$DEST.XXXX")
trap 'rm -f "$tmp" "$tmp.dry" "$tmp.stats"' EXIT
flock -s "$SRC.lock" cp "$SRC" "$tmp"
# A campaign whose impacts are as shipped (the same /dem/index: ids, statuses, messages, values)
# keeps its shipped file: the copy would differ only in HDF5 bytes or provenance strings. The
# index is compared as h5dump prints it (its first line names the file): h5diff exits 0 for
# datasets of different lengths ("not comparable"), and so kept a shipped file one impact
# short on 2026-12-07, until this compared the text.
index_text() { h5dump -g /dem/index "$1" 2> /dev/null | tail -n +2; }
shipped_index=""
if [ -f "$DEST" ]; then shipped_index=$(index_text "$DEST" || true); fi
if [ -n "$shipped_index" ] && [ "$(index_text "$tmp")" = "$shipped_index" ]; then
  rm -f "$tmp"
  echo "$SRC: its impacts are as shipped in ${DEST#"$ROOT"/}: file left as it is"
else
  mv "$tmp" "$DEST"
  echo "shipped $SRC -> ${DEST#"$ROOT"/}"
fi
"$BIN" dem campaign "$DESIGN" --out "$DEST" --dry-run --json 2>/dev/null > "$tmp.dry" || {
  echo "$0: the dry run of $DESIGN on $DEST failed" >&2
  exit 1
}
"$BIN" stats "$DEST" --json > "$tmp.stats" || { echo "$0: ricochet stats $DEST failed" >&2; exit 1; }
python3 - "$tmp.dry" "$tmp.stats" <<'PY'
import collections, json, sys
dry, stats = sys.argv[1:]
d = json.load(open(dry))
s = json.load(open(stats))
status = collections.Counter()
for row in d.get("impacts", []):
    status[row.get("status") or "not run"] += 1
print(f"  impacts of the design (reruns known so far included): {len(d['impacts'])} on {d['beds']} beds")
print("  by status in the file: " + ", ".join(f"{k} {v}" for k, v in sorted(status.items())))
print(f"  impact set: {s['n']} rebounds (ricochet stats)")
print(f"  still to run: {d['to_run']} impacts, {d['beds_to_build']} beds to build")
PY
