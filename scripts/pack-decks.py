#!/usr/bin/env python3
"""Packs a campaign's pinned decks for a new machine: the same decks give the same bytes.

    scripts/pack-decks.py DECKS_DIR OUT.tar.xz

A bed's cache key hashes the bed decks' text (src-ext/bed.hpp), so the beds that
scripts/ship-beds.sh ships are usable only with the decks the campaign pinned
(scripts/pin-program.sh). A new machine has no pinned folder and would pin the tree's decks,
which differ once a deck has been edited since (2026-12-07: the bed decks' checkpoints changed
every bed key, and the shipped bed of the speed campaign went unfound). ship-beds.sh therefore
ships the pinned decks beside the beds (pinned-decks.tar.xz) and pin_program extracts them
instead of the tree's. The archive holds liggghts-inputs/ with its files sorted, modification
times, owners and modes fixed, so packing the same decks twice gives the same file (git sees no
change). Writes through OUT.part; exit 2 on a wrong call.
"""
import io
import lzma
import os
import sys
import tarfile


def main():
    if len(sys.argv) != 3 or not os.path.isdir(sys.argv[1]):
        print(__doc__.strip().split("\n")[2].strip(), file=sys.stderr)
        sys.exit(2)
    decks, out = sys.argv[1], sys.argv[2]
    buf = io.BytesIO()
    with tarfile.open(fileobj=buf, mode="w", format=tarfile.PAX_FORMAT) as tar:
        for root, dirs, files in os.walk(decks):
            dirs.sort()
            for name in sorted(files):
                path = os.path.join(root, name)
                info = tarfile.TarInfo(
                    os.path.join("liggghts-inputs", os.path.relpath(path, decks)))
                info.size = os.path.getsize(path)
                info.mtime, info.mode, info.uid, info.gid = 0, 0o644, 0, 0
                with open(path, "rb") as f:
                    tar.addfile(info, f)
    with open(out + ".part", "wb") as f:
        f.write(lzma.compress(buf.getvalue(), preset=6))
    os.replace(out + ".part", out)


if __name__ == "__main__":
    main()
