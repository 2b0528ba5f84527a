"""Statistics, damage-equivalent loads and load duration distributions of one case's series, after the
transient. The same definitions as `windrive del` and `windrive ldd` (src/analysis/fatigue/damage.rs, ldd.rs),
checked against them in tests/python/test_campaign.py:

- DEL_m = (Σ n_i S_i^m / N_eq)^(1/m), S_i the rainflow ranges (ASTM E1049-85, the `rainflow` package;
  half cycles count ½), N_eq = f_eq × (last − first time of the analysed window).
- LDD: each sample holds until the next (the last gets no time); bin i collects the seconds and the
  revolutions n_i = Σ t_j·|ω_j| / 2π of the samples whose load falls in it; loads outside [min, max]
  count in the end bins, as windrive's bins do.
"""

from __future__ import annotations

import math

import numpy as np
import pyarrow as pa
import pyarrow.csv as pacsv
import rainflow

from .schema import Channel


class AnalysisError(Exception):
    """The series cannot be analysed as asked (a channel missing, nothing after the transient)."""


def read_series(path: str, columns: list[str]) -> dict[str, np.ndarray]:
    """The time column and `columns` of a windrive CSV, as float arrays (pyarrow's reader: the CSV of a
    600 s case has 600 001 rows, which numpy.loadtxt takes seconds to parse)."""
    with open(path) as f:
        header = f.readline().rstrip("\n").split(",")
    missing = [c for c in columns if c not in header]
    if missing:
        raise AnalysisError(f"{', '.join(missing)} not in the series (its columns: {', '.join(header[1:])})")
    wanted = list(dict.fromkeys(["time", *columns]))
    # one thread: the workers already fill the cores, and a small file reads faster without a pool;
    # the types given: a third faster than pyarrow inferring them
    options = pacsv.ConvertOptions(include_columns=wanted, column_types={c: pa.float64() for c in wanted})
    try:
        table = pacsv.read_csv(path, read_options=pacsv.ReadOptions(use_threads=False), convert_options=options)
    except pa.ArrowInvalid as e:
        raise AnalysisError(f"{path}: {e}") from None
    return {c: table.column(c).to_numpy() for c in wanted}


def after_transient(series: dict[str, np.ndarray], transient: float) -> dict[str, np.ndarray]:
    keep = series["time"] >= transient
    if keep.sum() < 2:
        raise AnalysisError(f"fewer than two samples after the transient of {transient} s")
    return {k: v[keep] for k, v in series.items()}


def monotone_thinned(x: np.ndarray) -> np.ndarray:
    """x without the samples strictly inside a monotone run (x[i-1] < x[i] < x[i+1] or the reverse).
    `rainflow` finds the reversals in a Python loop over every sample, a third of the analysis of a
    1 kHz series; such samples are never reversals and dropping them leaves each reversal decision the
    same (the step before and after keeps its sign), so the cycles are the package's exactly (tested).
    The first two and the last samples stay: the package takes its first direction from x[1] − x[0] and
    treats a two-sample series differently from a longer one."""
    if len(x) < 4:
        return x
    d = np.diff(x)
    keep = np.ones(len(x), dtype=bool)
    keep[1:-1] = d[:-1] * d[1:] <= 0
    keep[:2] = True
    return x[keep]


def cycles(x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Rainflow ranges and counts (½ for a half cycle)."""
    found = [(r, n) for r, _mean, n, _i, _j in rainflow.extract_cycles(monotone_thinned(x).tolist())]
    if not found:
        return np.zeros(0), np.zeros(0)
    ranges, counts = np.array(found).T
    return ranges, counts


def damage_equivalent_loads(ranges, counts, slopes, n_eq: float) -> dict[float, float]:
    return {m: float((np.sum(counts * ranges**m) / n_eq) ** (1.0 / m)) for m in slopes}


def load_duration(time, load, speed, lo: float, hi: float, bins: int) -> tuple[np.ndarray, np.ndarray]:
    dt = np.diff(time)
    width = (hi - lo) / bins
    index = np.clip(np.floor((load[:-1] - lo) / width), 0, bins - 1).astype(int)
    seconds = np.bincount(index, weights=dt, minlength=bins)
    revolutions = np.bincount(index, weights=dt * np.abs(speed[:-1]) / (2.0 * math.pi), minlength=bins)
    return seconds, revolutions


def needed_columns(channels: tuple[Channel, ...]) -> list[str]:
    cols = [c.name for c in channels] + [c.ldd.speed for c in channels if c.ldd]
    return list(dict.fromkeys(cols))


def analyse(series: dict[str, np.ndarray], channels: tuple[Channel, ...], feq: float, transient: float) -> dict:
    """One flat dict per case: `<channel>.mean/.std/.min/.max`, `.del_m<m>` per slope, and with an LDD
    `.ldd_s` and `.ldd_rev` (lists, one value per bin), plus the analysed duration."""
    s = after_transient(series, transient)
    t = s["time"]
    duration = float(t[-1] - t[0])
    out: dict = {"analysed_s": duration}
    for c in channels:
        x = s[c.name]
        out[f"{c.name}.mean"] = float(np.mean(x))
        out[f"{c.name}.std"] = float(np.std(x))
        out[f"{c.name}.min"] = float(np.min(x))
        out[f"{c.name}.max"] = float(np.max(x))
        if c.m:
            ranges, counts = cycles(x)
            for m, d in damage_equivalent_loads(ranges, counts, c.m, feq * duration).items():
                out[f"{c.name}.del_m{m:g}"] = d
        if c.ldd:
            sec, rev = load_duration(t, x, s[c.ldd.speed], c.ldd.min, c.ldd.max, c.ldd.bins)
            out[f"{c.name}.ldd_s"] = sec.tolist()
            out[f"{c.name}.ldd_rev"] = rev.tolist()
    return out
