"""The wind climate's weights of DLC 1.2 bins and the IEC normal turbulence model.

Bins: the simulated speeds are cut_in, cut_in + w, cut_in + 2w, … (w = bin_width); bin j covers
[v_j − w/2, v_j + w/2] clipped to [cut_in, cut_out], so the bins tile cut-in to cut-out exactly and their
probabilities add up to the hub-height wind lying between cut-in and cut-out, F(cut_out) − F(cut_in). A
last bin cut short by cut_out is simulated at cut_out, never above it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

# 8760 h a year, as `windrive life` (src/analysis/fatigue/lifetime.rs) and thesis Table 7.1 count hours
HOURS_PER_YEAR = 8760.0

# IEC 61400-1 ed. 3 Table 1: reference turbulence intensity at 15 m/s per turbulence class
IREF = {"A": 0.16, "B": 0.14, "C": 0.12}


@dataclass(frozen=True)
class WindBin:
    speed: float  # simulated mean hub-height wind speed, m/s
    lo: float
    hi: float
    probability: float  # of the hub-height wind lying in [lo, hi]


def weibull_cdf(v: float, k: float, a: float) -> float:
    return 1.0 - math.exp(-((v / a) ** k)) if v > 0 else 0.0


def ntm_turbulence_intensity(speed: float, turbulence_class: str) -> float:
    """IEC 61400-1 ed. 3 normal turbulence model: σ1 = I_ref·(0.75·V_hub + 5.6), TI = σ1 / V_hub."""
    return IREF[turbulence_class] * (0.75 * speed + 5.6) / speed


def wind_bins(cut_in: float, cut_out: float, width: float, k: float, a: float) -> list[WindBin]:
    edges = [cut_in]
    e = cut_in + width / 2
    while e < cut_out - 1e-9 * width:  # no sliver bin from rounding
        edges.append(e)
        e += width
    edges.append(cut_out)
    bins = []
    for j, (lo, hi) in enumerate(zip(edges, edges[1:])):
        speed = min(cut_in + j * width, cut_out)
        bins.append(WindBin(speed, lo, hi, weibull_cdf(hi, k, a) - weibull_cdf(lo, k, a)))
    return bins
