"""Gear damage in the lifetime report (windrive life --cases through python/windrive_campaign/lifetime.py, report.py;
docs/CAMPAIGNS.md, Lifetime report): the teeth's lifetime Miner damage, shares and life of a synthetic
table against a hand computation, the files and printed table of `scripts/campaign report`, and a table
without gear columns giving the report it gave before. No simulation: a few seconds."""

import json
import math
import pathlib
import sys

import pandas as pd
import pyarrow as pa
import pyarrow.parquet as pq
import pytest
import scipy.stats

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "python"))

from campaign_cli import campaign_cli  # noqa: E402
from windrive_campaign import lifetime as lt  # noqa: E402
from windrive_campaign.errors import CampaignError  # noqa: E402

LSS = "torsional.lss_torque"
META = {"campaign": "geared", "years": 2.0, "feq_hz": 0.5}
GROUPS = ["DLC 1.2 10 m/s", "DLC 1.2 12 m/s", "shutdown-rated"]
FILES = ["lifetime.csv", "lifetime.json", "lifetime_ldd.csv", "lifetime.png"]
GEAR_FILES = ["lifetime_gears.csv", "lifetime_gears.png"]


def gear(s1_flank, s1_root, p1_root, g3_root=0.0):
    """A case's gear columns as `windrive gears` gives them: p1 has no flank (NaN), g3 a root that never
    sees a positive stress here (no damage), and a column that is not a damage."""
    return {"gear.s1.flank_day": s1_flank, "gear.s1.root_day": s1_root, "gear.s1.cycles": 1e6,
            "gear.p1.flank_day": math.nan, "gear.p1.root_day": p1_root, "gear.g3.root_day": g3_root}  # fmt: skip


def rows(with_gears=True):
    """Two seeds of the 10 m/s bin, one case at 12 m/s, a shutdown, a grid case (no weight) and a failed
    case, as in test_campaign_lifetime.py, each with a DEL and (with_gears) gear damage per day."""
    base = {"status": "ok", "error": "", "seed": 1, "events": math.nan, "hours": math.nan,
            "wind_speed": math.nan, "param.rotor.wind_speed": math.nan}  # fmt: skip
    found = [
        {**base, "name": "dlc12-v10-s1", "group": "dlc12", "wind_speed": 10.0, "hours": 100.0, "analysed_s": 10.0,
         f"{LSS}.del_m3": 2.0, **gear(2e-3, 3e-4, 1e-5)},
        {**base, "name": "dlc12-v10-s2", "group": "dlc12", "wind_speed": 10.0, "hours": 100.0, "seed": 2,
         "analysed_s": 10.0, f"{LSS}.del_m3": 1.0, **gear(1e-3, 1e-4, 2e-5)},
        {**base, "name": "dlc12-v12-s1", "group": "dlc12", "wind_speed": 12.0, "hours": 50.0, "analysed_s": 20.0,
         f"{LSS}.del_m3": 3.0, **gear(4e-3, 6e-4, 5e-5)},
        {**base, "name": "event-shutdown-rated", "group": "event", "events": 1000.0, "seed": None,
         "param.rotor.wind_speed": 12.0, "analysed_s": 30.0, f"{LSS}.del_m3": 10.0, **gear(0.5, 0.2, 0.01)},
        {**base, "name": "grid-fidelity=5", "group": "grid", "seed": None, "analysed_s": 10.0,
         f"{LSS}.del_m3": 99.0, **gear(99.0, 99.0, 99.0, 99.0)},
        {**base, "name": "dlc12-v14-s1", "group": "dlc12", "status": "failed", "error": "boom", "wind_speed": 14.0,
         "hours": 70.0, "analysed_s": math.nan, f"{LSS}.del_m3": math.nan,
         **gear(math.nan, math.nan, math.nan, math.nan)},
    ]  # fmt: skip
    if not with_gears:
        found = [{k: v for k, v in r.items() if not k.startswith("gear.")} for r in found]
    return found


def by_hand(day: list[float]) -> dict:
    """Lifetime damage and group damages from the four weighted cases' damage per day: a DLC 1.2 case
    adds hours / 24 days of its damage per day, the shutdown 1000 windows of 30 s."""
    v10 = 100 / 24 * day[0] + 100 / 24 * day[1]
    v12 = 50 / 24 * day[2]
    shutdown = 1000 * day[3] * 30 / 86400
    return {"DLC 1.2 10 m/s": v10, "DLC 1.2 12 m/s": v12, "shutdown-rated": shutdown}


HAND = {
    ("s1", "flank"): by_hand([2e-3, 1e-3, 4e-3, 0.5]),
    ("s1", "root"): by_hand([3e-4, 1e-4, 6e-4, 0.2]),
    ("p1", "root"): by_hand([1e-5, 2e-5, 5e-5, 0.01]),
}


def write_table(folder: pathlib.Path, table_rows) -> pathlib.Path:
    folder.mkdir(parents=True, exist_ok=True)
    t = pa.Table.from_pandas(pd.DataFrame(table_rows), preserve_index=False)
    pq.write_table(t.replace_schema_metadata({"windrive_campaign": json.dumps(META)}), folder / "geared.parquet")
    return folder


# ---------------------------------------------------------------------------------------------------
# the figures


def test_gear_damage_is_the_hand_computation():
    life = lt.compute(pd.DataFrame(rows()), META)
    assert [(r["tooth"], r["kind"]) for r in life.gears] == [("s1", "flank"), ("s1", "root"), ("p1", "root"),
                                                              ("g3", "root")]  # fmt: skip
    assert life.groups == GROUPS
    for r in life.gears[:3]:
        groups = HAND[(r["tooth"], r["kind"])]
        total = sum(groups.values())
        assert r["damage"] == pytest.approx(total, rel=1e-12), r["tooth"]
        assert r["life_years"] == pytest.approx(2.0 / total, rel=1e-12), r["tooth"]
        assert r["share"] == pytest.approx({g: d / total for g, d in groups.items()}, rel=1e-12), r["tooth"]
    # a root with no damage lives forever and has no shares
    g3 = life.gears[3]
    assert g3["damage"] == 0.0 and g3["life_years"] == math.inf
    assert all(math.isnan(s) for s in g3["share"].values())


def test_gear_damage_leaves_the_del_figures_alone():
    plain = lt.compute(pd.DataFrame(rows(with_gears=False)), META)
    geared = lt.compute(pd.DataFrame(rows()), META)
    assert plain.gears == []
    assert plain.rows == geared.rows and plain.groups == geared.groups and plain.left_out == geared.left_out


def test_a_tooth_rated_in_only_some_finished_cases_is_an_error():
    """A NaN among rated values would make the lifetime sum silently short."""
    table = rows()
    table[2]["gear.s1.root_day"] = math.nan
    with pytest.raises(CampaignError, match=r"campaign geared: column gear.s1.root_day is NaN in 1 finished "
                                            r"case\(s\) \(dlc12-v12-s1\) but rated in the others"):  # fmt: skip
        lt.compute(pd.DataFrame(table), META)


def test_teeth_keep_the_table_order_flank_before_root():
    base = rows()[0]
    shuffled = {k: v for k, v in base.items() if not k.startswith("gear.")}
    shuffled.update({"gear.r1.root_day": 1e-4, "gear.s1.root_day": 2e-4, "gear.r1.flank_day": 3e-4,
                     "gear.s1.max_root": 5e8, "gear.s1.flank_day": 4e-4, "x.flank_day": 1.0})  # fmt: skip
    life = lt.compute(pd.DataFrame([shuffled]), META)
    assert [(r["tooth"], r["kind"]) for r in life.gears] == [("r1", "flank"), ("r1", "root"), ("s1", "flank"),
                                                              ("s1", "root")]  # fmt: skip


# ---------------------------------------------------------------------------------------------------
# the report command


def test_report_writes_the_gear_files_and_table(tmp_path):
    folder = write_table(tmp_path / "geared", rows())
    r = campaign_cli("report", folder)
    assert r.returncode == 1, r.stderr  # the failed case is left out and counted
    assert "not in the lifetime: 1 failed: dlc12-v14-s1" in r.stderr and "Traceback" not in r.stderr
    for name in FILES + GEAR_FILES:
        assert (folder / name).is_file(), name
    assert (folder / "lifetime_gears.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    s1_flank = HAND[("s1", "flank")]
    total = sum(s1_flank.values())

    table = pd.read_csv(folder / "lifetime_gears.csv")
    assert list(table.columns) == ["tooth", "kind", "damage", "damage_lo", "damage_hi", "life_years",
                                   *(f"share:{g}" for g in GROUPS)]  # fmt: skip
    # the 95 % interval over seeds: Student's t of the 10 m/s bin's two seeds (its sum's variance n·s² =
    # (y1 − y2)², one degree of freedom; the other groups have one case each and add none), held at 0
    half = scipy.stats.t.ppf(0.975, 1) * 100 / 24 * (2e-3 - 1e-3)
    assert table.damage_hi[0] == pytest.approx(total + half, rel=1e-9)
    assert table.damage_lo[0] == pytest.approx(max(total - half, 0.0), rel=1e-9, abs=1e-15)
    assert list(zip(table.tooth, table.kind)) == [("s1", "flank"), ("s1", "root"), ("p1", "root"), ("g3", "root")]
    assert table.damage[0] == pytest.approx(total, rel=1e-12)
    assert table["share:shutdown-rated"][0] == pytest.approx(s1_flank["shutdown-rated"] / total, rel=1e-12)
    assert table.life_years[3] == math.inf

    # strict JSON: the damage-free root's infinite life and undefined shares are null
    gears = json.loads((folder / "lifetime.json").read_text(), parse_constant=pytest.fail)["gears"]
    assert "nominal ISO 6336" in gears["method"]
    assert gears["lifetime"][0]["life_years"] == pytest.approx(2.0 / total, rel=1e-12)
    assert gears["lifetime"][3]["life_years"] is None and set(gears["lifetime"][3]["share"].values()) == {None}

    assert "gear damage over 2 years" in r.stdout and "share of gear damage [%]" in r.stdout
    assert f"s1       flank  {total:>11.4e} {2.0 / total:>13.4g}" in r.stdout  # then its interval
    assert "lifetime_gears.csv, lifetime_gears.png" in r.stdout


def test_a_table_without_gear_columns_gives_the_report_without_gears(tmp_path):
    plain = write_table(tmp_path / "plain", rows(with_gears=False))
    geared = write_table(tmp_path / "geared", rows())
    r = campaign_cli("report", plain)
    g = campaign_cli("report", geared)
    assert r.returncode == g.returncode == 1 and r.stderr == g.stderr, r.stderr
    assert sorted(p.name for p in plain.iterdir()) == sorted(["geared.parquet", *FILES])
    assert "gear damage" not in r.stdout and "lifetime_gears" not in r.stdout
    # the DEL part is the same with gears: the files byte for byte, the JSON but for its gear section,
    # the printed table up to the gear section
    for name in ["lifetime.csv", "lifetime_ldd.csv"]:
        assert (plain / name).read_text() == (geared / name).read_text(), name
    with_gears = json.loads((geared / "lifetime.json").read_text())
    assert "gears" in with_gears and json.loads((plain / "lifetime.json").read_text()) == {
        k: v for k, v in with_gears.items() if k != "gears"}  # fmt: skip
    before_gears = g.stdout.split("\ngear damage over")[0]
    assert r.stdout.startswith(before_gears)
    assert r.stdout.endswith(f"written: {plain}/lifetime.csv, lifetime.json, lifetime_ldd.csv, lifetime.png\n")
