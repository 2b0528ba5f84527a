"""Lifetime Miner damage of rated parts, gear teeth (gear_lifetime.py) and rolling bearings
(bearing_lifetime.py), from their damage-per-day columns, weighted like the DEL damage sums in lifetime.py:

- a case's damage in its analysed window is D_i = <damage per day> × T_i / 86 400, undoing windrive's
  per-day scaling (the window's damage × 86 400 / T_i, T_i its analysed seconds, the same window the
  campaign's `analysed_s` measures: both keep t ≥ transient);
- the lifetime damage D_life = Σ_i w_i · D_i with lifetime.py's weights w_i (a DLC 1.2 case its climate
  hours in windows, an event its count), so a DLC 1.2 case adds hours_i / 24 × its damage per day;
- a group's share of D_life, the groups those of the DEL shares;
- the life in years, years / D_life (inf when D_life = 0).

A tooth and a bearing differ only in which columns hold their damage and how a row is labelled; those
two modules choose, the sums are here.
"""

from __future__ import annotations

import math

import pandas as pd

from .errors import CampaignError

SECONDS_PER_DAY = 86400.0


def window_damage(ok: pd.DataFrame, column: str) -> pd.Series:
    """Each case's Miner damage in its analysed window, from its damage per day."""
    return ok[column] * ok.analysed_s / SECONDS_PER_DAY


def life_years(years: float, damage: float) -> float:
    return years / damage if damage > 0 else math.inf


def lifetime(
    ok: pd.DataFrame, found: list[tuple[dict, str]], years: float, groups: list[str], campaign: str
) -> list[dict]:
    """One row per (labels, damage-per-day column) of `found`, in its order: the labels, then damage
    (D_life), life_years, share{group}.

    `ok` holds the finished, weighted cases with lifetime.compute's columns `w` (weight) and `label`
    (share group). A column NaN in every case is a part windrive does not rate (p1's flank): no row.
    NaN in only some cases would make a sum silently short, so it is an error."""
    rows = []
    for labels, column in found:
        missing = ok[column].isna()
        if missing.all():
            continue
        if missing.any():
            names = ", ".join(ok.name[missing].head(5))
            raise CampaignError(f"campaign {campaign}: column {column} is NaN in {int(missing.sum())} finished "
                                f"case(s) ({names}) but rated in the others: run them again")  # fmt: skip
        rows.append({**labels, **_damage(ok, column, years, groups)})
    return rows


def _damage(ok: pd.DataFrame, column: str, years: float, groups: list[str]) -> dict:
    per_case = ok.w * window_damage(ok, column)
    total = float(per_case.sum())
    by_group = per_case.groupby(ok.label).sum()
    return {
        "damage": total,
        "life_years": life_years(years, total),
        "share": {g: float(by_group.get(g, 0.0)) / total if total > 0 else math.nan for g in groups},
    }
