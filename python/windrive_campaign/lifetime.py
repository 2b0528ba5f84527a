"""A campaign's lifetime figures from its Parquet table (issue 15 §2), by the convention of `windrive
life` (src/analysis/fatigue/lifetime.rs), so the two agree on the cases it can compute (tested):

- each case stands for w_i repetitions in the design life: a DLC 1.2 case w_i = hours_i · 3600 / T_i
  (its climate hours over its analysed seconds T_i), an event w_i = events_i (per_year × years);
  grid cases have no weight and stay out;
- a case's Σ n S^m is recovered from its DEL: DEL_i^m · f_eq · T_i (DEL_i = (Σ n S^m / (f_eq T_i))^(1/m));
- the lifetime damage sum D = Σ_i w_i · DEL_i^m · f_eq · T_i, and the lifetime DEL = (D / (f_eq T_life))^(1/m)
  with T_life the whole design life, years · 8760 h · 3600 s, not its operating hours: that is what
  `windrive life` divides by (life_hours), so one number means the same thing in both tools;
- a group's share of D: each DLC 1.2 wind bin (its seeds together) and each event;
- the lifetime LDD: Σ_i w_i · (seconds, revolutions) per load bin.

D is a damage sum in load^m × cycles, not a Miner damage: no S-N curve is attached to a channel here.
With `[gears]` and `[bearings]`, the teeth's and the bearings' Miner damage over the design life uses
the same weights and groups (gear_lifetime.py, bearing_lifetime.py, both through miner_lifetime.py).
"""

from __future__ import annotations

import json
import math
import numbers
import re
from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from . import bearing_lifetime, gear_lifetime
from .errors import CampaignError

DEL_COLUMN = re.compile(r"^(?P<channel>.+)\.del_m(?P<m>[0-9.eE+-]+)$")

# Thesis §3.4.3 ("3.65"; docs/SOURCES.md §Thesis): the DEL of the measured shutdown series over the DEL of
# each other measured series, each over its own duration at 1 Hz, m = 6, the same for HSS and LSS torque.
THESIS_M = 6.0

# 8760 h a year, as `windrive life` (src/analysis/fatigue/lifetime.rs) and thesis Table 7.1 count hours
HOURS_PER_YEAR = 8760.0
THESIS_RATIOS = {"normal operation": 3.65, "start-up": 1.43, "normal stop": 1.1}


@dataclass
class Lifetime:
    campaign: str
    years: float
    feq_hz: float
    life_s: float  # T_life, the reference of the lifetime DELs
    groups: list[str]  # in campaign order
    rows: list[dict]  # one per channel and slope: channel, m, lifetime_del, damage_sum, share{group}
    ldd: dict[str, dict] = field(default_factory=dict)  # channel -> edges, seconds, revolutions
    ratios: list[dict] = field(default_factory=list)  # the thesis's DEL ratios beside ours
    used: int = 0
    operating_hours: float = 0.0
    events: float = 0.0
    left_out: dict[str, list[str]] = field(default_factory=dict)  # status -> case names not counted
    gears: list[dict] = field(default_factory=list)  # per tooth and flank/root: damage, life_years, share{group}
    bearings: list[dict] = field(default_factory=list)  # per bearing: C_r, damage, life_years, share{group}


def read_metadata(schema_metadata: dict | None) -> dict:
    raw = (schema_metadata or {}).get(b"windrive_campaign")
    return json.loads(raw) if raw else {}


def weights(t: pd.DataFrame) -> pd.Series:
    """Repetitions of each case in the design life; NaN for the grid, which has no weight."""
    w = pd.Series(math.nan, index=t.index)
    dlc = t.group == "dlc12"
    w[dlc] = t.hours[dlc] * 3600.0 / t.analysed_s[dlc]
    ev = t.group == "event"
    w[ev] = t.events[ev]
    return w


def group_labels(t: pd.DataFrame) -> pd.Series:
    """The share groups: a DLC 1.2 wind bin pools its seeds; an event is its own group."""

    def label(row) -> str:
        if row["group"] == "dlc12":
            return f"DLC 1.2 {row['wind_speed']:g} m/s"
        return row["name"].removeprefix("event-") if row["group"] == "event" else row["name"]

    return t.apply(label, axis=1)


def slopes(columns) -> dict[str, list[float]]:
    """Every analysed channel and its Wöhler slopes, from the `<channel>.del_m<m>` columns."""
    found: dict[str, list[float]] = {}
    for c in columns:
        if m := DEL_COLUMN.match(c):
            found.setdefault(m["channel"], []).append(float(m["m"]))
    return found


def damage_sums(t: pd.DataFrame, channel: str, m: float, feq: float) -> pd.Series:
    """Each case's Σ n S^m, from its DEL over its analysed seconds."""
    return t[f"{channel}.del_m{m:g}"] ** m * feq * t.analysed_s


def _left_out(t: pd.DataFrame) -> dict[str, list[str]]:
    out: dict[str, list[str]] = {}
    for status, names in t[t.status != "ok"].groupby("status")["name"]:
        out[status] = list(names)
    grid = t[(t.group == "grid") & (t.status == "ok")]
    if len(grid):
        out["grid (no weight)"] = list(grid["name"])
    return out


def compute(t: pd.DataFrame, meta: dict) -> Lifetime:
    """The lifetime figures of every analysed channel and slope from the finished, weighted cases."""
    years = meta.get("years") or 20.0  # a campaign without [climate] counts its events over 20 years
    feq = meta.get("feq_hz") or 1.0
    ok = t[(t.status == "ok") & t.group.isin(["dlc12", "event"])].copy()
    if ok.empty:
        raise CampaignError(
            f"campaign {meta.get('campaign', '?')}: no finished DLC 1.2 or event case to weigh "
            f"({_describe_left_out(_left_out(t)) or 'the table is empty'})"
        )
    ok["w"] = weights(ok)
    ok["label"] = group_labels(ok)
    groups = list(dict.fromkeys(ok.label))
    life = Lifetime(
        campaign=meta.get("campaign", ""),
        years=years,
        feq_hz=feq,
        life_s=years * HOURS_PER_YEAR * 3600.0,
        groups=groups,
        rows=[],
        used=len(ok),
        operating_hours=float(ok.hours[ok.group == "dlc12"].sum()),
        events=float(ok.events[ok.group == "event"].sum()),
        left_out=_left_out(t),
    )
    for channel, ms in slopes(t.columns).items():
        for m in ms:
            life.rows.append(_row(ok, channel, m, feq, life.life_s, groups))
    for channel, bins in (meta.get("ldd_bins") or {}).items():
        if f"{channel}.ldd_s" in ok:
            life.ldd[channel] = lifetime_ldd(ok, channel, bins)
    life.ratios = thesis_ratios(ok, slopes(t.columns), feq)
    life.gears = gear_lifetime.lifetime(ok, years, groups, life.campaign)
    life.bearings = bearing_lifetime.lifetime(ok, years, groups, life.campaign)
    return life


def _row(ok: pd.DataFrame, channel: str, m: float, feq: float, life_s: float, groups: list[str]) -> dict:
    per_case = ok.w * damage_sums(ok, channel, m, feq)
    total = float(per_case.sum())
    by_group = per_case.groupby(ok.label).sum()
    return {
        "channel": channel,
        "m": m,
        "lifetime_del": (total / (feq * life_s)) ** (1.0 / m),
        "damage_sum": total,
        "share": {g: float(by_group.get(g, 0.0)) / total if total > 0 else math.nan for g in groups},
    }


def lifetime_ldd(ok: pd.DataFrame, channel: str, bins: dict) -> dict:
    """Seconds and revolutions per load bin over the design life, each case weighted like its damage."""
    seconds = np.zeros(bins["bins"])
    revolutions = np.zeros(bins["bins"])
    for w, s, n in zip(ok.w, ok[f"{channel}.ldd_s"], ok[f"{channel}.ldd_rev"]):
        seconds += w * np.asarray(s, dtype=float)
        revolutions += w * np.asarray(n, dtype=float)
    return {
        "speed": bins["speed"],
        "edges": np.linspace(bins["min"], bins["max"], bins["bins"] + 1).tolist(),
        "seconds": seconds.tolist(),
        "revolutions": revolutions.tolist(),
    }


def event_kind(name: str) -> str | None:
    """The thesis's event kinds, from the event's name: its 'shutdown' is a stop with the mechanical
    brake (emergency-like), its 'normal stop' a slow-down without it."""
    n = name.lower()
    if "shutdown" in n or "emergency" in n:
        return "shutdown"
    if "start" in n:
        return "start-up"
    if "stop" in n:
        return "normal stop"
    return None


def pooled_del(rows: pd.DataFrame, channel: str, m: float, feq: float) -> float:
    """The DEL of several cases taken as one series of their summed time: (Σ w Σ n S^m / (f_eq Σ w T))^(1/m)."""
    time_s = float((rows.w * rows.analysed_s).sum())
    return float((rows.w * damage_sums(rows, channel, m, feq)).sum() / (feq * time_s)) ** (1.0 / m)


def thesis_ratios(ok: pd.DataFrame, found: dict[str, list[float]], feq: float) -> list[dict]:
    """Our DEL ratios of a shutdown event to the other groups the thesis compares it with, at its m = 6,
    beside its figures. Normal operation is DLC 1.2 pooled over the climate's operating hours, and also
    the DLC 1.2 bin at the shutdown's wind speed when there is one (the thesis's is one rated series)."""
    out = []
    events = ok[ok.group == "event"]
    shutdowns = events[events["name"].map(lambda n: event_kind(n.removeprefix("event-")) == "shutdown")]
    dlc = ok[ok.group == "dlc12"]
    for channel, ms in found.items():
        if THESIS_M not in ms:
            continue
        col = f"{channel}.del_m{THESIS_M:g}"
        for _, s in shutdowns.iterrows():
            others = _comparisons(s, events, dlc, channel, feq)
            for versus, label, theirs, del_other in others:
                out.append({
                    "channel": channel, "m": THESIS_M, "shutdown": s["label"], "versus": versus,
                    "versus_cases": label, "ours": float(s[col]) / del_other, "thesis": theirs,
                })  # fmt: skip
    return out


def _comparisons(s, events: pd.DataFrame, dlc: pd.DataFrame, channel: str, feq: float) -> list[tuple]:
    col = f"{channel}.del_m{THESIS_M:g}"
    found = []
    if len(dlc):
        found.append(("normal operation", "DLC 1.2, climate-weighted", THESIS_RATIOS["normal operation"],
                      pooled_del(dlc, channel, THESIS_M, feq)))  # fmt: skip
        v = _event_wind_speed(s)
        same = dlc[np.isclose(dlc.wind_speed, v)] if v is not None else dlc.iloc[0:0]
        if len(same):
            found.append(("normal operation", f"DLC 1.2 {v:g} m/s", THESIS_RATIOS["normal operation"],
                          pooled_del(same, channel, THESIS_M, feq)))  # fmt: skip
    for _, e in events.iterrows():
        kind = event_kind(e["name"].removeprefix("event-"))
        if kind in ("start-up", "normal stop"):
            found.append((kind, e["label"], THESIS_RATIOS[kind], float(e[col])))
    return found


def _event_wind_speed(row) -> float | None:
    for k, v in row.items():
        # numbers.Real: a column of integer speeds comes back as numpy.int64, not int
        if k.startswith("param.") and k.endswith(".wind_speed") and isinstance(v, numbers.Real) and not pd.isna(v):
            return float(v)
    return None


def _describe_left_out(left_out: dict[str, list[str]]) -> str:
    return ", ".join(f"{len(v)} {k}" for k, v in left_out.items())
