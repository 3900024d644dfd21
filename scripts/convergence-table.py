#!/usr/bin/env python3
"""Convergence table of a resolved campaign with replica beds (issue 11, item 3).

    scripts/convergence-table.py BUILD_DIR CAMPAIGN.h5 [--base base] [--json OUT.json]

The campaign's impact ids are CONFIG-sN (liggghts-inputs/campaigns/convergence.toml): one
incident state, one configuration of the bed per CONFIG, N the replica bed's seed. For each
configuration the table gives the mean over its replica beds of V_out (m/s, m/s, rad/s), of the
maximum penetration (mm) and contact duration (ms), and of the per-impact upscaled e_n^2 and mu_R
(`ricochet upscale`: the reduced engine's law fitted to each impact; mu is left out, one impact
hardly identifies it). Each mean is compared with the base configuration's:

    z = (m_c - m_b) / sqrt(s_c^2 / n_c + s_b^2 / n_b)        (Welch's statistic)

with s the replica beds' sample standard deviation. A change counts as resolved by the data when
|m_c - m_b| exceeds the pooled replica scatter s_p (the bed-to-bed sd, the issue's criterion:
"changes by less than the replicate scatter"); |z| says how sure the difference of the means is.
Cost per impact: the LIGGGHTS CPU time of the impact (cpu_s), the grain count (grains).

Only the standard library: the HDF5 file is read with h5dump (hdf5-tools), the fits with the
ricochet binary.
"""
import argparse
import json
import math
import re
import statistics
import subprocess
import sys


def h5_column(path, dataset):
    out = subprocess.run(["h5dump", "-y", "-w", "0", "-d", dataset, path], check=True,
                         capture_output=True, text=True).stdout
    body = out[out.index("DATA {") + len("DATA {"):out.rindex("}")]
    body = body[:body.rindex("}")]
    return body


def numbers(text):
    return [float(x) for x in re.findall(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?|nan", text)]


def strings(text):
    return re.findall(r'"((?:[^"\\]|\\.)*)"', text)


def read_index(path):
    cols_dump = subprocess.run(["h5dump", "-a", "/dem/index/values/columns", path], check=True,
                               capture_output=True, text=True).stdout
    columns = strings(cols_dump.split("DATA {", 1)[1])[0].split(",")
    ids = strings(h5_column(path, "/dem/index/id"))
    status = strings(h5_column(path, "/dem/index/status"))
    values = numbers(h5_column(path, "/dem/index/values"))
    n = len(columns)
    rows = [dict(zip(columns, values[i * n:(i + 1) * n])) for i in range(len(ids))]
    return {i: dict(r, status=s) for i, s, r in zip(ids, status, rows)}


def mean_sd(xs):
    xs = [x for x in xs if x is not None and not math.isnan(x)]
    if not xs:
        return float("nan"), float("nan"), 0
    return statistics.fmean(xs), statistics.stdev(xs) if len(xs) > 1 else float("nan"), len(xs)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("build")
    ap.add_argument("campaign")
    ap.add_argument("--base", default="base")
    ap.add_argument("--json")
    a = ap.parse_args()

    index = read_index(a.campaign)
    up = json.loads(subprocess.run(
        [f"{a.build}/cli/ricochet", "upscale", a.campaign, "--by", "bed.Ly_m", "--no-intervals",
         "--json"], check=True, capture_output=True, text=True).stdout)
    fits = {im["id"]: im for im in up["impacts"]}

    quantities = [("V_out^x [m/s]", lambda r, f: r["vout_x"]),
                  ("V_out^y [m/s]", lambda r, f: r["vout_y"]),
                  ("omega_out [rad/s]", lambda r, f: r["wout"]),
                  ("penetration [mm]", lambda r, f: 1e3 * r["penetration"]),
                  ("duration [ms]", lambda r, f: 1e3 * r["contact_duration"]),
                  ("e_n^2", lambda r, f: f["params"]["en2"] if f else float("nan")),
                  ("mu_R", lambda r, f: f["params"]["muR"] if f else float("nan"))]
    configs = {}
    for iid, row in index.items():
        configs.setdefault(iid.rsplit("-s", 1)[0], []).append(iid)

    table = {}
    for c, ids in configs.items():
        ok = [i for i in ids if index[i]["status"] == "rebound"]
        entry = {"impacts": len(ids), "rebounds": len(ok),
                 "grains": statistics.fmean(index[i]["grains"] for i in ids),
                 "cpu_s": statistics.fmean(index[i]["cpu_s"] for i in ids),
                 "quantities": {}}
        for name, get in quantities:
            m, s, n = mean_sd([get(index[i], fits.get(i)) for i in ok])
            entry["quantities"][name] = {"mean": m, "sd": s, "n": n}
        table[c] = entry
    if a.base not in table:
        sys.exit(f"convergence-table: no configuration '{a.base}' in {a.campaign} "
                 f"(configurations: {', '.join(sorted(table))})")
    base = table[a.base]
    for c, entry in table.items():
        for name, q in entry["quantities"].items():
            b = base["quantities"][name]
            se = math.sqrt(q["sd"] ** 2 / max(q["n"], 1) + b["sd"] ** 2 / max(b["n"], 1))
            sp = math.sqrt(0.5 * (q["sd"] ** 2 + b["sd"] ** 2))
            q["change"] = q["mean"] - b["mean"]
            q["z"] = q["change"] / se if se > 0 else float("nan")
            q["pooled_sd"] = sp
            q["within_scatter"] = abs(q["change"]) <= sp
    if a.json:
        with open(a.json, "w") as f:
            json.dump(table, f, indent=1)

    names = [n for n, _ in quantities]
    print("| configuration | grains | CPU s / impact | rebounds | " + " | ".join(names) + " |")
    print("| :-- | --: | --: | --: | " + " | ".join("--:" for _ in names) + " |")
    for c, e in table.items():
        cells = []
        for n in names:
            q = e["quantities"][n]
            cell = f"{q['mean']:.3g} +- {q['sd']:.2g}"
            if c != a.base:
                cell += f" ({q['change']:+.2g}, z {q['z']:+.1f}{'' if q['within_scatter'] else ' !'})"
            cells.append(cell)
        print(f"| {c} | {e['grains']:.0f} | {e['cpu_s']:.0f} | {e['rebounds']}/{e['impacts']} | "
              + " | ".join(cells) + " |")
    print("\nmean +- replica-bed sd; (change from the base, Welch z); '!' marks a change larger "
          "than the pooled replica sd.")


if __name__ == "__main__":
    main()
