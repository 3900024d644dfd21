#!/usr/bin/env python3
"""The speed campaign's reading, as fixed before it ran (issue 33; docs/diagnosis.md, "The next
rung: inertial drag", written on 2026-12-06 before sand-speeds-1.5e9 ran).

    ricochet ladder data/resolved/sand-speeds-1.5e9.h5 --add crater_rim --add inertial_drag \\
        --json > ladder.json
    scripts/drag-reading.py ladder.json

Reads the ladder's JSON and prints, against the campaign's own replicate floors:
  - issue 33's target: met when the last rung's held-out error is within 2 x the noise floor
    (V_out with the contact features: the ladder's error) and each force-history component's
    held-out RMS within 2 x the campaign's own force_history_floor;
  - the drag: it holds when its rung's drop in held-out error below the rim rung's is positive by
    more than the drag rung's standard error (the ladder's), and does not hold otherwise.
Each number is printed with its standard error where the ladder gives one. A file whose rungs are
not (base, crater_rim, inertial_drag), whose floor is not the set's own replicates, or which
lacks a field is refused with status 2 naming the file and the field.
"""
import json
import sys


class Refused(Exception):
    pass


def field(obj, path, where):
    """obj[path[0]][path[1]]..., or Refused naming the missing field."""
    cur = obj
    for key in path:
        try:
            cur = cur[key]
        except (KeyError, IndexError, TypeError):
            raise Refused("%s: no field %s" % (where, ".".join(str(k) for k in path)))
    if cur is None:
        raise Refused("%s: field %s is null" % (where, ".".join(str(k) for k in path)))
    return cur


def reading(doc, where):
    rungs = field(doc, ["rungs"], where)
    added = [r.get("added") for r in rungs]
    if added != [None, "crater_rim", "inertial_drag"]:
        raise Refused("%s: field rungs: the rungs are %s, not the reading's (base, crater_rim, "
                      "inertial_drag)" % (where, added))
    source = field(doc, ["noise_floor_detail", "source"], where)
    if source != "replicates":
        raise Refused("%s: field noise_floor_detail.source: the floor is '%s', not the set's own "
                      "replicates" % (where, source))
    floor = field(doc, ["noise_floor"], where)
    rim, drag = rungs[1], rungs[2]
    last = drag
    lines = []
    ratio = field(last, ["ratio_to_floor"], where)
    err, se = field(last, ["heldout_error"], where), field(last, ["heldout_se"], where)
    v_ok = ratio <= 2
    lines.append("V_out with the contact features: rung %d (+%s) held-out %.4g +- %.2g = %.2f x "
                 "the floor %.4g: %s" % (len(rungs) - 1, last.get("added"), err, se, ratio, floor,
                                         "within 2 x" if v_ok else "above 2 x"))
    histories = field(doc, ["force_history"], where)
    ffloor = field(doc, ["force_history_floor", "rms"], where)
    h = histories[len(rungs) - 1]
    f_ok = True
    for c, unit in (("normal", "N"), ("tangential", "N"), ("moment", "N m")):
        rms = field(h, ["heldout_rms", c], where)
        hse = field(h, ["heldout_se", c], where)
        fl = field(ffloor, [c], where)
        ok = rms <= 2 * fl
        f_ok = f_ok and ok
        lines.append("force history, %s: held-out %.4g +- %.2g %s = %.2f x its floor %.4g %s: %s"
                     % (c, rms, hse, unit, rms / fl, fl, unit, "within 2 x" if ok else "above 2 x"))
    lines.append("issue 33's target on this set: %s" % ("met" if v_ok and f_ok else "not met"))
    drop = field(rim, ["heldout_error"], where) - field(drag, ["heldout_error"], where)
    dse = field(drag, ["heldout_se"], where)
    holds = drop > dse
    lines.append("the drag: held-out %.4g (rim) -> %.4g (drag), drop %+.4g against the drag rung's "
                 "SE %.2g: %s" % (rim["heldout_error"], drag["heldout_error"], drop, dse,
                                  "holds" if holds else "does not hold"))
    return lines


def main(argv):
    if len(argv) != 2:
        print("usage: drag-reading.py LADDER.json", file=sys.stderr)
        return 2
    try:
        with open(argv[1]) as f:
            doc = json.load(f)
        print("\n".join(reading(doc, argv[1])))
    except (OSError, ValueError) as e:
        print("%s: %s" % (argv[1], e), file=sys.stderr)
        return 2
    except Refused as e:
        print(str(e), file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
