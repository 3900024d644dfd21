"""Rates and differences with intervals for the study scripts (scripts/*-study.sh,
power-calibration.sh, rim-cross-shape.sh, body-id-check.sh).

Wilson (1927) score interval for a binomial proportion, J. Amer. Statist. Assoc. 22:209: the
interval every study table reports beside a rate. Student's t interval of a mean paired
difference, its quantile from the t distribution's CDF (the regularized incomplete beta function
by its continued fraction, Press et al., Numerical Recipes, 3rd ed., section 6.4), inverted by
bisection: no table.
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


def _betacf(a, b, x):
    """Continued fraction of the incomplete beta function (modified Lentz)."""
    tiny, c, d = 1e-300, 1.0, 1.0 - (a + b) * x / (a + 1)
    d = 1.0 / (d if abs(d) > tiny else tiny)
    h = d
    for m in range(1, 300):
        for num in (m * (b - m) * x / ((a + 2 * m - 1) * (a + 2 * m)),
                    -(a + m) * (a + b + m) * x / ((a + 2 * m) * (a + 2 * m + 1))):
            d = 1.0 + num * d
            d = 1.0 / (d if abs(d) > tiny else tiny)
            c = 1.0 + num / c
            c = c if abs(c) > tiny else tiny
            h *= d * c
        if abs(d * c - 1.0) < 1e-15:
            break
    return h


def _betai(a, b, x):
    """Regularized incomplete beta I_x(a, b)."""
    if x <= 0.0:
        return 0.0
    if x >= 1.0:
        return 1.0
    lbt = math.lgamma(a + b) - math.lgamma(a) - math.lgamma(b) + a * math.log(x) + b * math.log(1 - x)
    if x < (a + 1) / (a + b + 2):
        return math.exp(lbt) * _betacf(a, b, x) / a
    return 1.0 - math.exp(lbt) * _betacf(b, a, 1 - x) / b


def student_t_cdf(t, dof):
    """P(T <= t) for Student's t with dof degrees of freedom."""
    tail = 0.5 * _betai(0.5 * dof, 0.5, dof / (dof + t * t))
    return 1.0 - tail if t > 0 else tail


def student_t_quantile(p, dof):
    """The p quantile (0.5 < p < 1) of Student's t with dof degrees of freedom, by bisection."""
    lo, hi = 0.0, 1.0
    while student_t_cdf(hi, dof) < p:
        hi *= 2
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if student_t_cdf(mid, dof) < p else (lo, mid)
    return 0.5 * (lo + hi)


def paired_t(diffs, level=0.95):
    """(mean, lower, upper) of the mean of paired differences, Student's t interval at `level`;
    needs at least 2 differences."""
    n = len(diffs)
    mean = sum(diffs) / n
    sd = math.sqrt(sum((d - mean) ** 2 for d in diffs) / (n - 1))
    h = student_t_quantile(0.5 + level / 2, n - 1) * sd / math.sqrt(n)
    return mean, mean - h, mean + h
