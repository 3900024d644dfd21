#!/usr/bin/env python3
"""Per-level table and figure of the stiffness-plateau campaign (issue 32, item 1).

    scripts/plateau-table.py BUILD_DIR data/resolved/stiffness-plateau.h5 [--svg OUT.svg]

The campaign's impact ids are E<level>-<state>-s<seed> (liggghts-inputs/campaigns/
stiffness-plateau*.toml): the grain modulus E_grain [Pa], the incident state (cyl: the lab-mean
cylinder; Tnn: a lab triangle release) and the replica bed's seed. For each level and shape the
table gives, over its rebounds, the means of what the issue asks per level:

  - V_out (m/s, m/s, rad/s; the cylinder only: the triangles' six states have different V_out,
    their moves are read pairwise with `ricochet paired`);
  - the largest penetration of the block's lowest point below the levelled surface [mm];
  - the elastic recovery: that largest depth minus the depth at the end of the contact [mm];
  - the largest grain overlap over grain diameter during the contact (grain-grain and
    grain-block pairs) [-];
  - the contact duration (the force window of the track) [ms];
  - the levelled bed's grains (the same bed volume and grain sizes at every level, so the
    packing: a bed that settles denser under softer contacts holds more);
  - the cost: the time step [us], the steps and the CPU seconds of one impact (one rank).

The track quantities come from `ricochet stats FILE --json` (docs/commands/stats.md), the rest
from the campaign index (/dem/index). Hertz theory gives the reading (docs/resolved-model.md):
an elastic indentation goes as E^-2/5, a contact time as E^-2/5, the time step as E^-1/2.

--svg draws, with gnuplot, V_out^y of every state against E_grain (replica mean and sd) and the
largest penetration against E_grain with the elastic E^-2/5 slope for reference.
--tracks OUT.svg draws the tracks of one state and seed at every level (--track-of, default
cyl-s0): the normal contact force, the penetration and V_y against time (/dem/tracks, read with
h5dump).
"""
import argparse
import importlib.util
import json
import os
import statistics
import subprocess
import tempfile

_here = os.path.dirname(os.path.abspath(__file__))
_spec = importlib.util.spec_from_file_location("convergence_table",
                                               os.path.join(_here, "convergence-table.py"))
_ct = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(_ct)
read_index, mean_sd = _ct.read_index, _ct.mean_sd


def parse_id(iid):
    level, state, seed = iid.split("-")
    return float(level[1:]), state, int(seed[1:])


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("build")
    ap.add_argument("campaign")
    ap.add_argument("--svg", help="the figure (SVG; PNG when the name ends in .png)")
    ap.add_argument("--tracks", help="the tracks' figure (SVG; PNG when the name ends in .png)")
    ap.add_argument("--track-of", default="cyl-s0", help="state and seed of --tracks")
    a = ap.parse_args()

    index = read_index(a.campaign)
    stats = json.loads(subprocess.run([f"{a.build}/cli/ricochet", "stats", a.campaign, "--json"],
                                      check=True, capture_output=True, text=True).stdout)
    tracks = {t["id"]: t for t in stats["tracks"]["impacts"]}

    groups = {}
    for iid, row in index.items():
        e, state, _ = parse_id(iid)
        shape = "cylinder" if state == "cyl" else "triangles"
        groups.setdefault((e, shape), []).append(iid)

    cols = [("V_out^x [m/s]", lambda i: index[i]["vout_x"], "cylinder"),
            ("V_out^y [m/s]", lambda i: index[i]["vout_y"], "cylinder"),
            ("omega_out [rad/s]", lambda i: index[i]["wout"], "cylinder"),
            ("penetration [mm]", lambda i: 1e3 * tracks[i]["max_penetration"], None),
            ("elastic recovery [mm]", lambda i: 1e3 * tracks[i]["elastic_recovery"], None),
            ("impact's e_y", lambda i: tracks[i]["impact_restitution"], "cylinder"),
            ("impact [ms]", lambda i: 1e3 * tracks[i]["impact_duration"], "cylinder"),
            ("overlap / d", lambda i: tracks[i]["max_overlap_d"], None),
            ("contact [ms]", lambda i: 1e3 * tracks[i]["contact_duration"], None),
            # The levelled bed's grains: at a fixed bed volume, its solid fraction up to the
            # grains' mean volume (the same size distribution at every level).
            ("bed grains", lambda i: index[i]["grains"], None),
            ("dt [us]", lambda i: 1e6 * index[i]["dt_s"], None),
            ("steps", lambda i: index[i]["steps"], None),
            ("CPU s", lambda i: index[i]["cpu_s"], None)]
    print("| E_grain [Pa] | shape | rebounds | " + " | ".join(c[0] for c in cols) + " |")
    print("| --: | :-- | --: | " + " | ".join("--:" for _ in cols) + " |")
    for (e, shape), ids in sorted(groups.items()):
        ok = [i for i in ids if index[i]["status"] == "rebound" and i in tracks]
        cells = []
        for name, get, only in cols:
            if only and only != shape:
                cells.append("")
                continue
            m, s, n = mean_sd([get(i) for i in ok])
            # Grain counts in full: their level-to-level change is a few tenths of a percent.
            fm, fs = (",.0f", ",.0f") if name == "bed grains" else (".3g", ".2g")
            cells.append(f"{m:{fm}}" + (f" +- {s:{fs}}" if shape == "cylinder" and n > 1 else ""))
        print(f"| {e:.2g} | {shape} | {len(ok)}/{len(ids)} | " + " | ".join(cells) + " |")
    print("\nMeans over the rebounds of each level (the cylinder: +- the sd over its 3 replica "
          "beds; the triangles: 6 states x 3 beds pooled, so only the bed's own quantities are "
          "compared). CPU s: one rank, the machine's other core busy.")

    if a.svg:
        draw(a.svg, index, tracks)
    if a.tracks:
        draw_tracks(a.tracks, a.campaign, sorted(
            (i for i in index if i.split("-", 1)[1] == a.track_of), key=lambda i: parse_id(i)[0]))


def terminal_for(path, height=420):
    return (f"pngcairo size 1000,{height} font 'sans,10'" if path.endswith(".png") else
            f"svg size 1000,{height} font 'sans,12' background rgb 'white'")


def draw_tracks(out, campaign, ids):
    """fcy [N], penetration [mm] and vy [m/s] against t [s] of each impact's /dem/tracks/ID."""
    with tempfile.TemporaryDirectory() as tmp:
        plots = {"fcy": [], "pen": [], "vy": []}
        for iid in ids:
            body = _ct.h5_column(campaign, f"/dem/tracks/{iid}")
            rows = []
            for line in body.splitlines():
                try:
                    r = [float(x) for x in line.replace(",", " ").split()]
                except ValueError:  # the attributes' lines (column names, conventions)
                    continue
                if len(r) >= 10:
                    rows.append(r)
            path = os.path.join(tmp, f"{iid}.dat")
            with open(path, "w") as f:
                for r in rows:  # columns: t x y theta vx vy w fcx fcy penetration ...
                    f.write(f"{r[0]} {r[8]} {1e3 * r[9]} {r[5]}\n")
            level = iid.split("-")[0][1:]
            plots["fcy"].append(f"'{path}' u 1:2 w l lw 1.5 t 'E = {level} Pa'")
            plots["pen"].append(f"'{path}' u 1:3 w l lw 1.5 notitle")
            plots["vy"].append(f"'{path}' u 1:4 w l lw 1.5 notitle")
        script = f"""
set terminal {terminal_for(out, 380)}
set output '{out}'
set multiplot layout 1,3
set xlabel 't [s]'
set key top right
set ylabel 'normal contact force [N]'
plot {', '.join(plots['fcy'])}
set ylabel 'penetration [mm]'
plot {', '.join(plots['pen'])}
set ylabel 'V_y [m/s]'
plot {', '.join(plots['vy'])}
unset multiplot
"""
        subprocess.run(["gnuplot"], input=script, text=True, check=True)
        print(f"figure: {out}")


def draw(svg, index, tracks):
    states = {}
    for iid, row in index.items():
        if row["status"] != "rebound" or iid not in tracks:
            continue
        e, state, _ = parse_id(iid)
        states.setdefault(state, {}).setdefault(e, []).append(
            (row["vout_y"], 1e3 * tracks[iid]["max_penetration"]))
    with tempfile.TemporaryDirectory() as tmp:
        plots_v, plots_p = [], []
        for k, (state, by_e) in enumerate(sorted(states.items())):
            path = os.path.join(tmp, f"{state}.dat")
            with open(path, "w") as f:
                for e in sorted(by_e):
                    v = [x[0] for x in by_e[e]]
                    p = [x[1] for x in by_e[e]]
                    sv = statistics.stdev(v) if len(v) > 1 else 0.0
                    sp = statistics.stdev(p) if len(p) > 1 else 0.0
                    f.write(f"{e * (1 + 0.04 * (k - 3))} {statistics.fmean(v)} {sv} "
                            f"{statistics.fmean(p)} {sp}\n")
            plots_v.append(f"'{path}' u 1:2:3 w yerrorlines lw 1.5 t '{state}'")
            plots_p.append(f"'{path}' u 1:4:5 w yerrorlines lw 1.5 notitle")
        script = f"""
set terminal {terminal_for(svg)}
set output '{svg}'
set multiplot layout 1,2
set logscale x
set format x '10^{{%L}}'
set xlabel 'E_{{grain}} [Pa]'
set key outside right
set ylabel 'V_{{out}}^{{y}} [m/s]'
set title 'Rebound: replica mean +- sd per state'
plot {', '.join(plots_v)}
unset key
set logscale y
set ylabel 'largest penetration [mm]'
set title 'Penetration (dashed: elastic E^{{-2/5}})'
plot {', '.join(plots_p)}, 21*(x/1.5e7)**(-0.4) dt 2 lc rgb 'black'
unset multiplot
"""
        subprocess.run(["gnuplot"], input=script, text=True, check=True)
        print(f"figure: {svg}")


if __name__ == "__main__":
    main()
