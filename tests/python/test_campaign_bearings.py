"""Bearing damage in campaigns ([bearings], python/windrive_campaign/bearings.py, windrive life --cases):
the campaign file's errors, [bearings] as analysis (digest, recorded channels asked of windrive), a
gearbox without roller sets stopped before any case runs, a failing `windrive bearings` recorded as a
failed case, the probe, and a real campaign of scenes/d-shutdown-6dof (the GRC 750 kW gearbox; one
DLC 1.2 case and a shutdown, 1.5 s each at 5 slices) on a 2-worker LocalCluster: its bearing columns
are `windrive bearings` on the kept series, and its lifetime report is the weighted sum of the table.
About 7-9 s on 2 cores."""

import dataclasses
import json
import math
import pathlib
import subprocess
import sys

import pandas as pd
import pyarrow.parquet as pq
import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "python"))

from campaign_cli import campaign_cli, run_campaign, write_campaign  # noqa: E402
from windrive_campaign import bearings, cases, driver, gears, lifetime, runner, schema  # noqa: E402
from windrive_campaign.errors import CampaignError  # noqa: E402

SCENE = ROOT / "scenes" / "d-shutdown-6dof"
TORQUE = "gearbox.lss_torque"
# every GRC bearing has a roller set (bearing_set.rs, grc_bearings_turn_with_the_gear_ratios)
GRC = ["carrier_a", "carrier_b", "planet_1_uw", "planet_1_dw", "planet_2_uw", "planet_2_dw", "planet_3_uw",
       "planet_3_dw", "lss_a", "lss_b", "ims_a", "ims_b", "ims_c", "hss_a", "hss_b", "hss_c"]  # fmt: skip


def campaign(section="[bearings]", top=""):
    """A valid campaign of scenes/d-shutdown-6dof with `section` last."""
    return f"""scene = "{SCENE}"
stop_time = 1.0
{top}
[[channel]]
name = "{TORQUE}"

[[event]]
name = "shutdown"
per_year = 1

{section}
"""


# ---------------------------------------------------------------------------------------------------
# the campaign file


@pytest.mark.parametrize(
    "section, top, message, line",
    [
        ('[bearings]\ngerbox = "grc750"', "", "bearings.gerbox: unknown key (known here: gearbox, component, oil_", 12),
        ("[bearings]\noil_viscosity = [24, 320]", "", "bearings.oil_viscosity: the viscosity at 40 °C is the larger", 12),
        ("[bearings]\noil_viscosity = 320", "", "bearings.oil_viscosity: must be [ν at 40 °C, ν at 100 °C]", 12),
        ("[bearings]\ncontamination = 1.5", "", "bearings.contamination: ISO 281's e_C lies in 0 to 1", 12),
        ('[bearings]\noil_temperature = "hot"', "", "bearings.oil_temperature: must be a finite number", 12),
        ('[bearings]\ngearbox = ""', "", "bearings.gearbox: must be a non-empty string, not ''", 12),
        ("[bearings]\ngearbox = 750", "", "bearings.gearbox: must be a non-empty string, not 750", 12),
        ('[bearings]\ncomponent = "gear box"', "", "bearings.component: 'gear box': a scene component's name", 12),
        ('[bearings]\ngearbox = "no/such.toml"', "", "bearings.gearbox: ", 12),
        ("", 'bearings = "grc750"', "bearings: must be a table, not a string", 3),
    ],
)
def test_schema_errors_name_file_key_and_line(tmp_path, section, top, message, line):
    path = write_campaign(tmp_path, campaign(section, top))
    with pytest.raises(CampaignError) as e:
        schema.load(path)
    assert message in str(e.value)
    assert str(e.value).startswith(f"{path}:{line}:"), str(e.value)
    if "no/such.toml" in section:  # a description file is relative to the campaign file
        assert f"{tmp_path / 'no' / 'such.toml'}: no such gearbox description file" in str(e.value)


def test_bearings_is_analysis_not_simulation(tmp_path, windrive):
    """[bearings] changes what a case's series is analysed for, not the series: the analysis digest
    changes, the ids do not, and a campaign without it keeps its digest. The cases record what windrive
    itself says `windrive bearings` reads; with [gears] too, both lists."""
    plain = schema.load(write_campaign(tmp_path, campaign(section=""), "a.toml"))
    rated = schema.load(write_campaign(tmp_path, campaign(), "b.toml"))
    assert plain.bearings is None and rated.bearings == bearings.Bearings("grc750", "gearbox")
    assert "bearings" not in plain.analysis_spec()
    assert rated.analysis_spec()["bearings"] == {"gearbox": "grc750", "component": "gearbox"}
    (a,) = cases.expand(plain, {plain.scene: ("s", "d")}, "w")
    (b,) = cases.expand(rated, {rated.scene: ("s", "d")}, "w")
    assert a.id == b.id and a.analysis_digest != b.analysis_digest

    listed = subprocess.run([windrive, "bearings", "--channels"], capture_output=True, text=True, check=True)
    channels = listed.stdout.split()
    assert len(channels) == 2 * len(GRC) + 2 and "gearbox.planet_1_uw_axial_load" in channels
    assert driver.recorded(rated, windrive) == [TORQUE, *channels]

    both = schema.load(write_campaign(tmp_path, campaign('[gears]\ntable = "P"\nfmu = "gearbox6dof"\n[bearings]'),
                                      "both.toml"))  # fmt: skip
    assert both.gears == gears.Gears("P", "gearbox6dof", "gearbox") and both.bearings == rated.bearings
    recorded = driver.recorded(both, windrive)
    assert recorded == list(dict.fromkeys([TORQUE, *both.gears.channels(windrive), *channels]))


def test_a_description_file_is_relative_to_the_campaign_file(tmp_path, windrive):
    """As a scene is: the workers' working directory is not the user's. windrive reads it as it reads
    the preset it was copied from."""
    (tmp_path / "desc").mkdir()
    (tmp_path / "desc" / "grc.toml").write_text((ROOT / "fmus/gearbox6dof/resources/grc750.toml").read_text())
    (tmp_path / "campaigns").mkdir()
    path = write_campaign(tmp_path / "campaigns", campaign('[bearings]\ngearbox = "../desc/grc.toml"'))
    c = schema.load(path)
    assert c.bearings.gearbox == str(tmp_path / "desc" / "grc.toml")
    assert c.bearings.channels(windrive) == bearings.Bearings().channels(windrive)


def test_a_gearbox_without_roller_sets_stops_the_campaign_before_any_case(tmp_path):
    """nrel5mw describes no roller set: windrive's own message, from asking it for the channels, before
    the scene's probe or any case runs."""
    path = write_campaign(tmp_path, campaign('[bearings]\ngearbox = "nrel5mw"'))
    out = tmp_path / "out"
    r = campaign_cli("run", path, "--out", out, "--workers", 1)
    assert r.returncode == 2, r.stderr
    assert r.stderr.startswith(f"error: {path}: [bearings] gearbox = 'nrel5mw', component = 'gearbox': ")
    assert "error: --gearbox nrel5mw: no bearing has a roller set" in r.stderr and "Traceback" not in r.stderr
    assert not (out / "cases").exists() and not (out / "scenes").exists()


# ---------------------------------------------------------------------------------------------------
# a failing bearing rating, the probe


def test_a_failing_bearing_rating_fails_the_case_with_its_stderr(tmp_path, windrive):
    """run_case alone, as a worker runs it: the series lacks the bearing loads (not recorded), so the
    case is failed with windrive's own error."""
    c = schema.load(write_campaign(tmp_path, campaign()))
    (case,) = cases.expand(c, {c.scene: (str(SCENE), "d")}, "w")
    case = dataclasses.replace(case, stop_time=0.05, params={"gearbox.slices": 5})
    spec = runner.RunSpec(windrive, str(tmp_path / "out"), c.channels, 1.0, False, (TORQUE,), timeout=60.0,
                          bearings=bearings.Bearings())  # fmt: skip
    r = runner.run_case(case, spec)
    assert r["status"] == "failed" and r["returncode"] == 1, r["error"]
    assert r["error"].startswith("error: analysis: gearbox.carrier_a_radial_load not in the series"), r["error"]
    assert r["stats"] == {}


def test_the_probe_stops_a_campaign_whose_series_bearings_cannot_rate(tmp_path, windrive):
    """A probe series without what windrive bearings reads stops the campaign before any case runs."""
    rated = bearings.Bearings()
    with pytest.raises(CampaignError, match=r"\[bearings\] gearbox = 'grc750', component = 'gearbox': windrive "
                                            r"bearings cannot rate its series: .*carrier_a_radial_load"):  # fmt: skip
        cases.snapshot_scene(SCENE, windrive, tmp_path, [TORQUE], bearings=rated)
    ssp, _ = cases.snapshot_scene(SCENE, windrive, tmp_path, [TORQUE, *rated.channels(windrive)], bearings=rated)
    assert pathlib.Path(ssp).is_file()


def test_bearings_rated_with_two_ratings_are_an_error():
    """Cases rated with different descriptions (C_r differs) do not add up."""
    ok = pd.DataFrame({"name": ["a", "b"], "group": "event", "status": "ok", "wind_speed": math.nan, "hours": math.nan,
                       "events": 1.0, "analysed_s": 10.0, "bearing.x.day": [1.0, 2.0], "bearing.x.c": [1e6, 2e6]})  # fmt: skip
    with pytest.raises(CampaignError, match=r"campaign k: bearing x has C_r = 1000000, 2000000 N in different"):
        lifetime.compute(ok, {"campaign": "k"})


# ---------------------------------------------------------------------------------------------------
# a real campaign

REAL = f"""scene = "{SCENE}"
stop_time = 1.5
transient = 0.2
keep_series = true
params = {{ "gearbox.slices" = 5 }}     # 5 slices per bearing and mesh instead of 35: cheaper

[bearings]
gearbox = "grc750"
oil_temperature = 75.0  # a warmer oil than windrive's estimate: the a_ISO columns must follow it

[[channel]]
name = "{TORQUE}"

[climate]
weibull = {{ k = 2.0, A = 11.0 }}
years = 20

[dlc12]
cut_in = 14.0
cut_out = 15.0          # one bin at 14 m/s
seeds = 1
turbulence_class = "B"

[[event]]
name = "shutdown-rated"
per_year = 50
transient = 0.0
params = {{ "rotor.shutdown_time" = 0.3 }}
"""


@pytest.fixture(scope="module")
def real_run(tmp_path_factory):
    return run_campaign(tmp_path_factory.mktemp("bearings"), REAL, "bearings")


def test_bearing_columns_are_windrive_bearings_on_the_kept_series(real_run, windrive):
    out, t = real_run
    assert list(t.name) == ["dlc12-v14-s1", "event-shutdown-rated"]
    assert (t.status == "ok").all() and (t.analysis_s > 0).all()
    for _, row in t.iterrows():
        series = out / "cases" / row.id / "series.parquet"
        header = pq.read_schema(series).names
        assert header == ["time", TORQUE, *bearings.Bearings().channels(windrive)]  # recorded: no more
        command = [windrive, "bearings", series, "--gearbox", "grc750", "--component", "gearbox",
                   "--transient", repr(row.transient), "--oil-temperature", "75", "--json"]  # fmt: skip
        theirs = json.loads(subprocess.run(command, capture_output=True, text=True, check=True).stdout)
        # the oil reached the analysis: at windrive's default 65 °C a slow planet bearing's modified damage
        # differs (a fast bearing's a_ISO may sit at its cap of 50 at both temperatures)
        default = json.loads(subprocess.run(command[:-3] + ["--json"], capture_output=True, text=True,
                                            check=True).stdout)  # fmt: skip
        planet = GRC.index("planet_1_uw")
        assert default[planet]["modified_damage"] < theirs[planet]["modified_damage"], "a warmer oil is thinner"
        # the default spelled out in windrive bearings' own flags is the default
        spelled = command[:-3] + ["--oil-viscosity", "320,24", "--oil-temperature", "65", "--contamination", "0.5",
                                  "--json"]  # fmt: skip
        assert json.loads(subprocess.run(spelled, capture_output=True, text=True, check=True).stdout) == default
        assert [b["name"] for b in theirs] == GRC
        for b in theirs:
            for column, field in bearings.COLUMNS.items():
                assert row[f"bearing.{b['name']}.{column}"] == pytest.approx(b[field], rel=1e-12), (b["name"], column)
        assert row["bearing.hss_a.day"] > 0 and row["bearing.planet_1_uw.revolutions"] > 0


def test_the_lifetime_report_is_the_weighted_sum_of_the_table(real_run, tmp_path):
    """D_life of every bearing = Σ w_i · day_i · T_i / 86 400 from the table, here in its other form: a
    DLC 1.2 case adds its hours / 24 days of damage per day, the shutdown 1000 windows (50 a year for
    20 years) of T_i seconds. Shares sum to 1, the life is 20 years / D_life."""
    out, t = real_run
    r = campaign_cli("report", out, "--out", tmp_path)
    assert r.returncode == 0, r.stderr
    dlc, event = t.iloc[0], t.iloc[1]
    assert dlc.group == "dlc12" and event.group == "event" and event.events == 1000
    table = pd.read_csv(tmp_path / "lifetime_bearings.csv")
    groups = ["DLC 1.2 14 m/s", "shutdown-rated"]
    assert list(table.columns) == ["bearing", "dynamic_load_rating", "damage", "damage_lo", "damage_hi", "life_years",
                                   "events_share", "modified_damage", "modified_events_share",
                                   "thesis_damage", "thesis_events_share", *(f"share:{g}" for g in groups)]  # fmt: skip
    assert list(table.bearing) == GRC
    for _, b in table.iterrows():
        parts = {
            groups[0]: dlc.hours / 24 * dlc[f"bearing.{b.bearing}.day"],
            groups[1]: event.events * event[f"bearing.{b.bearing}.day"] * event.analysed_s / 86400,
        }
        damage = sum(parts.values())
        assert damage > 0
        assert b.damage == pytest.approx(damage, rel=1e-12), b.bearing
        assert b.life_years == pytest.approx(20 / damage, rel=1e-12), b.bearing
        assert b.dynamic_load_rating == dlc[f"bearing.{b.bearing}.c"] == event[f"bearing.{b.bearing}.c"]
        for g in groups:
            assert b[f"share:{g}"] == pytest.approx(parts[g] / damage, rel=1e-12), (b.bearing, g)
        assert sum(b[f"share:{g}"] for g in groups) == pytest.approx(1.0, rel=1e-12)
        assert b.events_share == pytest.approx(parts[groups[1]] / damage, rel=1e-12)
        # the thesis's count, summed alike from its own column
        thesis = {
            groups[0]: dlc.hours / 24 * dlc[f"bearing.{b.bearing}.thesis_day"],
            groups[1]: event.events * event[f"bearing.{b.bearing}.thesis_day"] * event.analysed_s / 86400,
        }
        assert b.thesis_damage == pytest.approx(sum(thesis.values()), rel=1e-12), b.bearing
        assert b.thesis_events_share == pytest.approx(thesis[groups[1]] / sum(thesis.values()), rel=1e-12)
        # and ISO 281's modified life from its column
        modified = {
            groups[0]: dlc.hours / 24 * dlc[f"bearing.{b.bearing}.nm_day"],
            groups[1]: event.events * event[f"bearing.{b.bearing}.nm_day"] * event.analysed_s / 86400,
        }
        assert b.modified_damage == pytest.approx(sum(modified.values()), rel=1e-12), b.bearing
        assert b.modified_events_share == pytest.approx(modified[groups[1]] / sum(modified.values()), rel=1e-12)

    section = json.loads((tmp_path / "lifetime.json").read_text(), parse_constant=pytest.fail)["bearings"]
    assert section["method"].startswith("ISO 281 basic rating life L10") and "a_ISO·L10" in section["method"]
    assert [b["bearing"] for b in section["lifetime"]] == GRC
    assert section["lifetime"][0]["damage"] == pytest.approx(table.damage[0], rel=1e-15)
    assert (tmp_path / "lifetime_bearings.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert "bearing damage over 20 years" in r.stdout and "share of bearing damage [%]" in r.stdout
    hss_c = table.iloc[-1]
    assert (f"hss_c          {hss_c.dynamic_load_rating / 1e3:>8.0f} {hss_c.damage:>11.4e} "
            f"{hss_c.life_years:>13.4g} {100 * hss_c.events_share:>11.2f}   {hss_c.modified_damage:>13.4e} "
            f"{100 * hss_c.modified_events_share:>11.2f}   {hss_c.thesis_damage:>15.4e}") in r.stdout  # fmt: skip
    assert r.stdout.rstrip().endswith("lifetime_bearings.csv, lifetime_bearings.png")


def test_the_oil_is_left_out_of_the_spec_unless_set():
    """A [bearings] without oil keys gives the analysis the spec it always had (its digest unchanged); set
    keys reach the spec and the probe's `windrive bearings` command as windrive's own flags."""
    plain = bearings.Bearings()
    assert plain.spec() == {"gearbox": "grc750", "component": "gearbox"}
    assert "--oil-temperature" not in bearings.command("w", "s.csv", plain, 0.0)
    oil = bearings.Bearings(oil_viscosity=(220.0, 19.0), oil_temperature=70.0, contamination=0.3)
    assert oil.spec() == {"gearbox": "grc750", "component": "gearbox", "oil_viscosity": [220.0, 19.0],
                          "oil_temperature": 70.0, "contamination": 0.3}  # fmt: skip
    cmd = bearings.command("w", "s.csv", oil, 0.0)
    for flag, value in [("--oil-viscosity", "220.0,19.0"), ("--oil-temperature", "70.0"), ("--contamination", "0.3")]:
        assert cmd[cmd.index(flag) + 1] == value
