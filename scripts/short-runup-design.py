#!/usr/bin/env python3
"""The impacts of a campaign design whose run-up would start behind the bed's back wall, as an
explicit design with a shorter free flight (amended on 2026-12-06, docs/resolved-model.md, "The
blind triangles' fast states").

    scripts/short-runup-design.py RICOCHET DESIGN.toml DECKS FILE.h5 --name NAME --out NAME.toml

The driver refuses an impact (status `invalid`, docs/commands/dem.md, "What an impact does", 3)
whose block would be inserted closer to the wall behind it than its bounding radius plus 4 grain
radii: the insertion point is the landing point (run.x_impact_frac of the bed) less V_in^x times
the free flight before contact (run.t_pre_s). The blind triangles' design (t_pre_s = 0.025 s,
landing 0.26 m from the back wall of the 1.5 m bed) does that to the lab's four fastest releases
(V_in^x 5.31-5.69 m/s). This script keeps everything of such an impact (id, incident state,
orientation, seed, bed, block, the landing point) and shortens only its free flight, to the
longest multiple of 2.5 ms that starts the block behind the margin: at the landing it changes
nothing, and at the extraction's 400 frames/s it leaves 9 frames or more of free flight (the
decks' default is 12.5 ms).

RICOCHET's dry run of DESIGN (decks DECKS, campaign file FILE) names the refused impacts, with
the reason and the spec as FILE's index records it; only the run-up refusals are taken (any other
reason stops the script, exit 2), whatever FILE records for them, so that the design written is
the same on every machine (an impact of it that FILE has, run under this design, is skipped when
the design runs). With no such impact nothing is written. The
orientation is written in degrees with 17 significant digits (the spec keeps radians): the same
orientation to the last bit or one unit of it. Exit 2 when a run-up cannot be shortened to 12.5
ms or more.

Only the standard library.
"""
import argparse
import json
import math
import re
import subprocess
import sys
import tomllib

RUNUP = re.compile(r"the block would start at x = ([0-9.]+) m and touch the bed at x = ([0-9.]+) m: "
                   r"it must start at least ([0-9.]+) m from the wall behind it")
STEP_S = 0.0025
SHORTEST_S = 0.0125


def toml_value(v):
    """A spec's value (the index keeps parameters as strings) as TOML: a number when it reads as
    one, else a string (e.g. bed.rolling_model)."""
    if isinstance(v, (int, float)):
        return repr(v)
    try:
        return repr(float(v))
    except ValueError:
        return json.dumps(v)


def inline(table):
    return "{ " + ", ".join(f"{k} = {toml_value(v)}" for k, v in sorted(table.items())) + " }"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("ricochet")
    ap.add_argument("design")
    ap.add_argument("decks")
    ap.add_argument("file")
    ap.add_argument("--name", required=True)
    ap.add_argument("--out", required=True)
    a = ap.parse_args()
    plan = json.loads(subprocess.run(
        [a.ricochet, "dem", "campaign", a.design, "--decks", a.decks, "--out", a.file, "--dry-run",
         "--json"], check=True, capture_output=True, text=True).stdout)
    with open(a.design, "rb") as f:
        source = tomllib.load(f)
    impacts = []
    for p in plan["impacts"]:
        if p["invalid"] is None:
            continue
        m = RUNUP.match(p["invalid"])
        if not m:
            print(f"short-runup-design: {p['id']} is refused for another reason: {p['invalid']}",
                  file=sys.stderr)
            return 2
        touch, margin = float(m.group(2)), float(m.group(3))
        spec = p["spec"]
        vx = spec["vin"][0]
        t_pre = math.floor((touch - margin) / vx / STEP_S + 1e-9) * STEP_S
        if t_pre < SHORTEST_S - 1e-12:
            print(f"short-runup-design: {p['id']}: V_in^x {vx} m/s leaves {touch - margin:.4f} m "
                  f"of run-up, under {SHORTEST_S} s of free flight", file=sys.stderr)
            return 2
        run = dict(spec["run"], t_pre_s=round(t_pre, 6))
        impacts.append((spec, run, float(spec["run"]["t_pre_s"])))
    if not impacts:
        print(f"{a.design}: no impact would be refused for its run-up; nothing written")
        return 0
    out = [f"# {a.name}: written by scripts/short-runup-design.py from {source['campaign']['name']}",
           "# (the impacts its driver refuses for a run-up behind the back wall, their free flight",
           "# shortened; everything else as that design gives it).", "[campaign]",
           f'name = "{a.name}"', "ranks_per_impact = 1",
           f'cache_dir = "{source["campaign"]["cache_dir"]}"', f'work_dir = "dem-work/{a.name}"', ""]
    if "extract" in source:
        out += ["[extract]"] + [f"{k} = {json.dumps(v)}" for k, v in source["extract"].items()] + [""]
    for spec, run, old in impacts:
        out += ["[[impact]]", f'id = "{spec["id"]}"', f'shape = "{spec["shape"]}"',
                f"vin = [{', '.join(repr(v) for v in spec['vin'])}]",
                f"alpha_in_deg = {math.degrees(spec.get('alpha_in_rad', 0.0)):.17g}"]
        if "seed" in spec:
            out.append(f"seed = {spec['seed']}")
        out += [f"{k} = {inline(spec[k])}" for k in ("bed", "block") if spec.get(k)]
        out += [f"run = {inline(run)}", f"# t_pre_s {old} s in {source['campaign']['name']}", ""]
    with open(a.out, "w") as f:
        f.write("\n".join(out))
    print(f"{a.out}: {len(impacts)} impacts ({', '.join(s['id'] for s, _, _ in impacts)})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
