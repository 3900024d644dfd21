#!/usr/bin/env bash
# Ships the built beds that a running campaign still needs into data/resolved/beds/FILE/, so that
# a session on a new machine resumes without building them again (a 1.5 m bed of the sand
# calibration's reruns is about 92,000 grains and an hour of one core). A bed is the cache's
# LIGGGHTS restart file (compressed with xz) and its parameters file, both byte for byte: the
# campaign started on a new machine finds them in its cache (scripts/stiffness-plateau.sh seeds the
# cache from this folder) and runs the same impacts as on the machine that built them.
# What is in flight goes too, since every session gets a new machine and a stiff bed's build
# (1.5-2 h) and impact (up to 1.5 h) together outlast a session: the latest checkpoint of a bed
# being built (bed-KEY.building.ckpt-PHASE-CHUNK-SETTLED.restart.xz, which ensure_bed resumes) and
# of an impact being run (impact-ID.gen-G.tar.xz: its work folder's checkpoint.json, restart and
# track, which run_impact resumes bit for bit); each is replaced by the next one shipped and
# removed once its bed or impact is done. Run it at the end of a session, lanes running
# (scripts/ship-session.sh does, for every campaign); scripts/seed-shipped.sh puts them back.
#
#   scripts/ship-beds.sh DESIGN.toml RESULTS/FILE.h5 [RICOCHET]
#   e.g. scripts/ship-beds.sh liggghts-inputs/campaigns/sand-calibration-1.5e9.toml \
#          results/sand-calibration/sand-calibration-1.5e9.h5
#
# Which beds: those of the impacts the design's dry run still lists as to run (run in the results
# folder on the campaign's pinned decks, where the design's cache_dir is), which the cache holds
# complete; a shipped bed that no impact needs any more is removed from the folder, and the file
# pinned-in names the results folder whose pinned decks key them (scripts/lanes-status.sh tells
# not to re-pin that folder while they wait), and pinned-decks.tar.xz holds those decks
# (scripts/pack-decks.py), which a new machine pins for that folder (scripts/pin-program.sh). Run
# it after
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
python3 - "$dry" "$OUT" "$DEST" "$ROOT/scripts/pack-decks.py" "$DECKS" <<'PY'
import json, os, re, shutil, subprocess, sys, tarfile, tempfile
dry, out, dest, pack_decks, decks = sys.argv[1:]
d = json.load(open(dry))
cache = os.path.join(out, d["cache_dir"])
to_run = [p for p in d["impacts"] if p["status"] is None]
needed = sorted({p["bed_key"] for p in to_run})
ids = {p["id"] for p in to_run}


def xz_to(src, to):
    """src compressed into `to` through a .part name: a copy cut short is never taken for one."""
    with open(to + ".part", "wb") as f:
        subprocess.run(["xz", "-T2", "-6", "-c", src], stdout=f, check=True)
    os.replace(to + ".part", to)
    return os.path.getsize(to) / 1e6


def remove_shipped(pattern, keep=None):
    for name in sorted(os.listdir(dest)):
        if re.fullmatch(pattern, name) and name != keep:
            os.remove(os.path.join(dest, name))


# A build's checkpoint, src-ext/bed.hpp: bed-KEY.building.ckpt-PHASE-CHUNK-SETTLED.restart.
CKPT = re.compile(r"bed-([0-9a-f]+)\.building\.ckpt-(\d+)-(\d+)-(\d+)\.restart")


def latest_checkpoint(key):
    best = None
    for name in os.listdir(cache) if os.path.isdir(cache) else []:
        m = CKPT.fullmatch(name)
        if m and m.group(1) == key:
            state = (int(m.group(2)), int(m.group(3)))
            if best is None or state > best[0]:
                best = (state, name)
    return best


for key in needed:
    src = os.path.join(cache, f"bed-{key}")
    to = os.path.join(dest, f"bed-{key}")
    ckpts = rf"bed-{key}\.building\.ckpt-.*\.restart\.xz"
    if os.path.exists(to + ".params"):
        print(f"  bed {key}: shipped already")
        remove_shipped(ckpts)
        continue
    if os.path.exists(src + ".restart") and os.path.exists(src + ".params"):
        # The parameters file goes last, as in the cache: its presence marks a complete bed.
        size = xz_to(src + ".restart", to + ".restart.xz")
        shutil.copyfile(src + ".params", to + ".params")
        remove_shipped(ckpts)
        print(f"  bed {key}: shipped ({size:.1f} MB compressed)")
        continue
    # A build in flight: its latest checkpoint, so that a new machine resumes it there
    # (ensure_bed takes the latest checkpoint of the cache). A hard link holds the file while
    # the build goes on and removes it for the next one.
    latest = latest_checkpoint(key)
    if latest is None:
        print(f"  bed {key}: not built yet")
        continue
    (phase, chunk), name = latest
    if os.path.exists(os.path.join(dest, name + ".xz")):
        print(f"  bed {key}: its build's checkpoint (phase {phase}, chunk {chunk}) shipped already")
        continue
    with tempfile.TemporaryDirectory(dir=out) as tmp:
        held = os.path.join(tmp, name)
        os.link(os.path.join(cache, name), held)
        size = xz_to(held, os.path.join(dest, name + ".xz"))
    remove_shipped(ckpts, keep=name + ".xz")
    print(f"  bed {key}: its build in flight, checkpoint phase {phase}, chunk {chunk} shipped"
          f" ({size:.1f} MB compressed)")

# Impacts in flight (src-ext/impact_checkpoint.hpp): WORK/checkpoint.json, the restart of its
# generation and the track so far, as impact-ID.gen-G.tar.xz with their paths from the results
# folder, checkpoint.json last (it is what makes a checkpoint current).
IMPACT = re.compile(r"impact-(.+)\.gen-(\d+)\.tar\.xz")
for work, dirs, files in os.walk(out):
    dirs[:] = [x for x in dirs if x not in ("pinned", d["cache_dir"])]
    iid = os.path.basename(work)
    if "checkpoint.json" not in files or iid not in ids:
        continue
    for attempt in range(5):  # a new generation may be committed while this one is read
        with open(os.path.join(work, "checkpoint.json"), "rb") as f:
            text = f.read()
        gen = json.loads(text)["generation"]
        name = f"impact-{iid}.gen-{gen}.tar.xz"
        if os.path.exists(os.path.join(dest, name)):
            print(f"  impact {iid}: its checkpoint (generation {gen}) shipped already")
            break
        with tempfile.TemporaryDirectory(dir=out) as tmp:
            try:
                os.link(os.path.join(work, f"checkpoint-{gen}.restart"), os.path.join(tmp, "r"))
            except FileNotFoundError:
                continue
            # The track grows only: a copy taken after the checkpoint holds its track_bytes.
            shutil.copyfile(os.path.join(work, "impact.track.txt"), os.path.join(tmp, "t"))
            with open(os.path.join(tmp, "j"), "wb") as f:
                f.write(text)
            rel = os.path.relpath(work, out)
            with tarfile.open(os.path.join(dest, name + ".part"), "w:xz", preset=6) as tar:
                tar.add(os.path.join(tmp, "r"), f"{rel}/checkpoint-{gen}.restart")
                tar.add(os.path.join(tmp, "t"), f"{rel}/impact.track.txt")
                tar.add(os.path.join(tmp, "j"), f"{rel}/checkpoint.json")
        os.replace(os.path.join(dest, name + ".part"), os.path.join(dest, name))
        remove_shipped(rf"impact-{re.escape(iid)}\.gen-\d+\.tar\.xz", keep=name)
        size = os.path.getsize(os.path.join(dest, name)) / 1e6
        print(f"  impact {iid}: in flight, checkpoint generation {gen} shipped ({size:.1f} MB)")
        break
    else:
        print(f"  impact {iid}: a new checkpoint came at each of 5 tries: not shipped, run again")

# Which results folder's pinned decks key these beds (scripts/lanes-status.sh: keep that pin),
# and those decks, the ones the dry run above keyed the beds with, which a new machine pins for
# that folder (scripts/pin-program.sh): its tree's decks may have changed since, and with them
# every bed key.
with open(os.path.join(dest, "pinned-in"), "w") as f:
    f.write(os.path.basename(os.path.normpath(out)) + "\n")
if os.path.isdir(decks):
    subprocess.run([pack_decks, decks, os.path.join(dest, "pinned-decks.tar.xz")], check=True)
for name in sorted(os.listdir(dest)):
    m = IMPACT.fullmatch(name)
    if m and m.group(1) not in ids:
        os.remove(os.path.join(dest, name))
        print(f"  {name}: that impact is done, removed")
    elif name.startswith("bed-") and name.removeprefix("bed-").split(".")[0] not in needed:
        os.remove(os.path.join(dest, name))
        print(f"  {name}: no impact needs it any more, removed")
# Nothing built for, or in flight towards, what is still to run (a finished campaign): no folder.
if set(os.listdir(dest)) <= {"pinned-in", "pinned-decks.tar.xz"}:
    shutil.rmtree(dest)
    print(f"  nothing built or in flight for what is still to run: no folder {dest}")
PY
