"""Lifetime Miner damage of every gear tooth from a campaign with `[gears]` (gears.py): each tooth's
flank and root damage per day, `gear.<tooth>.flank_day` and `.root_day`, summed over the design life by
miner_lifetime.py (weights, group shares and life as for the DEL damage sums in lifetime.py).

The damage is the paper's (nominal ISO 6336 stresses without load factors, a two-slope S-N curve), so
it ranks load cases and teeth; it is not a certified gear rating.
"""

from __future__ import annotations

import re

import pandas as pd

from . import miner_lifetime

DAMAGE_COLUMN = re.compile(r"^gear\.(?P<tooth>[^.]+)\.(?P<kind>flank|root)_day$")
KINDS = ("flank", "root")


def damage_columns(columns) -> list[tuple[str, str, str]]:
    """(tooth, kind, column) of every `gear.<tooth>.flank_day` / `.root_day` column, teeth in table order."""
    found = [(m["tooth"], m["kind"], c) for c in columns if (m := DAMAGE_COLUMN.match(c))]
    order = list(dict.fromkeys(tooth for tooth, _, _ in found))
    return sorted(found, key=lambda f: (order.index(f[0]), KINDS.index(f[1])))


def lifetime(ok: pd.DataFrame, years: float, groups: list[str], campaign: str) -> list[dict]:
    """One row per rated tooth and kind: tooth, kind, damage (D_life), life_years, share{group}
    (miner_lifetime.lifetime; a flank or root windrive does not rate, p1's flank, has no row)."""
    found = [({"tooth": tooth, "kind": kind}, column) for tooth, kind, column in damage_columns(ok.columns)]
    return miner_lifetime.lifetime(ok, found, years, groups, campaign)
