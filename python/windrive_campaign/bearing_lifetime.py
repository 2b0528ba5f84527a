"""Lifetime Miner damage of every rolling bearing from a campaign with `[bearings]` (bearings.py): each
bearing's damage per day, `bearing.<name>.day` (revolutions over L10, scaled to a day), summed over the
design life by miner_lifetime.py (weights, group shares and life as for the DEL damage sums in
lifetime.py), with its basic dynamic load rating C_r from `bearing.<name>.c`.

The damage is ISO 281's basic rating life L10 without the life modification factor a_ISO
(lubrication, contamination, fatigue limit), so it ranks load cases and bearings; it is not a bearing
maker's modified life.
"""

from __future__ import annotations

import re

import pandas as pd

from . import miner_lifetime
from .errors import CampaignError

DAMAGE_COLUMN = re.compile(r"^bearing\.(?P<bearing>[^.]+)\.day$")


def lifetime(ok: pd.DataFrame, years: float, groups: list[str], campaign: str) -> list[dict]:
    """One row per rated bearing, in table order: bearing, dynamic_load_rating (C_r, N), damage
    (D_life), life_years, share{group} (miner_lifetime.lifetime)."""
    found = [
        ({"bearing": m["bearing"], "dynamic_load_rating": _rating(ok, m["bearing"], campaign)}, column)
        for column in ok.columns
        if (m := DAMAGE_COLUMN.match(column))
    ]
    return miner_lifetime.lifetime(ok, found, years, groups, campaign)


def _rating(ok: pd.DataFrame, bearing: str, campaign: str) -> float:
    """The bearing's C_r, the same in every case of one gearbox. Two values mean cases rated with
    different descriptions (a description file edited during the campaign), whose damage does not add."""
    values = ok[f"bearing.{bearing}.c"].dropna().unique()
    if len(values) > 1:
        raise CampaignError(f"campaign {campaign}: bearing {bearing} has C_r = "
                            f"{', '.join(f'{v:.6g}' for v in values[:5])} N in different finished cases: "
                            "they were rated with different gearbox descriptions")  # fmt: skip
    return float(values[0]) if len(values) else float("nan")
