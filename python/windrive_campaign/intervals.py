"""The interval a mean over n seeds can expect: Student's t with the scatter measured over every seed at hand.

Used where a page says how many seeds an accuracy needs (seeds.py, paper_doc.py). A percentile bootstrap
over the first few seeds is no guide there: over 3 seeds it has 10 distinct resamples and comes out far
too narrow; with t and the scatter of all N seeds the half-width falls smoothly as t(n − 1)/√n.
"""

from __future__ import annotations

import math

import numpy as np
import scipy.stats

CONFIDENCE = 0.95


def half_width(x, n: int, confidence: float = CONFIDENCE) -> float:
    """The relative half-width of the `confidence` interval of the mean of n seeds' values whose scatter
    is that of x: t(½ + confidence/2, n − 1) · s / √n / x̄, s the standard deviation of all of x."""
    x = np.asarray(x, dtype=float)
    if n < 2 or len(x) < 2:
        return math.nan
    t = scipy.stats.t.ppf(0.5 + confidence / 2.0, n - 1)
    return float(t * np.std(x, ddof=1) / math.sqrt(n) / np.mean(x))


def seeds_needed(x, accuracy: float, limit: int = 10_000) -> int:
    """The fewest seeds (at least 2) whose interval (half_width) is within ±accuracy of the mean; `limit`
    when even that many are not enough. The search starts where the normal quantile z ≤ t would first
    allow it, (z·s/x̄/accuracy)², since no fewer seeds can reach the accuracy: the same answer as from 2."""
    x = np.asarray(x, dtype=float)
    z = scipy.stats.norm.ppf(0.5 + CONFIDENCE / 2.0)
    cv = np.std(x, ddof=1) / np.mean(x) if len(x) >= 2 else math.nan
    start = int(max(2.0, math.floor((z * cv / accuracy) ** 2))) if math.isfinite(cv) else 2
    for n in range(min(start, limit), limit + 1):
        if half_width(x, n) <= accuracy:
            return n
    return limit
