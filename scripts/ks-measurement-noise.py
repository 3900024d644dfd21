#!/usr/bin/env python3
"""Two-sample KS of resolved V_out against the lab's, with the lab's measurement noise added to
the resolved values (issue 11, item 1; docs/resolved-calibration.md, "Fourth calibration").

    scripts/ks-measurement-noise.py CAMPAIGN.h5 [LAB.csv] [--sigma 0.1,0.1,8.3] [--draws 400]
                                    [--seed 1]

The lab's V_out are operator #2's pointing of 400 frames/s video (paper Table 1). The resolved
V_out are exact. Comparing their distributions like for like means adding the measurement error
to the resolved values. Its size per component is a lower bound from Table 1: the two operators
measured the same 28 releases, so var(operator 2) - var(operator 1) = var(noise 2) -
var(noise 1) <= var(noise 2), i.e. sigma_omega >= sqrt(10.7^2 - 6.7^2) = 8.3 rad/s; the
translation components' standard deviations agree to the table's 0.1 m/s, so the operators'
mean difference (0.1 m/s) stands for them. Each draw adds Gaussian noise (seeded) and runs the
two-sample KS test (asymptotic p, Numerical Recipes 14.3); the script prints the median p, the
10th percentile and the share of draws with p > 0.05. It says whether measurement noise of that
size can explain the narrower resolved spread, not that the resolved bed has the lab's scatter.

Only the standard library: the HDF5 file is read with h5dump (hdf5-tools).
"""
import argparse
import csv
import math
import random
import subprocess


def column(path, name):
    out = subprocess.run(["h5dump", "-y", "-w", "0", "-d", "/impacts/" + name, path],
                         capture_output=True, text=True, check=True).stdout
    body = out[out.index("DATA {") + 6:]
    body = body[:body.index("}")]
    return [float(x) for x in body.replace("\n", " ").split(",") if x.strip()]


def lab_columns(path):
    rows = [r for r in csv.reader(l for l in open(path) if not l.startswith("#"))]
    head = [h.split("[")[0] for h in rows[0]]  # names without their unit, e.g. vout_x[m/s]
    return {c: [float(r[head.index(c)]) for r in rows[1:]] for c in ("vout_x", "vout_y", "wout")}


def ks(a, b):
    a, b = sorted(a), sorted(b)
    d = 0.0
    for x in a + b:
        fa = sum(1 for y in a if y <= x) / len(a)
        fb = sum(1 for y in b if y <= x) / len(b)
        d = max(d, abs(fa - fb))
    ne = len(a) * len(b) / (len(a) + len(b))
    lam = (math.sqrt(ne) + 0.12 + 0.11 / math.sqrt(ne)) * d
    p = 2 * sum((-1) ** (k - 1) * math.exp(-2 * k * k * lam * lam) for k in range(1, 101))
    return d, min(1.0, max(0.0, p))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("campaign")
    ap.add_argument("lab", nargs="?", default="data/lab/cylinders.csv")
    ap.add_argument("--sigma", default="0.1,0.1,8.3", help="noise sd: vout_x, vout_y [m/s], wout [rad/s]")
    ap.add_argument("--draws", type=int, default=400)
    ap.add_argument("--seed", type=int, default=1)
    a = ap.parse_args()
    sigma = [float(s) for s in a.sigma.split(",")]
    if len(sigma) != 3 or min(sigma) < 0:
        ap.error("--sigma needs three non-negative numbers")
    lab = lab_columns(a.lab)
    rng = random.Random(a.seed)
    print(f"{a.campaign} against {a.lab}; noise sd {sigma}, {a.draws} draws, seed {a.seed}")
    for c, s in zip(("vout_x", "vout_y", "wout"), sigma):
        res = column(a.campaign, c)
        p0 = ks(res, lab[c])[1]
        ps = sorted(ks([v + rng.gauss(0, s) for v in res], lab[c])[1] for _ in range(a.draws))
        share = sum(p > 0.05 for p in ps) / len(ps)
        print(f"  {c:7s} KS p without noise {p0:.3g}; with noise: median {ps[len(ps) // 2]:.3g}, "
              f"10th percentile {ps[len(ps) // 10]:.3g}, share p > 0.05 {share:.0%}")


if __name__ == "__main__":
    main()
