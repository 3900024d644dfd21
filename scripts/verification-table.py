#!/usr/bin/env python3
"""The held-out table of the sand-only recalibration (issue 32, item 2), from its checks' JSON.

    scripts/verification-table.py HALF=CHECK.json [HALF=CHECK.json ...]
    e.g. scripts/verification-table.py held-out=results/sand-verification/check-held-out.json \\
             calibration=results/sand-verification/check-calibration.json

Each CHECK.json is `ricochet upscale VERIFICATION.h5 --lab data/lab/cylinders.csv --where H
--lab-where H --lab-noise 0.1,0.1,3.4 --seed 3202 --json` for one half H of the lab split
(scripts/dem-lanes.sh writes both). The table gives, per half and V_out component, the lab's
mean +- sd, the resolved mean, the gap in lab sd (`gap_to_lab.C.difference_in_lab_std`), the
median KS p-value over the 400 seeded draws of the lab's reading noise added to the resolved
values (`ks_with_lab_noise.median_p`) and the sd ratio with that noise
(`ks_with_lab_noise.std_ratio`), each against the targets fixed before the run
(docs/resolved-model.md, "Targets"): |gap| <= 0.5 lab sd, KS p > 0.05, sd ratio in [0.67, 1.5].
A half passes only where every component meets all three.

Exit status: 0 the table was printed (whatever it says), 2 bad input (a missing file, an
argument without HALF=, a JSON without the fields above), naming the file and field.
"""
import json
import sys

COMPONENTS = [("vout_x", "V_out^x [m/s]"), ("vout_y", "V_out^y [m/s]"), ("wout", "omega_out [rad/s]")]
GAP_MAX = 0.5  # lab sd
KS_P_MIN = 0.05
RATIO = (0.67, 1.5)


def fail(message):
    print(f"verification-table.py: {message}", file=sys.stderr)
    sys.exit(2)


def field(doc, path, source):
    node = doc
    for key in path:
        if not isinstance(node, dict) or key not in node:
            fail(f"{source}: no field {'.'.join(path)}")
        node = node[key]
    if not isinstance(node, (int, float)):
        fail(f"{source}: field {'.'.join(path)} is not a number")
    return float(node)


def mark(ok):
    return "pass" if ok else "**fail**"


def main(argv):
    if not argv or any(a in ("-h", "--help") for a in argv):
        print(__doc__.strip())
        sys.exit(0 if argv else 2)
    rows, verdicts = [], []
    for arg in argv:
        half, sep, path = arg.partition("=")
        if not sep or not half or not path:
            fail(f"argument '{arg}': expected HALF=CHECK.json")
        try:
            with open(path) as f:
                doc = json.load(f)
        except OSError as e:
            fail(f"{path}: {e.strerror}")
        except json.JSONDecodeError as e:
            fail(f"{path}: line {e.lineno}: not JSON ({e.msg})")
        passed = True
        for key, label in COMPONENTS:
            g = ["gap_to_lab", key]
            lab_mean = field(doc, g + ["lab_mean"], path)
            lab_sd = field(doc, g + ["lab_std"], path)
            dem_mean = field(doc, g + ["dem_mean"], path)
            gap = field(doc, g + ["difference_in_lab_std"], path)
            ks_p = field(doc, g + ["ks_with_lab_noise", "median_p"], path)
            ratio = field(doc, g + ["ks_with_lab_noise", "std_ratio"], path)
            ok_gap, ok_ks = abs(gap) <= GAP_MAX, ks_p > KS_P_MIN
            ok_ratio = RATIO[0] <= ratio <= RATIO[1]
            passed = passed and ok_gap and ok_ks and ok_ratio
            rows.append(f"| {half} | {label} | {lab_mean:.3f} +- {lab_sd:.3f} | {dem_mean:.3f} "
                        f"| {gap:+.2f} ({mark(ok_gap)}) | {ks_p:.3f} ({mark(ok_ks)}) "
                        f"| {ratio:.2f} ({mark(ok_ratio)}) |")
        verdicts.append(f"{half}: {'meets every target' if passed else 'misses a target'}")
    # Printed only once every file has been read: bad input leaves no partial table.
    print("| half | component | lab mean +- sd | resolved mean | gap [lab sd] | KS median p (noise) "
          "| sd ratio (noise) |")
    print("| :-- | :-- | --: | --: | --: | --: | --: |")
    print("\n".join(rows))
    print()
    print("; ".join(verdicts) + ".")


if __name__ == "__main__":
    main(sys.argv[1:])
