#!/usr/bin/env python3
"""Random half split of a lab impact set's releases, fixed by a seed written before it is used.

Issue 32, item 2: the lab cylinders are split into a calibration half and a held-out half with a
seed recorded in docs/resolved-model.md before any run. The split is language-independent so that
anyone can redo it with any SHA-256 tool: each release id gets the key SHA-256("SEED:ID") (UTF-8,
hex digest), the ids are sorted by key, and the first floor(n / 2) form the calibration half.
(FNV-1a was tried first and dropped before use: its high bits barely depend on the last
character, so sorting by it grouped C01-C09 together.)

  scripts/lab-split.py data/lab/cylinders.csv 3201           # the two halves, one line each
  scripts/lab-split.py data/lab/cylinders.csv 3201 --where calibration   # a --where expression
  scripts/lab-split.py data/lab/cylinders.csv 3201 --where held-out

--where prints the filter that keeps that half (`id!=X && ...`, docs/impact-sets.md "Filters"),
for any ricochet command that takes --where. Exit 2 on a missing file or a file without ids.
"""
import hashlib
import sys


def key(seed: str, release: str) -> str:
    return hashlib.sha256(f"{seed}:{release}".encode("utf-8")).hexdigest()


def read_ids(path: str) -> list:
    try:
        lines = open(path, encoding="utf-8").read().splitlines()
    except OSError as e:
        print(f"lab-split: {path}: {e.strerror}", file=sys.stderr)
        sys.exit(2)
    rows = [l for l in lines if l.strip() and not l.startswith("#")]
    if not rows or rows[0].split(",")[0] != "id":
        print(f"lab-split: {path}: line 1 of the data: expected a header starting with 'id'",
              file=sys.stderr)
        sys.exit(2)
    return [r.split(",")[0] for r in rows[1:]]


def main(argv: list) -> int:
    if len(argv) not in (3, 5) or (len(argv) == 5 and (argv[3] != "--where" or
                                                     argv[4] not in ("calibration", "held-out"))):
        print(__doc__, file=sys.stderr)
        return 2
    path, seed = argv[1], argv[2]
    ids = read_ids(path)
    order = sorted(ids, key=lambda i: key(seed, i))
    half = len(ids) // 2
    calibration, held_out = sorted(order[:half]), sorted(order[half:])
    if len(argv) == 5:
        drop = held_out if argv[4] == "calibration" else calibration
        print(" && ".join(f"id!={i}" for i in drop))
    else:
        print("calibration:", " ".join(calibration))
        print("held-out:   ", " ".join(held_out))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
