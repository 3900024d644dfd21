#!/usr/bin/env bash
# Ships the built beds that a running campaign still needs into data/resolved/beds/FILE/, so that
# a session on a new machine resumes without building them again (a 1.5 m bed of the sand
# calibration's reruns is about 92,000 grains and an hour of one core). A bed is the cache's
# LIGGGHTS restart file (compressed with xz) and its parameters file, both byte for byte: the
# campaign started on a new machine finds them in its cache (scripts/stiffness-plateau.sh seeds the
# cache from this folder) and runs the same impacts as on the machine that built them.
#
#   scripts/ship-beds.sh DESIGN.toml RESULTS/FILE.h5 [RICOCHET]
#   e.g. scripts/ship-beds.sh liggghts-inputs/campaigns/sand-calibration-1.5e9.toml \
#          results/sand-calibration/sand-calibration-1.5e9.h5
#
# Which beds: those of the impacts the design's dry run still lists as to run (run in the results
# folder on the campaign's pinned decks, where the design's cache_dir is), which the cache holds
# complete; a shipped bed that no impact needs any more is removed from the folder, and the file
# pinned-in names the results folder whose pinned decks key them (scripts/lanes-status.sh tells
# not to re-pin that folder while they wait). Run it after
# scripts/ship-campaign.sh, so that the dry run sees the shipped impacts. Exit 2 on a missing file,
# 1 when a step fails.
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
if [ $# -lt 2 ]; then
  echo "usage: $0 DESIGN.toml RESULTS/FILE.h5 [RICOCHET]" >&2
  exit 2
fi
DESIGN=$(realpath "$1")
SRC=$(realpath "$2")
BIN=$(realpath "${3:-$ROOT/build/cli/ricochet}")
for f in "$DESIGN" "$SRC" "$BIN"; do
  [ -e "$f" ] || { echo "$0: no such file: $f" >&2; exit 2; }
done
OUT=$(dirname "$SRC")
FILE=$(basename "$SRC" .h5)
DEST=$ROOT/data/resolved/beds/$FILE
DECKS=$OUT/pinned/liggghts-inputs
[ -d "$DECKS" ] || DECKS=$ROOT/liggghts-inputs
dry=$(mktemp)
trap 'rm -f "$dry"' EXIT
(cd "$OUT" && "$BIN" dem campaign "$DESIGN" --decks "$DECKS" --out "$SRC" --dry-run --json \
   2>/dev/null) > "$dry" || { echo "$0: the dry run of $DESIGN failed" >&2; exit 1; }
mkdir -p "$DEST"
python3 - "$dry" "$OUT" "$DEST" <<'PY'
import json, os, subprocess, sys
dry, out, dest = sys.argv[1:]
d = json.load(open(dry))
cache = os.path.join(out, d["cache_dir"])
needed = sorted({p["bed_key"] for p in d["impacts"] if p["status"] is None})
for key in needed:
    src = os.path.join(cache, f"bed-{key}")
    to = os.path.join(dest, f"bed-{key}")
    if os.path.exists(to + ".params"):
        print(f"  bed {key}: shipped already")
        continue
    if not (os.path.exists(src + ".restart") and os.path.exists(src + ".params")):
        print(f"  bed {key}: not built yet")
        continue
    # The parameters file goes last, as in the cache: its presence marks a complete bed.
    with open(to + ".restart.xz.part", "wb") as f:
        subprocess.run(["xz", "-T2", "-6", "-c", src + ".restart"], stdout=f, check=True)
    os.replace(to + ".restart.xz.part", to + ".restart.xz")
    with open(src + ".params", "rb") as f, open(to + ".params", "wb") as g:
        g.write(f.read())
    size = os.path.getsize(to + ".restart.xz") / 1e6
    print(f"  bed {key}: shipped ({size:.1f} MB compressed)")
# Which results folder's pinned decks key these beds (scripts/lanes-status.sh: keep that pin).
with open(os.path.join(dest, "pinned-in"), "w") as f:
    f.write(os.path.basename(os.path.normpath(out)) + "\n")
for name in sorted(os.listdir(dest)):
    if not name.startswith("bed-"):
        continue
    key = name.removeprefix("bed-").split(".")[0]
    if key not in needed:
        os.remove(os.path.join(dest, name))
        print(f"  {name}: no impact needs it any more, removed")
PY
