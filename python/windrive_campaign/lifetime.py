"""A campaign's lifetime figures from its Parquet table, computed by `windrive life --cases`
(src/analysis/fatigue/campaign.rs; docs/CAMPAIGNS.md, Lifetime report): each case weighted by what it
stands for in the design life (a DLC 1.2 case its climate hours, an event its count), the lifetime damage
sums and DELs per channel and Wöhler slope with each group's share and their 95 % intervals over seeds
(`*_ci`: Student's t over each DLC 1.2 bin's seeds), the lifetime LDD, the teeth's and the
bearings' Miner damage, and the thesis's DEL ratios. This module only hands the table over and reads the
answer; the convention is the binary's, one computation with `windrive life`.
"""

from __future__ import annotations

import json
import math
import subprocess
from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from . import binary
from .errors import CampaignError

# the thesis's DEL ratios are at m = 6 (§3.4.3)
THESIS_M = 6.0


@dataclass
class Lifetime:
    campaign: str
    years: float
    feq_hz: float
    life_s: float  # T_life, the reference of the lifetime DELs
    groups: list[str]  # in campaign order
    rows: list[dict]  # one per channel and slope: channel, m, lifetime_del, damage_sum, share{group}
    ldd: dict[str, dict] = field(default_factory=dict)  # channel -> speed, edges, seconds, revolutions
    ratios: list[dict] = field(default_factory=list)  # the thesis's DEL ratios beside ours
    used: int = 0
    operating_hours: float = 0.0
    events: float = 0.0
    left_out: dict[str, list[str]] = field(default_factory=dict)  # status -> case names not counted
    gears: list[dict] = field(default_factory=list)  # per tooth and flank/root: damage, life_years, share{group}
    bearings: list[dict] = field(default_factory=list)  # per bearing: C_r, damage, life_years, share{group}
    # how the 95 % intervals over each DLC 1.2 bin's seeds are taken, and the groups of one case
    intervals: dict = field(default_factory=dict)


def read_metadata(schema_metadata: dict | None) -> dict:
    raw = (schema_metadata or {}).get(b"windrive_campaign")
    return json.loads(raw) if raw else {}


def compute(t: pd.DataFrame, meta: dict, windrive: str | None = None) -> Lifetime:
    """The lifetime figures of every analysed channel and slope from the finished, weighted cases."""
    table = {
        "campaign": meta.get("campaign", ""),
        "years": meta.get("years"),
        "feq_hz": meta.get("feq_hz"),
        "ldd_bins": [{"channel": c, **b} for c, b in (meta.get("ldd_bins") or {}).items()],
        "columns": [str(c) for c in t.columns],
        "rows": [[_cell(v) for v in row] for row in t.itertuples(index=False, name=None)],
    }
    command = [binary.windrive(windrive), "life", "--cases", "-"]
    r = subprocess.run(command, input=json.dumps(table, allow_nan=False), capture_output=True, text=True)
    if r.returncode != 0:
        raise CampaignError(r.stderr.strip().removeprefix("error: ") or f"windrive life exited {r.returncode}")
    d = json.loads(r.stdout)
    nan = lambda x: math.nan if x is None else x  # noqa: E731 (JSON's null is NaN here)
    for row in d["rows"] + d["gears"] + d["bearings"]:
        row["share"] = {g: nan(s) for g, s in row["share"].items()}
        row["share_ci"] = {g: [nan(x) for x in ci] for g, ci in row["share_ci"].items()}
        for k in ("lifetime_del", "dynamic_load_rating", "events_share", "thesis_damage", "thesis_events_share",
                  "modified_damage", "modified_events_share"):
            if k in row:
                row[k] = nan(row[k])
        if "life_years" in row:  # null: no damage, it never fails
            row["life_years"] = math.inf if row["life_years"] is None else row["life_years"]
            row["life_years_ci"] = [math.inf if x is None else x for x in row["life_years_ci"]]
    for q in d["ratios"]:
        q["ours"] = nan(q["ours"])
    return Lifetime(
        campaign=d["campaign"], years=d["years"], feq_hz=d["feq_hz"], life_s=d["life_s"], groups=d["groups"],
        rows=d["rows"], ldd={x.pop("channel"): x for x in d["ldd"]}, ratios=d["ratios"], used=d["used"],
        operating_hours=d["operating_hours"], events=d["events"], left_out=dict(d["left_out"]),
        gears=d["gears"], bearings=d["bearings"], intervals=d["intervals"],
    )  # fmt: skip


def _cell(v):
    """A table value as JSON: NaN and None are null, numpy's numbers and arrays Python's."""
    if v is None:
        return None
    if isinstance(v, np.ndarray | list | tuple):
        return [_cell(x) for x in v]
    if isinstance(v, bool | np.bool_):
        return bool(v)
    if isinstance(v, int | float | np.integer | np.floating):
        return None if math.isnan(v) else float(v)
    return None if v is pd.NA or v is pd.NaT else str(v)
