#!/usr/bin/env python3
"""How each design point of a grain calibration rebounds: from its impact or from a roll-out.

Issue 32, item 2 (docs/resolved-model.md, "The calibration's result"): `ricochet stats` ends
the impact proper where the contact force first falls to the block's weight and gives the
block's vy there over its landing vy (`impact_restitution`, docs/commands/stats.md). This
script sets that beside each design point's grain parameters and packing:

  scripts/impact-regimes.py BUILD_DIR CAMPAIGN.h5 CALIBRATION.json

- CAMPAIGN.h5: the calibration's campaign file (tracks kept), read through
  `BUILD_DIR/cli/ricochet stats CAMPAIGN.h5 --json`;
- CALIBRATION.json: `ricochet calibrate-grains --out` on it: its `parameters`, and per design
  point (`points`) the impact ids, the parameter values `x`, the solid fractions and the mean
  V_out.

Prints a Markdown table, one row per design point with rebounds (means over its rebounds), sorted
by solid fraction, then Spearman's rank correlation of the impact restitution with the solid
fraction and with each parameter over the points, with its two-sided p (the t approximation,
n - 2 degrees of freedom) and Holm's adjustment over those tests. Exit 2 on a missing file.
"""
import json
import math
import os
import subprocess
import sys


def ranks(v):
    order = sorted(range(len(v)), key=lambda i: v[i])
    r = [0.0] * len(v)
    i = 0
    while i < len(order):
        j = i
        while j + 1 < len(order) and v[order[j + 1]] == v[order[i]]:
            j += 1
        for k in range(i, j + 1):
            r[order[k]] = (i + j) / 2 + 1  # ties share their mean rank
        i = j + 1
    return r


def spearman(a, b):
    """Spearman's rho (Pearson on ranks) and its two-sided p (t approximation, n - 2 dof)."""
    ra, rb = ranks(a), ranks(b)
    n = len(a)
    ma, mb = sum(ra) / n, sum(rb) / n
    cov = sum((x - ma) * (y - mb) for x, y in zip(ra, rb))
    rho = cov / math.sqrt(sum((x - ma) ** 2 for x in ra) * sum((y - mb) ** 2 for y in rb))
    if abs(rho) >= 1:
        return rho, 0.0
    t = rho * math.sqrt((n - 2) / (1 - rho * rho))
    return rho, student_t_two_sided(t, n - 2)


def student_t_two_sided(t, dof):
    # P(|T| > t) = I_{dof / (dof + t^2)}(dof / 2, 1 / 2), by the regularised incomplete beta's
    # continued fraction (Numerical Recipes, 3rd ed., section 6.4).
    x = dof / (dof + t * t)
    return betainc(dof / 2, 0.5, x)


def betainc(a, b, x):
    if x <= 0 or x >= 1:
        return 0.0 if x <= 0 else 1.0
    front = math.exp(math.lgamma(a + b) - math.lgamma(a) - math.lgamma(b) +
                     a * math.log(x) + b * math.log(1 - x))
    if x > (a + 1) / (a + b + 2):
        return 1 - betainc(b, a, 1 - x)
    c, d, f = 1.0, 1 - (a + b) * x / (a + 1), 0.0
    d = 1 / d if abs(d) > 1e-300 else 1e300
    f = d
    for m in range(1, 300):
        for num in (m * (b - m) * x / ((a + 2 * m - 1) * (a + 2 * m)),
                    -(a + m) * (a + b + m) * x / ((a + 2 * m) * (a + 2 * m + 1))):
            d = 1 + num * d
            d = 1 / d if abs(d) > 1e-300 else 1e300
            c = 1 + num / c if abs(c) > 1e-300 else 1e300
            f *= c * d
    return front * f / a


def main():
    if len(sys.argv) != 4:
        print(__doc__, file=sys.stderr)
        sys.exit(2)
    build, campaign, calibration = sys.argv[1:]
    for path in (campaign, calibration, os.path.join(build, "cli", "ricochet")):
        if not os.path.exists(path):
            print(f"impact-regimes: {path}: no such file", file=sys.stderr)
            sys.exit(2)
    stats = json.loads(subprocess.run([os.path.join(build, "cli", "ricochet"), "stats", campaign,
                                       "--json"], check=True, capture_output=True,
                                      text=True).stdout)
    tracks = {t["id"]: t for t in stats["tracks"]["impacts"]}
    cal = json.load(open(calibration))
    names = [p.split(".", 1)[1] for p in cal["parameters"]]

    rows = []
    for p in cal["points"]:
        # The point's rebounds with a track: its campaign ids, and their end-wall reruns.
        ids = [i for i in tracks if any(i == d or i.startswith(d + "-") for d in p["ids"])]
        got = [tracks[i] for i in ids if tracks[i]["impact_restitution"] is not None]
        if not got:
            continue
        mean = lambda key, s=1.0: s * sum(t[key] for t in got) / len(got)
        rows.append({"point": p["ids"][0].split("-")[1], "x": p["x"],
                     "solid_fraction": sum(p["solid_fraction"]) / len(p["solid_fraction"]),
                     "e": mean("impact_restitution"), "pen_mm": mean("max_penetration", 1e3),
                     "impact_ms": mean("impact_duration", 1e3),
                     "contact_ms": mean("contact_duration", 1e3), "vout": p["mean"],
                     "n": len(got)})
    rows.sort(key=lambda r: r["solid_fraction"])
    print("| point | solid fraction | " + " | ".join(names) + " | rebounds | impact's e_y | "
          "penetration [mm] | impact [ms] | contact [ms] | V_out (x, y, omega) |")
    print("| :-- | --: | " + " | ".join("--:" for _ in names) + " | --: | --: | --: | --: | --: | :-- |")
    for r in rows:
        v = r["vout"]
        print(f"| {r['point']} | {r['solid_fraction']:.3f} | " +
              " | ".join(f"{x:.2f}" for x in r["x"]) +
              f" | {r['n']} | {r['e']:.2f} | {r['pen_mm']:.1f} | {r['impact_ms']:.1f} | "
              f"{r['contact_ms']:.0f} | ({v[0]:.2f}, {v[1]:.2f}, {v[2]:.1f}) |")
    print(f"\nSpearman's rank correlation of the impact's e_y with, over the {len(rows)} points "
          "(two-sided p, t approximation, and Holm's adjustment over the tests listed):\n")
    e = [r["e"] for r in rows]
    cols = [("solid fraction", [r["solid_fraction"] for r in rows])]
    cols += [(n, [r["x"][k] for r in rows]) for k, n in enumerate(names)]
    tests = [(name,) + spearman(v, e) for name, v in cols]
    # Holm (1979): the k-th smallest of m p values times (m - k + 1), made monotone.
    order = sorted(range(len(tests)), key=lambda i: tests[i][2])
    holm, running = [0.0] * len(tests), 0.0
    for k, i in enumerate(order):
        running = max(running, min(1.0, (len(tests) - k) * tests[i][2]))
        holm[i] = running
    for (name, rho, p), ph in zip(tests, holm):
        print(f"- {name}: rho = {rho:+.2f}, p = {p:.3f}, Holm {ph:.3f}")


if __name__ == "__main__":
    main()
