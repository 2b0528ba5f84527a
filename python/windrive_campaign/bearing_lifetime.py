"""Lifetime Miner damage of every rolling bearing from a campaign with `[bearings]` (bearings.py): each
bearing's damage per day, `bearing.<name>.day` (revolutions over L10, scaled to a day), summed over the
design life by miner_lifetime.py (weights, group shares and life as for the DEL damage sums in
lifetime.py), with its basic dynamic load rating C_r from `bearing.<name>.c`.

The damage is ISO 281's basic rating life L10 without the life modification factor a_ISO
(lubrication, contamination, fatigue limit), so it ranks load cases and bearings; it is not a bearing
maker's modified life. Beside it, the thesis's count (`bearing.<name>.thesis_day`: rainflow cycles of the
load as load cycles, its ch. 5.4) summed the same way, and each count's share from the events (shutdowns,
start-ups): ISO 281 counts revolutions, so hours of turning outweigh a shutdown's few large swings; the
thesis's count weighs the swings.
"""

from __future__ import annotations

import math
import re

import pandas as pd

from . import miner_lifetime
from .errors import CampaignError

DAMAGE_COLUMN = re.compile(r"^bearing\.(?P<bearing>[^.]+)\.day$")
THESIS_COLUMN = re.compile(r"^bearing\.(?P<bearing>[^.]+)\.thesis_day$")


def lifetime(ok: pd.DataFrame, years: float, groups: list[str], campaign: str) -> list[dict]:
    """One row per rated bearing, in table order: bearing, dynamic_load_rating (C_r, N), damage
    (D_life), life_years, share{group} (miner_lifetime.lifetime), events_share, and the thesis's count's
    thesis_damage and thesis_events_share (NaN for a table without it)."""

    def found(pattern):
        return [({"bearing": m["bearing"]}, c) for c in ok.columns if (m := pattern.match(c))]

    ratings = {labels["bearing"]: _rating(ok, labels["bearing"], campaign) for labels, _ in found(DAMAGE_COLUMN)}
    rows = miner_lifetime.lifetime(ok, found(DAMAGE_COLUMN), years, groups, campaign)
    thesis = {r["bearing"]: r for r in miner_lifetime.lifetime(ok, found(THESIS_COLUMN), years, groups, campaign)}
    events = set(ok.label[ok.group == "event"])
    for r in rows:
        t = thesis.get(r["bearing"])
        r["dynamic_load_rating"] = ratings[r["bearing"]]
        r["events_share"] = _share_of(r, events)
        r["thesis_damage"] = t["damage"] if t else math.nan
        r["thesis_events_share"] = _share_of(t, events) if t else math.nan
    return rows


def _share_of(row: dict, groups: set[str]) -> float:
    return sum(s for g, s in row["share"].items() if g in groups)


def _rating(ok: pd.DataFrame, bearing: str, campaign: str) -> float:
    """The bearing's C_r, the same in every case of one gearbox. Two values mean cases rated with
    different descriptions (a description file edited during the campaign), whose damage does not add."""
    values = ok[f"bearing.{bearing}.c"].dropna().unique()
    if len(values) > 1:
        raise CampaignError(f"campaign {campaign}: bearing {bearing} has C_r = "
                            f"{', '.join(f'{v:.6g}' for v in values[:5])} N in different finished cases: "
                            "they were rated with different gearbox descriptions")  # fmt: skip
    return float(values[0]) if len(values) else float("nan")
