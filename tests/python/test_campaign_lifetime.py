"""The campaign's lifetime report (python/windrive_campaign/lifetime.py, report.py; docs/CAMPAIGNS.md,
Lifetime report): the aggregation against a hand computation on a synthetic table, against `windrive
life` on the real series of campaigns/tiny-life.toml, the report command's files and table, and its
errors. About 10 s on 2 cores: the one real campaign is two cases of 2 and 4 s."""

import json
import math
import pathlib
import subprocess
import sys

import numpy as np
import pandas as pd
import pyarrow as pa
import pyarrow.parquet as pq
import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "python"))

from campaign_cli import campaign_cli, one_line_error  # noqa: E402
from windrive_campaign import lifetime as lt  # noqa: E402
from windrive_campaign.errors import CampaignError  # noqa: E402

TINY_LIFE = ROOT / "campaigns" / "tiny-life.toml"
LSS = "torsional.lss_torque"


# ---------------------------------------------------------------------------------------------------
# a synthetic table, computed by hand

META = {"campaign": "synthetic", "years": 2.0, "feq_hz": 0.5,
        "ldd_bins": {LSS: {"speed": "torsional.rotor_speed", "min": 0.0, "max": 3.0, "bins": 3}}}  # fmt: skip


def synthetic_rows():
    """Two seeds of the 10 m/s bin, one case at 12 m/s, a shutdown, a grid case (no weight) and a
    failed case: numbers small enough to add up by hand below."""
    base = {"status": "ok", "error": "", "seed": 1, "probability": math.nan, "events": math.nan,
            "hours": math.nan, "wind_speed": math.nan, "param.rotor.wind_speed": math.nan}  # fmt: skip
    rows = [
        {**base, "name": "dlc12-v10-s1", "group": "dlc12", "wind_speed": 10.0, "hours": 100.0,
         "analysed_s": 10.0, f"{LSS}.del_m3": 2.0, f"{LSS}.ldd_s": [4.0, 6.0, 0.0], f"{LSS}.ldd_rev": [1.0, 2.0, 0.0]},
        {**base, "name": "dlc12-v10-s2", "group": "dlc12", "wind_speed": 10.0, "hours": 100.0, "seed": 2,
         "analysed_s": 10.0, f"{LSS}.del_m3": 1.0, f"{LSS}.ldd_s": [10.0, 0.0, 0.0], f"{LSS}.ldd_rev": [3.0, 0.0, 0.0]},
        {**base, "name": "dlc12-v12-s1", "group": "dlc12", "wind_speed": 12.0, "hours": 50.0,
         "analysed_s": 20.0, f"{LSS}.del_m3": 3.0, f"{LSS}.ldd_s": [0.0, 0.0, 20.0], f"{LSS}.ldd_rev": [0.0, 0.0, 5.0]},
        {**base, "name": "event-shutdown-rated", "group": "event", "events": 1000.0, "seed": None,
         "param.rotor.wind_speed": 12.0,
         "analysed_s": 30.0, f"{LSS}.del_m3": 10.0, f"{LSS}.ldd_s": [0.0, 30.0, 0.0], f"{LSS}.ldd_rev": [0.0, 1.0, 0.0]},
        {**base, "name": "grid-fidelity=5", "group": "grid", "seed": None,
         "analysed_s": 10.0, f"{LSS}.del_m3": 99.0, f"{LSS}.ldd_s": [9.0, 9.0, 9.0], f"{LSS}.ldd_rev": [9.0, 9.0, 9.0]},
        {**base, "name": "dlc12-v14-s1", "group": "dlc12", "status": "failed", "error": "boom", "wind_speed": 14.0,
         "hours": 70.0, "analysed_s": math.nan, f"{LSS}.del_m3": math.nan, f"{LSS}.ldd_s": None, f"{LSS}.ldd_rev": None},
    ]  # fmt: skip
    return rows


def write_synthetic(folder: pathlib.Path, rows, meta=META, name="synthetic"):
    folder.mkdir(parents=True, exist_ok=True)
    t = pa.Table.from_pandas(pd.DataFrame(rows), preserve_index=False)
    pq.write_table(t.replace_schema_metadata({"windrive_campaign": json.dumps(meta)}), folder / f"{name}.parquet")
    return folder


def test_aggregation_is_the_hand_computation():
    life = lt.compute(pd.DataFrame(synthetic_rows()), META)
    # Σ n S^m of a DLC case weighted: hours·3600 · f_eq · DEL^m; of the event: events · f_eq · T · DEL^m
    v10 = 100 * 3600 * 0.5 * 2.0**3 + 100 * 3600 * 0.5 * 1.0**3  # 1 620 000
    v12 = 50 * 3600 * 0.5 * 3.0**3  # 2 430 000
    shutdown = 1000 * 0.5 * 30 * 10.0**3  # 15 000 000
    total = v10 + v12 + shutdown
    life_s = 2 * 8760 * 3600
    (row,) = life.rows
    assert (row["channel"], row["m"]) == (LSS, 3.0)
    assert row["damage_sum"] == pytest.approx(total, rel=1e-12)
    assert row["lifetime_del"] == pytest.approx((total / (0.5 * life_s)) ** (1 / 3), rel=1e-12)
    assert life.groups == ["DLC 1.2 10 m/s", "DLC 1.2 12 m/s", "shutdown-rated"]
    assert row["share"] == pytest.approx(
        {"DLC 1.2 10 m/s": v10 / total, "DLC 1.2 12 m/s": v12 / total, "shutdown-rated": shutdown / total}, rel=1e-12
    )
    assert life.used == 4 and life.operating_hours == 250.0 and life.events == 1000.0
    assert life.left_out == {"failed": ["dlc12-v14-s1"], "grid (no weight)": ["grid-fidelity=5"]}


def test_lifetime_ldd_weights_each_case_like_its_damage():
    ldd = lt.compute(pd.DataFrame(synthetic_rows()), META).ldd[LSS]
    w10, w12, ev = 100 * 3600 / 10, 50 * 3600 / 20, 1000
    assert ldd["edges"] == [0.0, 1.0, 2.0, 3.0]
    assert ldd["seconds"] == pytest.approx([w10 * 4 + w10 * 10, w10 * 6 + ev * 30, w12 * 20], rel=1e-12)
    assert ldd["revolutions"] == pytest.approx([w10 * 1 + w10 * 3, w10 * 2 + ev * 1, w12 * 5], rel=1e-12)
    # the DLC 1.2 cases' seconds are the operating hours, the events' their counted seconds
    assert sum(ldd["seconds"]) == pytest.approx(250 * 3600 + 1000 * 30, rel=1e-12)


def test_thesis_ratio_is_shutdown_del_over_pooled_normal_operation():
    ratios = lt.compute(pd.DataFrame(synthetic_rows()), {**META, "ldd_bins": {}}).ratios
    assert ratios == []  # the thesis's ratio is at m = 6; the table has m = 3 only
    rows = [{**r, f"{LSS}.del_m6": r[f"{LSS}.del_m3"]} for r in synthetic_rows()]
    by = {(q["versus_cases"]): q for q in lt.compute(pd.DataFrame(rows), META).ratios}
    # normal operation pooled over its hours: (Σ hours DEL^6 / Σ hours)^(1/6)
    pooled = ((100 * 2.0**6 + 100 * 1.0**6 + 50 * 3.0**6) / 250) ** (1 / 6)
    assert by["DLC 1.2, climate-weighted"]["ours"] == pytest.approx(10.0 / pooled, rel=1e-12)
    # the bin at the shutdown's wind speed, 12 m/s
    assert by["DLC 1.2 12 m/s"]["ours"] == pytest.approx(10.0 / 3.0, rel=1e-12)
    assert {q["thesis"] for q in by.values()} == {3.65}
    # a start-up event: the shutdown's DEL over the start-up's, beside the thesis's 1.43
    startup = {**rows[3], "name": "event-startup-cut-in", f"{LSS}.del_m6": 4.0}
    by = {q["versus"]: q for q in lt.compute(pd.DataFrame([*rows, startup]), META).ratios}
    assert by["start-up"]["ours"] == pytest.approx(10.0 / 4.0) and by["start-up"]["thesis"] == 1.43
    # without a shutdown there is nothing to compare
    assert lt.compute(pd.DataFrame([r for r in rows if r["group"] == "dlc12"]), META).ratios == []


# ---------------------------------------------------------------------------------------------------
# a real campaign: tiny-life.toml (one DLC 1.2 bin + a shutdown) against `windrive life`


@pytest.fixture(scope="module")
def tiny_life(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("tiny-life")
    out = tmp / "out"
    r = campaign_cli("run", TINY_LIFE, "--out", out, "--workers", 2)
    assert r.returncode == 0, r.stderr
    rep = campaign_cli("report", out, "--out", tmp / "report")
    return out, tmp / "report", rep


def windrive_life(windrive, normal, shutdown, channel, m):
    command = [windrive, "life", "--normal", normal, "--shutdown", shutdown, "--channel", channel,
               "--weibull", "2,11", "--cut-in", "11", "--cut-out", "12", "--bin-width", "0",
               "--years", "20", "--shutdowns-per-year", "50", "--m", m, "--json"]  # fmt: skip
    return json.loads(subprocess.run(command, capture_output=True, text=True, check=True).stdout)


def test_report_agrees_with_windrive_life(tiny_life, windrive):
    out, report, rep = tiny_life
    assert rep.returncode == 0, rep.stderr
    t = pd.read_parquet(out / "tiny-life.parquet")
    normal = out / "cases" / t[t.group == "dlc12"].id.iloc[0] / "series.parquet"
    shutdown = out / "cases" / t[t.group == "event"].id.iloc[0] / "series.parquet"
    ours = json.loads((report / "lifetime.json").read_text())
    for channel, m in [(LSS, "3,6"), ("torsional.hss_torque", "6,9")]:
        theirs = windrive_life(windrive, normal, shutdown, channel, m)
        assert ours["operating_hours"] == pytest.approx(theirs["operating_hours"], rel=1e-12)
        assert ours["reference_s"] == theirs["life_hours"] * 3600
        # docs/CAMPAIGNS.md quotes the hours
        hours = f"{ours['operating_hours']:,.1f}".replace(",", " ")
        assert f"The operating hours agree too: {hours} h." in " ".join((ROOT / "docs/CAMPAIGNS.md").read_text().split())
        for d in theirs["lifetime_del"]:
            (row,) = [r for r in ours["lifetime"] if r["channel"] == channel and r["m"] == d["m"]]
            assert row["lifetime_del"] == pytest.approx(d["del"], rel=1e-9)
            assert row["share"]["shutdown-rated"] == pytest.approx(d["shutdown_share"], rel=1e-9)


def test_report_writes_its_files_and_table(tiny_life):
    out, report, rep = tiny_life
    t = pd.read_parquet(out / "tiny-life.parquet")
    assert (report / "lifetime.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    table = pd.read_csv(report / "lifetime.csv")
    hss = "torsional.hss_torque"
    assert list(zip(table.channel, table.m)) == [(LSS, 3), (LSS, 6), (hss, 6), (hss, 9)]
    assert (table["share:DLC 1.2 11 m/s"] + table["share:shutdown-rated"]).tolist() == pytest.approx([1.0] * 4)
    ldd = pd.read_csv(report / "lifetime_ldd.csv")
    assert len(ldd) == 12 and (ldd.channel == LSS).all()
    # every lifetime second in a bin: the operating hours plus 1000 shutdowns of their analysed seconds
    event_s = t[t.group == "event"].analysed_s.iloc[0]
    hours = t[t.group == "dlc12"].hours.iloc[0]
    assert ldd.seconds.sum() == pytest.approx(hours * 3600 + 1000 * event_s, rel=1e-9)
    # the printed ratio is the shutdown's DEL over normal operation's, at m = 6, from the table
    ratio = t[t.group == "event"][f"{LSS}.del_m6"].iloc[0] / t[t.group == "dlc12"][f"{LSS}.del_m6"].iloc[0]
    line = f"{LSS}: shutdown-rated / normal operation (DLC 1.2, climate-weighted): ours {ratio:.2f}, thesis 3.65"
    assert line in rep.stdout
    assert "share of D [%]" in rep.stdout and rep.stderr == ""


# ---------------------------------------------------------------------------------------------------
# errors: one line, no traceback, and unfinished cases counted


def test_no_table_is_named(tmp_path):
    (tmp_path / "empty").mkdir()
    one_line_error(campaign_cli("report", tmp_path / "empty"), "no campaign table", "scripts/campaign run")


def test_a_file_that_is_no_campaign_table_is_named(tmp_path):
    (tmp_path / "garbage.parquet").write_text("not parquet")
    one_line_error(campaign_cli("report", tmp_path / "garbage.parquet"), "garbage.parquet: cannot read the table")
    pq.write_table(pa.table({"x": [1.0]}), tmp_path / "other.parquet")
    one_line_error(campaign_cli("report", tmp_path / "other.parquet"), "not a campaign table (no column name, group")


def test_a_campaign_file_never_run_is_named(tmp_path):
    # the campaign file's results would be in results/campaigns/tiny-life under the working directory
    r = campaign_cli("report", TINY_LIFE, cwd=tmp_path)
    one_line_error(r, "results/campaigns/tiny-life: no campaign folder")


def test_a_table_of_grid_cases_only_has_no_lifetime(tmp_path):
    rows = [r for r in synthetic_rows() if r["group"] == "grid"]
    folder = write_synthetic(tmp_path / "grid", rows)
    one_line_error(campaign_cli("report", folder), "no finished DLC 1.2 or event case", "1 grid (no weight)")


def test_unfinished_cases_are_left_out_and_counted(tmp_path):
    rows = synthetic_rows()
    rows[1] = {**rows[1], "status": "pending", f"{LSS}.del_m3": math.nan}
    folder = write_synthetic(tmp_path / "partial", rows)
    r = campaign_cli("report", folder)
    assert r.returncode == 1, r.stderr
    assert "not in the lifetime: 1 failed: dlc12-v14-s1" in r.stderr
    assert "not in the lifetime: 1 pending: dlc12-v10-s2" in r.stderr
    assert "lower bound" in r.stderr and "Traceback" not in r.stderr
    # the report covers the finished cases: the pending seed adds nothing
    life = json.loads((folder / "lifetime.json").read_text())
    v10 = 100 * 3600 * 0.5 * 2.0**3
    assert life["lifetime"][0]["damage_sum"] == pytest.approx(v10 + 2_430_000 + 15_000_000, rel=1e-12)
    assert life["cases_left_out"]["pending"] == ["dlc12-v10-s2"]


def test_compute_refuses_an_empty_table():
    with pytest.raises(CampaignError, match="the table is empty"):
        lt.compute(pd.DataFrame(columns=["name", "group", "status"]), META)


# ---------------------------------------------------------------------------------------------------
# the lifetime interval's coverage over few seeds

COVERAGE_SIGMA = 0.6  # lognormal damage over seeds: CV 0.66, as C's LSS torque at m = 6 (docs/CAMPAIGNS.md)
COVERAGE_TRIALS = 200


def _synthetic_campaign(rng, seeds: int):
    """Three DLC 1.2 bins (30 000, 20 000, 10 000 h) of `seeds` 600 s cases each, their damage DEL^6
    lognormal(0, σ), and the expected lifetime damage sum."""
    hours = {8.0: 3e4, 12.0: 2e4, 16.0: 1e4}
    rows = []
    for v, h in hours.items():
        for s in range(1, seeds + 1):
            rows.append({"status": "ok", "error": "", "name": f"dlc12-v{v:g}-s{s}", "group": "dlc12", "seed": s,
                         "wind_speed": v, "hours": h / seeds, "probability": math.nan, "events": math.nan,
                         "param.rotor.wind_speed": math.nan, "analysed_s": 600.0,
                         f"{LSS}.del_m6": rng.lognormal(0.0, COVERAGE_SIGMA) ** (1 / 6)})  # fmt: skip
    truth = sum(h * 3600.0 * math.exp(COVERAGE_SIGMA**2 / 2) for h in hours.values())  # f_eq 1 Hz
    return pd.DataFrame(rows), truth


HOURS_SHARE = 3e4 / 6e4  # the 8 m/s bin's expected share of the lifetime damage


def coverage(seeds: int) -> tuple[float, float, float]:
    """How often the report's 95 % intervals hold the truth: of the lifetime damage sum and of the 8 m/s bin's
    share; and how often a percentile bootstrap of each bin's seeds (the report's earlier method, numpy
    here) held the sum's."""
    rng = np.random.default_rng(seeds)
    meta = {"campaign": "coverage", "years": 20.0, "feq_hz": 1.0, "ldd_bins": {}}
    t_hits = share_hits = boot_hits = 0
    for _ in range(COVERAGE_TRIALS):
        t, truth = _synthetic_campaign(rng, seeds)
        row = lt.compute(t, meta).rows[0]
        lo, hi = row["damage_sum_ci"]
        t_hits += lo <= truth <= hi
        s_lo, s_hi = row["share_ci"]["DLC 1.2 8 m/s"]
        share_hits += s_lo <= HOURS_SHARE <= s_hi
        x = (t[f"{LSS}.del_m6"].to_numpy() ** 6 * t["hours"].to_numpy() * 3600.0).reshape(3, seeds)
        draws = np.take_along_axis(np.broadcast_to(x, (2000, 3, seeds)), rng.integers(0, seeds, (2000, 3, seeds)), 2)
        b_lo, b_hi = np.percentile(draws.sum(axis=(1, 2)), [2.5, 97.5])
        boot_hits += b_lo <= truth <= b_hi
    return t_hits / COVERAGE_TRIALS, share_hits / COVERAGE_TRIALS, boot_hits / COVERAGE_TRIALS


def test_the_lifetime_interval_covers_over_few_seeds_where_a_bootstrap_does_not():
    """The report's intervals of a lifetime damage sum and of a bin's share (Student's t over each bin's
    seeds) against the truth of synthetic campaigns, beside a percentile bootstrap of the same seeds;
    docs/CAMPAIGNS.md quotes them."""
    t2, s2, b2 = coverage(2)
    t6, s6, b6 = coverage(6)
    assert min(t2, t6, s2, s6) >= 0.88 and b2 < 0.75 and b6 < t6, (t2, s2, b2, t6, s6, b6)
    text = " ".join((ROOT / "docs" / "CAMPAIGNS.md").read_text().split())
    quoted = (f"in {100 * b2:.0f} % of them with 2 seeds a bin and {100 * b6:.0f} % with 6, t in {100 * t2:.0f} % "
              f"and {100 * t6:.0f} % (a bin's share: {100 * s2:.0f} % and {100 * s6:.0f} %)")  # fmt: skip
    assert quoted in text, quoted
