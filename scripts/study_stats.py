"""Rates with intervals for the study scripts (scripts/*-study.sh, power-calibration.sh).

Wilson (1927) score interval for a binomial proportion, J. Amer. Statist. Assoc. 22:209: the
interval every study table reports beside a rate.
"""
import math


def wilson(k, n, z=1.96):
    """(rate, lower, upper) of k successes in n trials at the two-sided level of z."""
    p = k / n
    d = 1 + z * z / n
    c = (p + z * z / (2 * n)) / d
    h = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / d
    return p, max(0.0, c - h), min(1.0, c + h)


def wilson_text(k, n, digits=3):
    """'k/n = rate [lower, upper]' (digits decimals), or 'k/n' when n is 0."""
    if n == 0:
        return "%d/%d" % (k, n)
    p, lo, hi = wilson(k, n)
    f = "%%.%df" % digits
    return ("%d/%d = " + f + " [" + f + ", " + f + "]") % (k, n, p, lo, hi)


def cells(rows, *columns):
    """The rows grouped by the values of `columns`, in order of first appearance:
    a list of (key tuple, rows)."""
    groups = {}
    for r in rows:
        groups.setdefault(tuple(r[c] for c in columns), []).append(r)
    return list(groups.items())
