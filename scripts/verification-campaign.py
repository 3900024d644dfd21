#!/usr/bin/env python3
"""The verification campaign of a grain calibration: the calibrated grains hit at every lab state.

Issue 32, item 2 (docs/resolved-model.md, "Recalibration with what sand has", "Verification"): the
grains that `ricochet calibrate-grains` found are checked by a real campaign, not by the surrogate.
This script writes that campaign's design from three files, so that the check follows the plan
without a hand in between (scripts/dem-lanes.sh runs it as soon as the calibration ends):

  scripts/verification-campaign.py SAMPLED.toml CALIBRATION.json LAB.csv --beds 3 \\
      --name sand-verification-1.5e9 --out DESIGN.toml [--blind-triangles]

- SAMPLED.toml: the sampled campaign the calibration was fitted on. Its [bed], [block], [run] and
  [extract] tables are kept (E_grain_Pa, the walls, the window), its [design.sample] parameters
  are set to the calibrated values, and its [design.tie] is applied to them (a tied parameter
  takes its source's calibrated value). The position along the bed is the first value of its
  [design.vary] run.x_impact_frac (fixed here before any verification impact: 0.26 for
  sand-calibration-1.5e9.toml).
- CALIBRATION.json: `calibrate-grains --json` or `--out`: its `calibrated` {PARAMETER: value}.
- LAB.csv: the lab releases (every one, in file order); release k (0-based) is hit on the bed of
  replica seed k mod BEDS, as the plan says.

With --blind-triangles the design is the blind check of the same grains on the lab triangles
(issue 32, item 3; issue 35, item 4) instead: LAB.csv's triangle releases through [design]
incident_from, one orientation per release stratified over the prism's period (alpha_in_deg_sample
range [-60, 60] deg, seed 1, as every earlier blind run, so that runs compare release by release),
one bed (replica seed 0, the verification's first), the DEM force window (the lab's ground window
is not reliable for a rotating prism, docs/resolved-calibration.md), and t_pre_s = 0.025 s of
free flight before contact instead of the decks' 0.0125 s: T17's spinning vertex reached the
ground 2 frames after the start in both earlier blind runs, too few frames to reconstruct V_in
(fixed here, before any run on the calibrated bed). T13 and T15 rolled to the end wall of a 0.6 m
slab; the calibrated bed is 1.0 m long, which leaves them 0.74 m from x_impact_frac 0.26.

With --states-from DESIGN.toml the design is the calibrated grains at another campaign's incident
states and positions instead (its [design] shape and incident list, its [design.vary]
run.x_impact_frac), on the verification's first bed (replica seed 0); LAB.csv is not read. Issue
33, item 4 runs it with liggghts-inputs/campaigns/speeds-calibrated-long.toml: the lab's mean
cylinder state scaled by 0.5-1.5 at three positions, the states on which the fifth bed's force loop
stopped at 8.1x its floor, now on the plateau bed's calibrated grains (fixed here before any run).

With --bed-length-m L the beds are L long instead of the sampled campaign's length (bed.Lx_m,
else the decks' default of liggghts-inputs/common/grain-defaults.in), and every position keeps its
distance from the back wall (x_impact_frac scaled by the old length over L): the block lands where
it landed in the calibration (with --states-from: in the other campaign, whose own length counts)
and has the difference in length more room ahead. scripts/dem-lanes.sh gives
1.5 m to all three designs (fixed on 2026-11-29, before any of their impacts, from the geometry
alone: at the calibration state the cylinder travelled 0.37-0.60 m from release to the end of its
run on the 1.0 m slab, and sandv00-p02 at x 0.32 stopped at the end wall; the lab's V_in^x reaches
1.11 x, the speed states 1.5 x, that state's, and T13 and T15 reached the end wall in every earlier
blind run).

With --active-zone-m R every impact of the design integrates only the grains within R of the
block's path (run.active_zone_m, docs/resolved-model.md, "Active zone"); scripts/dem-lanes.sh gives
it only when the paired check below passed at the calibrated grains. With --zone-check R the
design is that check instead: the first four releases of LAB.csv that the verification hits on
replica bed 0 (releases 0, 3, 6, 9 with --beds 3: C01, C04, C07, C10), each twice on that bed,
as `whole-ID` (the whole bed) and `zoneR-ID` (run.active_zone_m = R), for
`ricochet paired --base whole- --against zoneR-` (scripts/active-zone-verdict.sh; the rule is
fixed in docs/resolved-model.md before any run).

With --id-prefix P (with --blind-triangles only) every generated id starts with P ([design]
id_prefix): the same orientations and states under other ids, for the triangles' active-zone check
(amended on 2026-12-06, before any triangle ran in a zone: scripts/dem-lanes.sh, docs/
resolved-model.md "Active zone"): `--blind-triangles --active-zone-m 0.3 --id-prefix zone0.3-`
is the blind design's zone arm, run with `dem campaign --only` beside the whole bed's own impacts,
and `ricochet paired --base T --against zone0.3-T` pairs them.

With --sets the script prints the calibrated grains' bed.* and block.* settings instead, one
SECTION.NAME=VALUE per line (the sampled campaign's [bed] and [block], the calibrated values, the
ties), for `ricochet dem drop --set`: scripts/plateau-drop.sh drops the sphere on the same grains
(DROP_GRAINS_FROM). --name and --out are then not used.

Exit 2, naming the file, on a missing file, a calibrated parameter that the sampled campaign does
not sample, or a lab file without the impact-set header.
"""
import argparse
import hashlib
import json
import os
import sys
import tomllib


def fail(path: str, why: str) -> None:
    print(f"verification-campaign: {path}: {why}", file=sys.stderr)
    sys.exit(2)


def read_lab(path: str) -> list:
    try:
        lines = open(path, encoding="utf-8").read().splitlines()
    except OSError as e:
        fail(path, e.strerror)
    rows = [l for l in lines if l.strip() and not l.startswith("#")]
    head = rows[0].split(",") if rows else []
    want = ["id", "shape", "vin_x[m/s]", "vin_y[m/s]", "win[rad/s]"]
    if head[:5] != want:
        fail(path, f"line 1 of the data: expected the columns {','.join(want)} first")
    return [r.split(",")[:5] for r in rows[1:]]


def deck_bed_length_m() -> float:
    """The decks' default bed length: `variable Lx_m index VALUE` in grain-defaults.in."""
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "liggghts-inputs",
                        "common", "grain-defaults.in")
    try:
        for line in open(path, encoding="utf-8"):
            f = line.split()
            if f[:3] == ["variable", "Lx_m", "index"]:
                return float(f[3])
    except (OSError, ValueError, IndexError) as e:
        fail(path, f"no default bed length ({e})")
    fail(path, "no `variable Lx_m index` line")


def toml_value(v) -> str:
    if isinstance(v, str):
        return json.dumps(v)
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, float):
        return repr(v)
    return str(v)


def main(argv: list) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("sampled")
    ap.add_argument("calibration")
    ap.add_argument("lab", nargs="?")
    ap.add_argument("--beds", type=int, default=3)
    ap.add_argument("--name")
    ap.add_argument("--out")
    ap.add_argument("--blind-triangles", action="store_true")
    ap.add_argument("--states-from", metavar="DESIGN.toml")
    ap.add_argument("--sets", action="store_true")
    ap.add_argument("--bed-length-m", type=float)
    ap.add_argument("--active-zone-m", type=float)
    ap.add_argument("--zone-check", type=float, metavar="R")
    ap.add_argument("--id-prefix", metavar="P")
    a = ap.parse_args(argv)
    if a.id_prefix is not None and (not a.blind_triangles or not a.id_prefix.strip()):
        fail("--id-prefix", "a non-empty prefix, with --blind-triangles only")
    if a.zone_check is not None and (a.states_from or a.blind_triangles):
        fail("--zone-check", "checks the verification's own design: not with --states-from or "
             "--blind-triangles")
    for opt, r in (("--active-zone-m", a.active_zone_m), ("--zone-check", a.zone_check)):
        if r is not None and not 0.05 <= r <= 5.0:
            fail(opt, f"{r} is outside [0.05, 5] m")
    if a.states_from and a.blind_triangles:
        fail("--states-from", "and --blind-triangles are two different designs: give one")
    if not a.states_from and not a.lab and not a.sets:
        fail("LAB.csv", "missing (needed unless --states-from)")
    if not a.sets and (not a.name or not a.out):
        fail("--name/--out", "both are required (unless --sets)")
    if a.bed_length_m is not None and not 0.3 <= a.bed_length_m <= 5.0:
        fail("--bed-length-m", f"{a.bed_length_m} is outside [0.3, 5] m")
    if a.beds < 1:
        fail("--beds", "expects at least 1")
    try:
        sampled = tomllib.load(open(a.sampled, "rb"))
    except (OSError, tomllib.TOMLDecodeError) as e:
        fail(a.sampled, str(e))
    try:
        raw = open(a.calibration, "rb").read()
        calibrated = json.loads(raw)["calibrated"]
    except (OSError, ValueError, KeyError) as e:
        fail(a.calibration, f"no `calibrated` object ({e})")
    design = sampled.get("design", {})
    sample = design.get("sample", {})
    tables = {s: dict(sampled.get(s, {})) for s in ("bed", "block", "run")}
    for name, value in calibrated.items():
        if name not in sample:
            fail(a.calibration, f"{name} is not a [design.sample] parameter of {a.sampled}")
        section, key = name.split(".", 1)
        tables[section][key] = float(f"{value:.4g}")
    for target, source in design.get("tie", {}).items():
        section, key = target.split(".", 1)
        s_section, s_key = source.split(".", 1)
        tables[section][key] = tables[s_section][s_key]
    if a.sets:
        for section in ("bed", "block"):
            for k, v in sorted(tables[section].items()):
                print(f"{section}.{k}={v}")
        return 0
    def kept_distance(bed: dict) -> float:
        """The x_impact_frac multiplier that keeps a landing point's distance from the back wall
        of a bed configured by `bed` (its Lx_m, else the decks') on the --bed-length-m bed."""
        if a.bed_length_m is None:
            return 1.0
        return float(bed.get("Lx_m", deck_bed_length_m())) / a.bed_length_m

    scale = kept_distance(tables["bed"])
    if a.bed_length_m is not None:
        tables["bed"]["Lx_m"] = a.bed_length_m
    if a.active_zone_m is not None:
        tables["run"]["active_zone_m"] = a.active_zone_m
    positions = design.get("vary", {}).get("run.x_impact_frac")
    if positions:
        tables["run"]["x_impact_frac"] = round(positions[0] * scale, 6)
    states = None
    if a.states_from:
        try:
            other_toml = tomllib.load(open(a.states_from, "rb"))
            other = other_toml.get("design", {})
        except (OSError, tomllib.TOMLDecodeError) as e:
            fail(a.states_from, str(e))
        if not other.get("incident"):
            fail(a.states_from, "no [design] incident list")
        scale = kept_distance(other_toml.get("bed", {}))  # its positions: fractions of its bed
        states = {"shape": other.get("shape", "cylinder"), "incident": other["incident"],
                  "positions": [round(x * scale, 6) for x in
                                other.get("vary", {}).get("run.x_impact_frac", [])]}
        if states["positions"]:
            tables["run"].pop("x_impact_frac", None)
    lab = read_lab(a.lab) if not states else []
    extract = dict(sampled.get("extract", {}))
    if a.blind_triangles:
        lab = [r for r in lab if r[1] == "triangle"]
        if not lab:
            fail(a.lab, "no triangle release")
        extract["window"] = "force"
        tables["run"]["t_pre_s"] = 0.025
    zone_ids = []
    if a.zone_check is not None:
        lab = [r for k, r in enumerate(lab) if k % a.beds == 0][:4]
        zone_ids = ["whole", f"zone{a.zone_check:g}"]
    digest = hashlib.sha256(raw).hexdigest()[:16]
    out = [
        f"# Generated by scripts/verification-campaign.py from {a.sampled},",
        f"# {a.calibration} (SHA-256 {digest}...) and {a.states_from or a.lab}: the calibrated grains",
        (f"# hit at the incident states and positions of {a.states_from}, on replica bed 0."
         if states else
         f"# hit blind at the {len(lab)} lab triangle states, one stratified orientation each."
         if a.blind_triangles else
         f"# hit at {len(lab)} lab states on replica bed 0, the whole bed and an active zone of "
         f"{a.zone_check:g} m." if zone_ids else
         f"# hit at the {len(lab)} lab states, release k on the bed of replica seed k mod {a.beds}."),
        "[campaign]",
        f'name = "{a.name}"',
        "ranks_per_impact = 1",
        'cache_dir = "dem-cache"',
        f'work_dir = "dem-work/{a.name}"',
    ]
    if extract:
        out += ["", "[extract]"] + [f"{k} = {toml_value(v)}" for k, v in extract.items()]
    for section in ("bed", "block", "run"):
        if tables[section]:
            out += ["", f"[{section}]"]
            out += [f"{k} = {toml_value(v)}" for k, v in sorted(tables[section].items())]
    if a.blind_triangles:
        # Absolute: the campaign scripts run a pinned copy of the design from another folder.
        lab_path = os.path.abspath(a.lab)
        out += ["", "[design]", 'shape = "triangle"', f"incident_from = {json.dumps(lab_path)}",
                "alpha_in_deg_sample = { range = [-60.0, 60.0], seed = 1 }", "seeds = [0]"]
        if a.id_prefix:
            out += [f"id_prefix = {json.dumps(a.id_prefix)}"]
        lab = []
    if states:
        rows = ", ".join("[" + ", ".join(repr(float(c)) for c in v) + "]" for v in states["incident"])
        out += ["", "[design]", f"shape = {json.dumps(states['shape'])}", f"incident = [{rows}]",
                "seeds = [0]"]
        if states["positions"]:
            out += ["[design.vary]", '"run.x_impact_frac" = [' +
                    ", ".join(repr(float(x)) for x in states["positions"]) + "]"]
    for k, (rid, shape, vx, vy, w) in enumerate(lab):
        if zone_ids:
            for prefix in zone_ids:
                out += ["", "[[impact]]", f'id = "{prefix}-{rid}"', f'shape = "{shape}"',
                        f"vin = [{vx}, {vy}, {w}]", "seed = 0"]
                if prefix != "whole":
                    out += [f"run = {{ active_zone_m = {a.zone_check!r} }}"]
            continue
        out += ["", "[[impact]]", f'id = "{rid}"', f'shape = "{shape}"',
                f"vin = [{vx}, {vy}, {w}]", f"seed = {k % a.beds}"]
    try:
        with open(a.out, "w", encoding="utf-8") as f:
            f.write("\n".join(out) + "\n")
    except OSError as e:
        fail(a.out, e.strerror)
    if states:
        n = len(states["incident"]) * max(1, len(states["positions"] or []))
        print(f"{a.out}: {n} impacts at the states of {a.states_from}")
    else:
        print(f"{a.out}: " + ("the blind triangles" if a.blind_triangles
                              else f"{2 * len(lab)} impacts, the zone check" if zone_ids
                              else f"{len(lab)} impacts on {a.beds} beds"))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
