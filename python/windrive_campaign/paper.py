"""The paper's comparison (its Tables 6 and 7; paper_data.py) from a campaign's table: our gear
damage per cell of wind speed × turbulence intensity, both tables side by side, and the shapes the paper
draws its conclusions from. Pure computation on the table; paper_report.py writes and prints it.

- A cell is a mean wind speed and a TI in percent; steady wind (`rotor.turbulence = "none"`) is TI 0, as
  in the paper's Table 7. A turbulent case with TI 0 is not steady: the rotor FMU reads TI 0 as its IEC
  class default, so such a case is left out and named. Our damage per cell is the mean over its cases
  (the seeds); only finished grid cases count.
- Every η of ours carries a 95 % percentile-bootstrap interval over its cell's seeds (BOOTSTRAP_DRAWS
  draws of the cell's cases with replacement, the steady reference fixed: it has one case and no seed).
  The draws come from a generator seeded by BOOTSTRAP_SEED and the cell's coordinates, so the intervals
  are the same on every run and machine, and adding a cell changes no other cell's interval.
- η = (D − D_const,rated) / D_const,rated × 100 % (the paper's Eq. 5), D_const,rated the steady 11.5 m/s
  cell. The shapes work on D / D_const,rated = 1 + η/100, so the paper's Table 7 goes through the same
  functions as ours.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from . import paper_data as data
from .errors import CampaignError

ROTOR = "rotor"  # the component whose parameters set the wind (scenes/p-normal)
WIND = f"param.{ROTOR}.wind_speed"
TI = f"param.{ROTOR}.turbulence_intensity"
TURBULENCE = f"param.{ROTOR}.turbulence"
STEADY = "none"

FLAT_SPEEDS = (14.0, 20.0)  # (a): the paper's "almost constant when mean wind speed is higher than 14 m/s"
STEADY_ABOVE = 14.0  # (b): "beyond 13 m/s, the damage caused by steady wind is higher"; cells at 14 m/s and up


def damage_column(kind: str, tooth: str) -> str:
    return f"gear.{tooth}.{data.DAMAGE_COLUMN[kind]}"


def label(kind: str, tooth: str) -> str:
    return f"{tooth} {kind}"


TABLE7_LABELS = [label(k, t) for k, t in data.TABLE7_COLUMNS]


def _key(x: float) -> float:
    """Cell coordinates rounded so that 0.14 × 100 and 14.0 meet."""
    return round(float(x), 6)


def placed(t: pd.DataFrame) -> pd.DataFrame:
    """The finished grid cases with their cell: `v` (wind speed) and `ti` (TI in %, 0 for steady wind),
    keyed as `_key` rounds them. For tables that hold the wind columns (`cells` also names the cases
    it cannot place)."""
    ok = t[(t.status == "ok") & (t.group == "grid")].copy()
    steady = ok[TURBULENCE].eq(STEADY).fillna(False).astype(bool)
    ok["v"] = ok[WIND].astype(float).map(_key)
    ok["ti"] = (ok[TI].astype(float) * 100.0).where(~steady, 0.0).map(_key)
    return ok


@dataclass
class Cells:
    mean: pd.DataFrame  # index (wind_speed, ti_pct), columns every gear damage column: the mean over cases
    count: pd.Series  # cases per cell
    used: int
    left_out: dict[str, list[str]] = field(default_factory=dict)  # why -> case names
    cases: pd.DataFrame | None = None  # every case placed: index (wind_speed, ti_pct), its gear damage columns


def cells(t: pd.DataFrame) -> Cells:
    """Our finished grid cases placed in cells, averaged per cell."""
    gear_columns = [c for c in t.columns if c.startswith("gear.") and c.endswith((".root_day", ".flank_day"))]
    if not gear_columns:
        raise CampaignError("no gear damage columns (gear.<tooth>.root_day, .flank_day): "
                            "run the campaign with [gears] table = \"P\" (docs/CAMPAIGNS.md)")  # fmt: skip
    needed = {damage_column(r[2], r[3]) for r in data.TABLE6}
    needed |= {damage_column(kind, tooth) for kind, tooth in data.TABLE7_COLUMNS}
    absent = sorted(needed - set(gear_columns))
    if absent:
        raise CampaignError(f"no column {', '.join(absent)}: the paper's teeth are those of [gears] table = \"P\"")
    if WIND not in t.columns:
        raise CampaignError(f"no column {WIND}: the grid must set the wind speed")
    left_out: dict[str, list[str]] = {}

    def leave(why: str, rows: pd.DataFrame):
        if len(rows):
            left_out.setdefault(why, []).extend(rows["name"])

    for status, rows in t[t.status != "ok"].groupby("status"):
        leave(str(status), rows)
    leave("not a grid case", t[(t.status == "ok") & (t.group != "grid")])
    ok = t[(t.status == "ok") & (t.group == "grid")].copy()
    steady = pd.Series(False, index=ok.index)  # without the column every case has the scene's turbulence
    if TURBULENCE in ok:
        steady = ok[TURBULENCE].eq(STEADY).fillna(False).astype(bool)
    ti = ok[TI].astype(float) * 100.0 if TI in ok else pd.Series(math.nan, index=ok.index)
    ok["wind_speed_"] = ok[WIND].astype(float).map(_key)
    ok["ti_pct"] = ti.where(~steady, 0.0).map(lambda x: _key(x) if x == x else x)
    leave("no rotor.wind_speed", ok[ok.wind_speed_.isna()])
    leave("turbulent without rotor.turbulence_intensity", ok[~steady & ok.ti_pct.isna()])
    leave("turbulent with TI 0 (the IEC class default, not steady wind)", ok[~steady & (ok.ti_pct == 0.0)])
    placed = ok[ok.wind_speed_.notna() & ok.ti_pct.notna() & (steady | (ok.ti_pct > 0.0))]
    grouped = placed.groupby(["wind_speed_", "ti_pct"])
    mean = grouped[gear_columns].mean()
    mean.index.names = ["wind_speed", "ti_pct"]
    count = grouped.size()
    count.index.names = ["wind_speed", "ti_pct"]
    cases = placed.set_index(["wind_speed_", "ti_pct"])[gear_columns]
    cases.index.names = ["wind_speed", "ti_pct"]
    return Cells(mean=mean, count=count, used=len(placed), left_out=left_out, cases=cases)


def const_rated(c: Cells) -> pd.Series:
    """D_const,rated of every damage column: the steady cell at the rated 11.5 m/s."""
    key = (_key(data.RATED_SPEED), 0.0)
    if key not in c.mean.index:
        raise CampaignError(
            f"no finished steady {data.RATED_SPEED:g} m/s case ({TURBULENCE} = \"{STEADY}\", "
            f"{WIND} = {data.RATED_SPEED:g}): η (the paper's Eq. 5) is relative to its damage"
        )
    return c.mean.loc[key]


def relative(c: Cells, dc: pd.Series) -> pd.DataFrame:
    """D / D_const,rated of the six Table 7 damages per cell."""
    out = pd.DataFrame(index=c.mean.index)
    for kind, tooth in data.TABLE7_COLUMNS:
        col = damage_column(kind, tooth)
        out[label(kind, tooth)] = c.mean[col] / dc[col] if dc[col] > 0 else math.nan
    return out


def paper_relative() -> pd.DataFrame:
    """The paper's Table 7 as D / D_const,rated = 1 + η/100."""
    rows = {(_key(v), _key(ti)): [1.0 + e / 100.0 for e in etas] for v, by_ti in data.TABLE7.items()
            for ti, etas in by_ti.items()}  # fmt: skip
    out = pd.DataFrame.from_dict(rows, orient="index", columns=TABLE7_LABELS)
    out.index = pd.MultiIndex.from_tuples(out.index, names=["wind_speed", "ti_pct"])
    return out.sort_index()


def paper_cells() -> list[tuple[float, float]]:
    return [(_key(v), _key(ti)) for v, by_ti in data.TABLE7.items() for ti in by_ti]


# ---------------------------------------------------------------------------------------------------
# the two tables


def table6(c: Cells) -> pd.DataFrame:
    """The paper's Table 6 beside ours: damage per day (absolute, not ×1e-6), ours/paper, each gear's
    rank within its stage and kind of damage (1 = most damaged; the paper's "-" ranks last), and the
    factor on our stresses that would give the paper's damage: (paper/ours)^(1/k), k the rating's exponent
    below the S-N knee (paper_data.damage_exponent). Exact while the raised stresses stay below the knee;
    above it the curve is flatter, so the factor is then a lower bound."""
    rows = []
    for stage, gear, damage, tooth, values in data.TABLE6:
        col = damage_column(damage, tooth)
        row = {"stage": stage, "gear": gear, "damage": damage, "tooth": tooth, "column": col}
        for speed, paper in zip(data.TABLE6_SPEEDS, values):
            key = (_key(speed), _key(data.TABLE6_TI_PCT))
            ours = float(c.mean.at[key, col]) if key in c.mean.index and col in c.mean else math.nan
            theirs = math.nan if paper is None else paper * data.TABLE6_UNIT
            row[f"paper_{speed:g}"] = theirs
            row[f"ours_{speed:g}"] = ours
            row[f"ratio_{speed:g}"] = ours / theirs if theirs == theirs else math.nan
            exponent = data.damage_exponent(damage, gear)
            row[f"factor_{speed:g}"] = (theirs / ours) ** (1.0 / exponent) if ours > 0 and theirs > 0 else math.nan
        rows.append(row)
    t = pd.DataFrame(rows)
    by = t.groupby(["stage", "damage"], sort=False)
    for speed in data.TABLE6_SPEEDS:
        s = f"{speed:g}"
        t[f"rank_paper_{s}"] = by[f"paper_{s}"].transform(lambda x: x.fillna(0.0).rank(ascending=False, method="min"))
        t[f"rank_ours_{s}"] = by[f"ours_{s}"].transform(lambda x: x.rank(ascending=False, method="min"))
    return t


def table7(rel: pd.DataFrame, ci: pd.DataFrame | None = None) -> pd.DataFrame:
    """The paper's Table 7 rows with the paper's η, ours and ours − paper (percentage points); with `ci`
    (eta_intervals) also our interval, `lo` and `hi` in %, and whether the paper's value lies inside it
    (1 or 0; empty where the cell has no interval: one case, or steady wind)."""
    rows = []
    for v, by_ti in data.TABLE7.items():
        for ti, etas in by_ti.items():
            key = (_key(v), _key(ti))
            row = {"wind_speed": v, "ti_pct": ti}
            if ci is not None:
                row["seeds"] = int(ci.at[key, "seeds"]) if key in ci.index else 0
            for name, paper in zip(TABLE7_LABELS, etas):
                ours = (float(rel.at[key, name]) - 1.0) * 100.0 if key in rel.index else math.nan
                row[f"{name} paper"] = paper
                row[f"{name} ours"] = ours
                row[f"{name} diff"] = ours - paper
                if ci is not None:
                    lo = float(ci.at[key, f"{name} lo"]) if key in ci.index else math.nan
                    hi = float(ci.at[key, f"{name} hi"]) if key in ci.index else math.nan
                    row[f"{name} lo"], row[f"{name} hi"] = lo, hi
                    row[f"{name} inside"] = float(lo <= paper <= hi) if lo == lo else math.nan
            rows.append(row)
    return pd.DataFrame(rows)


# ---------------------------------------------------------------------------------------------------
# intervals over seeds

BOOTSTRAP_SEED = 32  # issue 32; fixed so that every run and machine prints the same intervals
BOOTSTRAP_DRAWS = 4000  # the 2.5 % point then rests on 100 draws
CONFIDENCE = 0.95


def _rng(*key: float) -> np.random.Generator:
    """The bootstrap's generator for one cell (or pair of cells): BOOTSTRAP_SEED and the coordinates in
    thousandths, so a cell's draws do not depend on which other cells the campaign has."""
    return np.random.default_rng([BOOTSTRAP_SEED, *(int(round(k * 1000)) for k in key)])


def bootstrap_means(x: np.ndarray, rng: np.random.Generator, draws: int = BOOTSTRAP_DRAWS) -> np.ndarray:
    """Means of `draws` resamples with replacement of the rows of x (cases × columns): draws × columns."""
    n = x.shape[0]
    return x[rng.integers(0, n, size=(draws, n))].mean(axis=1)


def _percentiles(draws: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    tail = (1.0 - CONFIDENCE) / 2.0 * 100.0
    return np.percentile(draws, tail, axis=0), np.percentile(draws, 100.0 - tail, axis=0)


def _relative_cases(c: Cells, dc: pd.Series, key) -> np.ndarray:
    """The cell's cases as D / D_const,rated of the six Table 7 damages: cases × 6."""
    rows = c.cases.loc[[key]]
    cols = [damage_column(k, t) for k, t in data.TABLE7_COLUMNS]
    scale = np.array([1.0 / dc[col] if dc[col] > 0 else math.nan for col in cols])
    return rows[cols].to_numpy(dtype=float) * scale


def eta_intervals(c: Cells, dc: pd.Series) -> pd.DataFrame:
    """Per cell: the number of seeds and, for each Table 7 damage, the bootstrap interval of η in %
    (`<label> lo`, `<label> hi`); NaN for a cell of one case, whose seeds cannot be resampled."""
    rows = {}
    for key, n in c.count.items():
        row: dict[str, float] = {"seeds": int(n)}
        if n >= 2:
            lo, hi = _percentiles(bootstrap_means(_relative_cases(c, dc, key), _rng(*key)))
        else:
            lo = hi = np.full(len(TABLE7_LABELS), math.nan)
        for i, name in enumerate(TABLE7_LABELS):
            row[f"{name} lo"], row[f"{name} hi"] = (lo[i] - 1.0) * 100.0, (hi[i] - 1.0) * 100.0
        rows[key] = row
    out = pd.DataFrame.from_dict(rows, orient="index")
    out.index = pd.MultiIndex.from_tuples(out.index, names=["wind_speed", "ti_pct"])
    return out.sort_index()


def _sign(lo: float, hi: float) -> str:
    """+ or − when the whole interval has that sign, ± when it holds zero, - without an interval."""
    if lo != lo:
        return "-"
    return "+" if lo > 0 else "−" if hi < 0 else "±"


def verdicts(t7: pd.DataFrame, c: Cells, dc: pd.Series) -> dict:
    """What the intervals say about the paper's Table 7:

    - `inside`: per damage, of the paper's turbulent cells where we have an interval, how many paper
      values lie inside ours;
    - `sign_at_rated`: per damage and TI at the rated 11.5 m/s, the paper's η, ours with its interval and
      the sign the interval shows (+, − or ± when it holds zero);
    - `ti_trend`: above rated (14-20 m/s), per damage, D(TI 24) / D(TI 14) ours with a bootstrap interval
      (each cell's seeds drawn again on their own) against the paper's (1 + η24) / (1 + η14), and
      Spearman's rank correlation of η with TI at each speed, ours (cell means) and the paper's."""
    turbulent = t7[t7.ti_pct > 0]
    inside = {}
    for name in TABLE7_LABELS:
        flags = turbulent[f"{name} inside"].dropna() if f"{name} inside" in turbulent else pd.Series(dtype=float)
        inside[name] = {"inside": int(flags.sum()), "cells": int(len(flags))}
    total = {"inside": sum(v["inside"] for v in inside.values()), "cells": sum(v["cells"] for v in inside.values())}
    rated = turbulent[turbulent.wind_speed == data.RATED_SPEED]
    sign = {}
    for name in TABLE7_LABELS:
        sign[name] = [
            {
                "ti_pct": float(r.ti_pct),
                "paper": float(r[f"{name} paper"]),
                "ours": float(r[f"{name} ours"]),
                "lo": float(r[f"{name} lo"]),
                "hi": float(r[f"{name} hi"]),
                "sign": _sign(float(r[f"{name} lo"]), float(r[f"{name} hi"])),
            }
            for _, r in rated.iterrows()
        ]
    counts = {s: sum(x["sign"] == s for v in sign.values() for x in v) for s in ("+", "−", "±", "-")}
    trend = []
    lo_ti, hi_ti = 14.0, 24.0
    for v in sorted(data.TABLE7):
        if v < FLAT_SPEEDS[0]:
            continue
        a, b = (_key(v), _key(lo_ti)), (_key(v), _key(hi_ti))
        if a not in c.count.index or b not in c.count.index:
            continue
        xa, xb = _relative_cases(c, dc, a), _relative_cases(c, dc, b)
        ratio = xb.mean(axis=0) / xa.mean(axis=0)
        rlo = rhi = np.full(len(TABLE7_LABELS), math.nan)
        if len(xa) >= 2 and len(xb) >= 2:
            rlo, rhi = _percentiles(bootstrap_means(xb, _rng(v, hi_ti, 1)) / bootstrap_means(xa, _rng(v, lo_ti, 1)))
        paper_row = data.TABLE7[v]
        by_ti = turbulent[turbulent.wind_speed == v].sort_values("ti_pct")
        for i, name in enumerate(TABLE7_LABELS):
            theirs = (1.0 + paper_row[hi_ti][i] / 100.0) / (1.0 + paper_row[lo_ti][i] / 100.0)
            ours_eta = by_ti[f"{name} ours"].to_numpy(dtype=float)
            trend.append({
                "wind_speed": v,
                "damage": name,
                "ours": float(ratio[i]),
                "lo": float(rlo[i]),
                "hi": float(rhi[i]),
                "paper": float(theirs),
                "paper_inside": bool(rlo[i] <= theirs <= rhi[i]) if rlo[i] == rlo[i] else None,
                "spearman_ours": _spearman(by_ti.ti_pct.to_numpy(dtype=float), ours_eta),
                "spearman_paper": _spearman(by_ti.ti_pct.to_numpy(dtype=float),
                                            by_ti[f"{name} paper"].to_numpy(dtype=float)),  # fmt: skip
            })
    return {"inside": inside, "inside_total": total, "sign_at_rated": sign, "sign_counts": counts, "ti_trend": trend}


def _spearman(x: np.ndarray, y: np.ndarray) -> float:
    """Spearman's rank correlation (average ranks for ties) of the finite pairs; NaN below 3 pairs."""
    ok = np.isfinite(x) & np.isfinite(y)
    if ok.sum() < 3:
        return math.nan
    rx, ry = pd.Series(x[ok]).rank().to_numpy(), pd.Series(y[ok]).rank().to_numpy()
    if rx.std() == 0 or ry.std() == 0:
        return math.nan
    return float(np.corrcoef(rx, ry)[0, 1])


def missing_cells(c: Cells) -> list[tuple[float, float]]:
    """The paper's Table 7 cells (which include Table 6's) that the campaign has no case for."""
    return [k for k in paper_cells() if k not in c.mean.index]


# ---------------------------------------------------------------------------------------------------
# the shapes (a)-(c), on D / D_const,rated per cell, for ours and the paper's alike


def _turbulent(rel: pd.DataFrame) -> pd.DataFrame:
    return rel[rel.index.get_level_values("ti_pct") > 0.0]


def flatness(rel: pd.DataFrame, lo: float = FLAT_SPEEDS[0], hi: float = FLAT_SPEEDS[1]) -> dict:
    """(a) Per damage: the TI-averaged damage (mean over the turbulent cells of each speed) at every speed
    from lo to hi, and its max / min: 1 is perfectly flat."""
    turb = _turbulent(rel)
    v = turb.index.get_level_values("wind_speed")
    avg = turb[(v >= lo) & (v <= hi)].groupby(level="wind_speed").mean()
    out = {}
    for name in rel.columns:
        s = avg[name].dropna()
        out[name] = {
            "speeds": [float(x) for x in s.index],
            "ti_averaged": [float(x) for x in s],
            "max_over_min": float(s.max() / s.min()) if len(s) >= 2 else math.nan,
        }
    return out


def steady_above_turbulent(rel: pd.DataFrame, above: float = STEADY_ABOVE) -> dict:
    """(b) Per damage: of the turbulent cells at `above` m/s and faster that have a steady cell at their
    speed, how many are less damaging than it."""
    steady = rel[rel.index.get_level_values("ti_pct") == 0.0].droplevel("ti_pct")
    turb = _turbulent(rel)
    turb = turb[turb.index.get_level_values("wind_speed") >= above]
    out = {}
    for name in rel.columns:
        wins = total = 0
        for (v, _ti), d in turb[name].items():
            if v in steady.index and d == d and steady.at[v, name] == steady.at[v, name]:
                total += 1
                wins += bool(steady.at[v, name] > d)
        out[name] = {"steady_higher": wins, "cells": total, "fraction": wins / total if total else math.nan}
    return out


def speed_sensitivity(rel: pd.DataFrame) -> dict:
    """(c) Per damage: ∂D/∂V as linear finite differences between consecutive simulated speeds of the
    TI-averaged damage, in D_const,rated per m/s. Each difference averages over the turbulent TIs that
    both speeds have (the paper's 9 m/s row has TI 24 % only), so a missing cell does not pose as a
    slope. The peak is the interval with the largest difference."""
    turb = _turbulent(rel)
    speeds = sorted(set(turb.index.get_level_values("wind_speed")))
    out = {}
    for name in rel.columns:
        slopes = []
        for v0, v1 in zip(speeds, speeds[1:]):
            a = turb.xs(v0, level="wind_speed")[name].dropna()
            b = turb.xs(v1, level="wind_speed")[name].dropna()
            common = a.index.intersection(b.index)
            if len(common):
                slopes.append((v0, v1, float((b[common] - a[common]).mean() / (v1 - v0))))
        peak = max(slopes, key=lambda s: s[2]) if slopes else (math.nan, math.nan, math.nan)
        out[name] = {
            "slopes": [{"from": s[0], "to": s[1], "per_m_s": s[2]} for s in slopes],
            "peak_from": peak[0],
            "peak_to": peak[1],
            "peak_per_m_s": peak[2],
        }
    return out


def rankings(t6: pd.DataFrame) -> dict:
    """(d) The teeth ordered by damage, most damaged first, per speed and kind of damage, ours beside the
    paper's, and the share of pairs the two order alike (pairs the paper ties, its "-", and teeth we
    have no value for are not counted)."""
    out = {}
    for speed in data.TABLE6_SPEEDS:
        s = f"{speed:g}"
        for damage in ("bending", "pitting"):
            sub = t6[t6.damage == damage]
            paper = sub[f"paper_{s}"].fillna(0.0).to_numpy()
            ours = sub[f"ours_{s}"].to_numpy()
            teeth = list(sub.tooth)
            same = pairs = 0
            for i in range(len(teeth)):
                for j in range(i + 1, len(teeth)):
                    if paper[i] != paper[j] and np.isfinite(ours[i]) and np.isfinite(ours[j]) and ours[i] != ours[j]:
                        pairs += 1
                        same += (paper[i] > paper[j]) == (ours[i] > ours[j])
            out[f"{damage} {s} m/s"] = {
                "paper": [teeth[i] for i in np.argsort(-paper, kind="stable")],
                "ours": [teeth[i] for i in np.argsort(-np.nan_to_num(ours, nan=-np.inf), kind="stable")
                         if np.isfinite(ours[i])],  # fmt: skip
                "pairs_in_the_same_order": same,
                "pairs": pairs,
            }
    return out


def shapes(rel: pd.DataFrame) -> dict:
    return {
        "flat_above_14": flatness(rel),
        "steady_above_turbulent": steady_above_turbulent(rel),
        "speed_sensitivity": speed_sensitivity(rel),
    }


# ---------------------------------------------------------------------------------------------------
# Table 8 and the paper's own consistency


@dataclass
class Levels:
    """Table 8's rule made explicit: each damage's mean |η| over the cells of Table 7 (the paper's own
    numbers give its three levels in its order with it), each level the mean of its pair."""

    paper: pd.Series  # mean |η| in % per Table 7 label, from the paper's Table 7
    ours: pd.Series  # the same from our cell means, over the same cells
    ours_lo: pd.Series  # its 95 % interval (bootstrap of every turbulent cell's seeds at once)
    ours_hi: pd.Series
    paper_levels: np.ndarray  # per level (1, 2, 3) the mean of its pair, the paper's
    ours_levels: np.ndarray  # and ours
    # ours: level 1 over level 2 and level 2 over level 3, each (ratio, interval low, high)
    ratios: tuple[tuple[float, float, float], tuple[float, float, float]]


def _pair_means(per_label: np.ndarray) -> np.ndarray:
    """(…, 6) mean |η| per label -> (…, 3) per Table 8 level, in the levels' order."""
    idx = [[TABLE7_LABELS.index(label(k, t)) for k, t in pair] for pair in data.TABLE8.values()]
    return np.stack([per_label[..., i].mean(axis=-1) for i in idx], axis=-1)


def levels(c: Cells, dc: pd.Series, rel: pd.DataFrame) -> Levels:
    theirs = paper_relative()
    keys = [k for k in theirs.index if k in rel.index]
    paper_abs = (theirs.loc[keys] - 1.0).abs().mean() * 100.0
    ours_abs = (rel.loc[keys] - 1.0).abs().mean() * 100.0
    # every cell with seeds resampled in the same draw; the steady cells (one case) fixed
    draws = np.zeros((BOOTSTRAP_DRAWS, len(TABLE7_LABELS)))
    for key in keys:
        if c.count.get(key, 0) >= 2:
            draws += np.abs(bootstrap_means(_relative_cases(c, dc, key), _rng(*key, 8.0)) - 1.0)
        else:
            draws += np.abs(rel.loc[key].to_numpy(dtype=float) - 1.0)
    draws *= 100.0 / len(keys)
    lo, hi = _percentiles(draws)
    pairs = _pair_means(draws)
    ours_levels = _pair_means(ours_abs.to_numpy(dtype=float))
    ratios = []
    for a in (0, 1):
        r_lo, r_hi = _percentiles((pairs[:, a] / pairs[:, a + 1])[:, None])
        ratios.append((float(ours_levels[a] / ours_levels[a + 1]), float(r_lo[0]), float(r_hi[0])))
    return Levels(
        paper=paper_abs,
        ours=ours_abs,
        ours_lo=pd.Series(lo, index=TABLE7_LABELS),
        ours_hi=pd.Series(hi, index=TABLE7_LABELS),
        paper_levels=_pair_means(paper_abs.to_numpy(dtype=float)),
        ours_levels=ours_levels,
        ratios=(ratios[0], ratios[1]),
    )


def steady_spread() -> pd.DataFrame:
    """The paper's steady rows above rated, where the input torque is the rated torque at every speed and a
    gear's damage should not depend on the speed: per Table 7 damage the lowest and highest η (%) over them."""
    rows = {v: etas for v, by_ti in data.TABLE7.items() if v > data.RATED_SPEED for ti, etas in by_ti.items()
            if ti == 0.0}  # fmt: skip
    t = pd.DataFrame.from_dict(rows, orient="index", columns=TABLE7_LABELS)
    return pd.DataFrame({"speeds": len(t), "min": t.min(), "max": t.max(), "spread": t.max() - t.min()})


def text_grid_outside() -> tuple[list[float], list[float]]:
    """Table 7's wind speeds and TIs that the grid its text describes does not hold."""
    speeds = sorted({v for v in data.TABLE7})
    tis = sorted({ti for by_ti in data.TABLE7.values() for ti in by_ti if ti > 0})
    return ([v for v in speeds if v not in data.TEXT_SPEEDS], [ti for ti in tis if ti not in data.TEXT_TI_PCT])


# ---------------------------------------------------------------------------------------------------
# everything at once


@dataclass
class Comparison:
    cells: Cells
    const_rated: pd.Series  # D_const,rated per damage column (ours)
    table6: pd.DataFrame
    table7: pd.DataFrame
    relative: pd.DataFrame  # ours, D / D_const,rated for the Table 7 damages
    shapes_ours: dict
    shapes_paper: dict
    rankings: dict
    missing: list[tuple[float, float]]
    intervals: pd.DataFrame  # eta_intervals: seeds and η's bootstrap interval per cell
    verdicts: dict  # verdicts(): the paper's values inside ours, the sign at rated, the TI trend
    levels: Levels  # Table 8's rule on the paper's Table 7 and on ours


def compare(t: pd.DataFrame) -> Comparison:
    c = cells(t)
    dc = const_rated(c)
    rel = relative(c, dc)
    t6 = table6(c)
    ci = eta_intervals(c, dc)
    t7 = table7(rel, ci)
    return Comparison(
        cells=c,
        const_rated=dc,
        table6=t6,
        table7=t7,
        relative=rel,
        shapes_ours=shapes(rel),
        shapes_paper=shapes(paper_relative()),
        rankings=rankings(t6),
        missing=missing_cells(c),
        intervals=ci,
        verdicts=verdicts(t7, c, dc),
        levels=levels(c, dc, rel),
    )


def paper_const_rated() -> dict[str, float]:
    """The paper's D_const,rated as Table 6 implies it: its TI 14 % damage at 11.5 m/s over 1 + η/100 of
    the same cell in Table 7 (for the six Table 7 damages; Table 6's pitting is Table 7's contacting)."""
    out = {}
    eta = dict(zip(TABLE7_LABELS, data.TABLE7[data.RATED_SPEED][data.TABLE6_TI_PCT]))
    for kind, tooth in data.TABLE7_COLUMNS:
        t6_kind = "pitting" if kind == "contacting" else kind
        (values,) = [r[4] for r in data.TABLE6 if r[2] == t6_kind and r[3] == tooth]
        out[label(kind, tooth)] = values[0] * data.TABLE6_UNIT / (1.0 + eta[label(kind, tooth)] / 100.0)
    return out
