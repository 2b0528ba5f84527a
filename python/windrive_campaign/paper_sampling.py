"""What the wind's sampling changes: the paper's grid run twice, once with the blades sampling a full field
(3P, shear, the turbulence across the disc) and once with one rotor-averaged longitudinal series per
case, compared cell by cell (issue 32 §1: "report what 3P and full fields change in the drivetrain's
DELs against the rotor-averaged series").

The two runs draw different fields (a full field cannot be reduced to the series' phases), so a cell's
comparison is of its seed means: the ratio of the means with a 95 % percentile-bootstrap interval that
resamples each run's seeds on its own (paper.py's generator and draws, keyed by the cell).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pandas as pd

from . import paper

SAMPLING = f"param.{paper.ROTOR}.wind_sampling"
BLADES = "blades"
# what a drivetrain engineer reads first: the LSS torque's DEL, then the damage of the ring's bending
# (the first stage's ring gear, r1) and the sun's contact (s1), then the rotor power's standard deviation
QUANTITIES = (
    ("LSS torque DEL (m = 6)", "torsional.lss_torque.del_m6"),
    ("r1 bending damage", "gear.r1.root_day"),
    ("s1 contacting damage", "gear.s1.flank_day"),
    ("power standard deviation", "rotor.aerodynamic_power.std"),
)


def sampling_of(t: pd.DataFrame) -> str:
    """`blades` when every case sampled a full field, else `rotor_average` (the FMU's default, and what a
    table without the column ran)."""
    if SAMPLING in t and len(t) and t[SAMPLING].astype(str).eq(BLADES).all():
        return BLADES
    return "rotor_average"


def _by_cell(t: pd.DataFrame) -> dict[tuple[float, float], pd.DataFrame]:
    return {(float(v), float(ti)): g for (v, ti), g in paper.placed(t).groupby(["v", "ti"])}


@dataclass
class Ratio:
    blades: float  # the cell's mean over seeds, blades
    averaged: float  # and rotor-averaged
    ratio: float  # blades / averaged
    lo: float  # its 95 % interval (NaN with fewer than 2 seeds on either side)
    hi: float
    seeds: tuple[int, int]


def _ratio(a: np.ndarray, b: np.ndarray, key: tuple[float, ...]) -> Ratio:
    ma, mb = float(a.mean()), float(b.mean())
    ratio = ma / mb if mb > 0 else math.nan
    lo = hi = math.nan
    if len(a) >= 2 and len(b) >= 2 and mb > 0:
        rng = paper._rng(*key)
        da = paper.bootstrap_means(a[:, None], rng)[:, 0]
        db = paper.bootstrap_means(b[:, None], rng)[:, 0]
        with np.errstate(divide="ignore", invalid="ignore"):
            low, high = paper._percentiles((da / db)[:, None])
        lo, hi = float(low[0]), float(high[0])
    return Ratio(ma, mb, ratio, lo, hi, (len(a), len(b)))


def compare(blades: pd.DataFrame, averaged: pd.DataFrame) -> pd.DataFrame:
    """Per cell both runs hold and per quantity both tables have: the ratio blades / rotor-averaged of the
    seed means with its interval. Index (wind_speed, ti_pct, quantity)."""
    a, b = _by_cell(blades), _by_cell(averaged)
    rows = []
    for key in sorted(set(a) & set(b)):
        for q, (name, col) in enumerate(QUANTITIES):
            if col not in a[key] or col not in b[key]:
                continue
            xa = a[key][col].to_numpy(dtype=float)
            xb = b[key][col].to_numpy(dtype=float)
            xa, xb = xa[np.isfinite(xa)], xb[np.isfinite(xb)]
            if not len(xa) or not len(xb):
                continue
            r = _ratio(xa, xb, (*key, 32.0 + q))
            rows.append({"wind_speed": key[0], "ti_pct": key[1], "quantity": name, **r.__dict__})
    if not rows:
        return pd.DataFrame()
    return pd.DataFrame(rows).set_index(["wind_speed", "ti_pct", "quantity"]).sort_index()


def summary(cmp: pd.DataFrame) -> pd.DataFrame:
    """Per quantity over the turbulent cells: how many, the median and range of the ratio, and in how many
    cells the interval lies wholly above 1 or wholly below it."""
    turb = cmp[cmp.index.get_level_values("ti_pct") > 0]
    rows = []
    for name, _ in QUANTITIES:
        if name not in turb.index.get_level_values("quantity"):
            continue
        g = turb.xs(name, level="quantity")
        rows.append({"quantity": name, "cells": len(g), "median": float(g.ratio.median()),
                     "min": float(g.ratio.min()), "max": float(g.ratio.max()),
                     "above": int((g.lo > 1.0).sum()), "below": int((g.hi < 1.0).sum())})  # fmt: skip
    return pd.DataFrame(rows).set_index("quantity")
