"""Gear damage in campaigns ([gears], python/windrive_campaign/gears.py) and several grids ([[grid]]):
the campaign file's errors, the gear table (P, a gearbox6dof preset or a description file) and the
channels windrive says it reads, a table windrive refuses stopped before any case runs, the union of
grids and its case names and ids, a failing `windrive gears` recorded as a failed case, the probe that
stops a campaign whose series it cannot rate, and a real campaign of scenes/p-normal (a turbulent and a
steady case, 12 s, 4 s discarded) on a 2-worker LocalCluster whose gear columns are `windrive gears` on
the kept series. About 15 s on 2 cores."""

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
from windrive_campaign import cases, driver, gears, runner, schema  # noqa: E402
from windrive_campaign.errors import CampaignError  # noqa: E402

SCENE = ROOT / "scenes" / "p-normal"
TEETH = ["s1", "p1", "ps1", "pr1", "r1", "s2", "p2", "ps2", "pr2", "r2", "p3", "g3"]


def campaign(top="", tables='[grid]\nrotor.wind_speed = [11.5]'):
    """A valid campaign of scenes/p-normal; `top` adds top-level keys, `tables` replaces the load cases."""
    return f"""scene = "{SCENE}"
stop_time = 2.0
{top}
[[channel]]
name = "torsional.lss_torque"
{tables}
"""


# ---------------------------------------------------------------------------------------------------
# the campaign file

TWO_GRIDS = """[[grid]]
rotor.turbulence = ["ntm"]
rotor.wind_speed = [11.5, 18.0]
rotor.turbulence_intensity = [0.09, 0.14]
[[grid]]
rotor.turbulence = ["none"]
rotor.wind_speed = [11.5, 18.0]
"""


@pytest.mark.parametrize(
    "text, message, line",
    [
        (campaign(tables=TWO_GRIDS + '[gears]\ntable = "no/such.toml"'), "gears.table: ", 14),
        (campaign(tables=TWO_GRIDS + '[gears]\ntabel = "P"'), "gears.tabel: unknown key (known here: table, fmu, component, face_load, dynamic_factor)", 14),
        (campaign(tables=TWO_GRIDS + "[gears]\ntable = 1"), "gears.table: must be a non-empty string", 14),
        (campaign(tables=TWO_GRIDS + "[gears]"),
         "gears.table: missing (the gear table: P, a gearbox6dof preset or a description file)", 13),
        (campaign(tables=TWO_GRIDS + '[gears]\ntable = "P"\ncomponent = "gear box"'),
         "gears.component: 'gear box': a scene component's name", 15),
        (campaign(tables=TWO_GRIDS + '[gears]\ntable = "P"\nfmu = "simpack"'),
         "gears.fmu: must be one of torsional, gearbox6dof, not 'simpack'", 15),
        (campaign(top='gears = "P"'), "gears: must be a table, not a string", 3),
        (campaign(tables=TWO_GRIDS + '[gears]\ntable = "P"\nface_load = "iso"'),
         "gears.face_load: must be one of one, model, not 'iso'", 15),
        (campaign(tables=TWO_GRIDS + '[gears]\ntable = "P"\nface_load = "model"'),
         "gears.face_load: model reads gearbox6dof's face_load_factor_<mesh> outputs", 15),
        (campaign(tables=TWO_GRIDS + '[gears]\ntable = "P"\ndynamic_factor = 0.9'),
         "gears.dynamic_factor: must be at least 1.0, not 0.9", 15),
        (campaign(tables=TWO_GRIDS + "[[grid]]\n"), "grid[3]: no axis", 13),
        (campaign(tables=TWO_GRIDS.replace('["none"]', '"none"')), "grid[2].rotor.turbulence: a grid axis is a", 11),
        (campaign(tables=TWO_GRIDS.replace("[0.09, 0.14]\n[[grid]]", "[0.09, 0.14]\nspeed = [1]\n[[grid]]")),
         "grid[1].speed: a parameter is named component.variable", 10),
        (campaign(top="grid = 3", tables=""), "grid: must be a table [grid] or an array of tables [[grid]]", 3),
    ],
)
def test_schema_errors_name_file_key_and_line(tmp_path, text, message, line):
    path = write_campaign(tmp_path, text)
    with pytest.raises(CampaignError) as e:
        schema.load(path)
    assert message in str(e.value)
    assert str(e.value).startswith(f"{path}:{line}:"), str(e.value)
    if "no/such.toml" in text:  # a description file is relative to the campaign file, as for [bearings]
        assert f"{tmp_path / 'no' / 'such.toml'}: no such gearbox description file" in str(e.value)


def listed(windrive, *options):
    """What `windrive gears --channels` prints with `options`."""
    r = subprocess.run([windrive, "gears", "--channels", *options], capture_output=True, text=True, check=True)
    return r.stdout.split()


def test_gears_is_analysis_not_simulation(tmp_path, windrive):
    """[gears] changes what a case's series is analysed for, not the series: the analysis digest changes
    (finished cases are rated on the next run), the ids do not. Without it the digest is the one of
    campaigns written before [gears] existed, and table P's the one it had when P was the only table."""
    plain = schema.load(write_campaign(tmp_path, campaign(), "a.toml"))
    rated = schema.load(write_campaign(tmp_path, campaign(tables='[grid]\nrotor.wind_speed = [11.5]\n[gears]\n'
                                                                 'table = "P"'), "b.toml"))  # fmt: skip
    assert plain.gears is None and rated.gears == gears.Gears("P", "torsional", "torsional")
    assert "gears" not in plain.analysis_spec() and rated.analysis_spec()["gears"] == "P"
    assert rated.analysis_digest() == "b1739a688554d2c0"  # as before any table but P existed
    (a,) = cases.expand(plain, {plain.scene: ("s", "d")}, "w")
    (b,) = cases.expand(rated, {rated.scene: ("s", "d")}, "w")
    assert a.id == b.id and a.analysis_digest != b.analysis_digest
    # the cases record what windrive gears says it reads, besides the analysed channels
    assert driver.recorded(plain) == ["torsional.lss_torque"]
    channels = listed(windrive, "--gearbox", "P")
    assert channels[-1] == "torsional.mesh_force_gear_pinion_1" and len(channels) == 6
    assert driver.recorded(rated, windrive) == ["torsional.lss_torque", *channels]


def test_a_gearbox6dof_preset_is_a_gear_table(tmp_path, windrive):
    """Any gearbox6dof description is a table: its channels are those windrive prints for it (GRC 750:
    one planetary and two parallel stages), named after the gearbox6dof FMU."""
    c = schema.load(write_campaign(tmp_path, campaign(tables='[grid]\nrotor.wind_speed = [11.5]\n[gears]\n'
                                                             'table = "grc750"\nfmu = "gearbox6dof"')))  # fmt: skip
    assert c.gears == gears.Gears("grc750", "gearbox6dof", "gearbox")
    assert c.analysis_spec()["gears"] == {"table": "grc750", "fmu": "gearbox6dof", "component": "gearbox"}
    channels = listed(windrive, "--gearbox", "grc750", "--fmu", "gearbox6dof", "--component", "gearbox")
    assert "gearbox.mesh_force_gear_pinion_2" in channels and "gearbox.mesh_force_sun_planet2_1" not in channels
    assert c.gears.channels(windrive) == tuple(channels)
    assert driver.recorded(c, windrive) == ["torsional.lss_torque", *channels]


def test_the_models_face_load_is_asked_for_and_read(tmp_path, windrive):
    """face_load = "model" rates with each sample's K_Hβ from gearbox6dof (`windrive gears --face-load
    model`): the spec says so, the cases record the face_load_factor channels windrive says it reads, and
    "one" is the unset default, which leaves the spec and digest as they were."""
    section = '[grid]\nrotor.wind_speed = [11.5]\n[gears]\ntable = "grc750"\nfmu = "gearbox6dof"\n'
    plain = schema.load(write_campaign(tmp_path, campaign(tables=section), "a.toml"))
    one = schema.load(write_campaign(tmp_path, campaign(tables=section + 'face_load = "one"'), "b.toml"))
    model = schema.load(write_campaign(tmp_path, campaign(tables=section + 'face_load = "model"'), "c.toml"))
    assert plain.gears == one.gears and plain.analysis_digest() == one.analysis_digest()
    assert model.gears == gears.Gears("grc750", "gearbox6dof", "gearbox", "model")
    assert model.analysis_spec()["gears"] == {"table": "grc750", "fmu": "gearbox6dof", "component": "gearbox",
                                              "face_load": "model"}
    assert model.analysis_digest() != plain.analysis_digest()
    channels = listed(windrive, "--gearbox", "grc750", "--fmu", "gearbox6dof", "--component", "gearbox",
                      "--face-load", "model")
    assert "gearbox.face_load_factor_sun_planet_1" in channels
    assert model.gears.channels(windrive) == tuple(channels)
    assert set(plain.gears.channels(windrive)) < set(channels)


def test_the_dynamic_factor_reaches_the_rating(tmp_path):
    """dynamic_factor = K_v rates every mesh with ISO 6336-1's K_v (`windrive gears --dynamic-factor`): the
    spec and the command line carry it; unset is 1 and leaves the spec and digest as they were."""
    section = '[grid]\nrotor.wind_speed = [11.5]\n[gears]\ntable = "P"\n'
    plain = schema.load(write_campaign(tmp_path, campaign(tables=section), "a.toml"))
    one = schema.load(write_campaign(tmp_path, campaign(tables=section + "dynamic_factor = 1"), "b.toml"))
    k_v = schema.load(write_campaign(tmp_path, campaign(tables=section + "dynamic_factor = 1.05"), "c.toml"))
    assert plain.gears == one.gears and plain.analysis_digest() == one.analysis_digest()
    assert k_v.analysis_spec()["gears"]["dynamic_factor"] == 1.05
    assert k_v.analysis_digest() != plain.analysis_digest()
    assert k_v.gears.options()[-2:] == ["--dynamic-factor", "1.05"]


def test_a_description_file_is_relative_to_the_campaign_file(tmp_path, windrive):
    """As for [bearings]: a value with a `/` or ending in .toml is a file, found from the campaign file's
    folder and passed to windrive as an absolute path; it reads it as the preset it was copied from."""
    (tmp_path / "desc").mkdir()
    (tmp_path / "desc" / "grc.toml").write_text((ROOT / "fmus/gearbox6dof/resources/grc750.toml").read_text())
    (tmp_path / "campaigns").mkdir()
    section = '[grid]\nrotor.wind_speed = [11.5]\n[gears]\ntable = "../desc/grc.toml"\nfmu = "gearbox6dof"'
    path = write_campaign(tmp_path / "campaigns", campaign(tables=section))
    c = schema.load(path)
    assert c.gears.table == str(tmp_path / "desc" / "grc.toml")
    assert c.gears.channels(windrive) == gears.Gears("grc750", "gearbox6dof", "gearbox").channels(windrive)


def test_a_table_windrive_refuses_stops_the_campaign_before_any_case(tmp_path):
    """No list of tables in Python: windrive's own message, from asking it for the channels, before the
    scene's probe or any case runs."""
    path = write_campaign(tmp_path, campaign(tables='[grid]\nrotor.wind_speed = [11.5]\n[gears]\ntable = "Q"'))
    out = tmp_path / "out"
    r = campaign_cli("run", path, "--out", out, "--workers", 1)
    assert r.returncode == 2, r.stderr
    assert r.stderr.startswith(f"error: {path}: [gears] table = 'Q', fmu = 'torsional', component = 'torsional': "
                               "windrive gears cannot rate it: error: --gearbox \"Q\": use P")  # fmt: skip
    assert "presets are" in r.stderr and "Traceback" not in r.stderr
    assert not (out / "cases").exists() and not (out / "scenes").exists()


# ---------------------------------------------------------------------------------------------------
# several grids


def expand(tmp_path, text, name="c.toml"):
    c = schema.load(write_campaign(tmp_path, campaign(tables=text), name))
    return cases.expand(c, {c.scene: ("s", "d")}, "w")


def test_the_cases_are_the_union_of_the_grids(tmp_path):
    found = expand(tmp_path, TWO_GRIDS)
    assert [k.name for k in found] == [
        "grid-turbulence=ntm,wind_speed=11.5,turbulence_intensity=0.09",
        "grid-turbulence=ntm,wind_speed=11.5,turbulence_intensity=0.14",
        "grid-turbulence=ntm,wind_speed=18.0,turbulence_intensity=0.09",
        "grid-turbulence=ntm,wind_speed=18.0,turbulence_intensity=0.14",
        "grid-turbulence=none,wind_speed=11.5",
        "grid-turbulence=none,wind_speed=18.0",
    ]
    assert found[-1].params == {"rotor.turbulence": "none", "rotor.wind_speed": 18.0}
    assert {k.group for k in found} == {"grid"} and len({k.id for k in found}) == 6


def test_one_grid_as_table_or_array_gives_the_same_cases(tmp_path):
    """The old [grid] is a one-entry [[grid]]: same names, same ids, so its finished cases stay done."""
    axes = 'torsional.fidelity = ["2", "5"]\nrotor.wind_speed = [10.0, 12.0]\n'
    table = expand(tmp_path, "[grid]\n" + axes, "a.toml")
    array = expand(tmp_path, "[[grid]]\n" + axes, "b.toml")
    assert [(k.name, k.id) for k in table] == [(k.name, k.id) for k in array]
    assert table[0].name == "grid-fidelity=2,wind_speed=10.0"


def test_a_parameter_set_two_grids_reach_is_one_case(tmp_path):
    """Steady 11.5 m/s in both grids (axes in another order): one case, named by the first grid. The
    names of the other cases do not depend on it, so adding a grid renames nothing."""
    overlap = TWO_GRIDS + '[[grid]]\nrotor.wind_speed = [11.5, 14.0]\nrotor.turbulence = ["none"]\n'
    found = expand(tmp_path, overlap)
    names = [k.name for k in found]
    assert len(found) == 7 and len({k.id for k in found}) == 7
    assert names[:6] == [k.name for k in expand(tmp_path, TWO_GRIDS, "two.toml")]
    assert names[6] == "grid-wind_speed=14.0,turbulence=none"
    assert "grid-wind_speed=11.5,turbulence=none" not in names


def test_two_cases_with_one_name_are_an_error(tmp_path):
    # "1" and 1 are different parameter values (and ids) that print alike
    clash = '[[grid]]\nrotor.seed = [1]\n[[grid]]\nrotor.seed = ["1"]\n'
    # (the integer seed is the case's own, cases.case_seed; the string is left for windrive to refuse)
    with pytest.raises(CampaignError, match=r"two different cases are named grid-seed=1 \(rotor.seed=\d+ "
                                            r"rotor.turbulence_period=2.0 rotor.turbulence_scaling='period' and rotor.seed='1' "):  # fmt: skip
        expand(tmp_path, clash)


# ---------------------------------------------------------------------------------------------------
# a failing gear rating, the probe


def test_a_failing_gear_rating_fails_the_case_with_its_stderr(tmp_path, windrive):
    """run_case alone, as a worker runs it: the series lacks what windrive gears reads (not recorded), so
    the case is failed with windrive's own error."""
    c = schema.load(write_campaign(tmp_path, campaign(tables='[grid]\nrotor.wind_speed = [11.5]\n[gears]\n'
                                                             'table = "P"')))  # fmt: skip
    (case,) = cases.expand(c, {c.scene: (str(SCENE), "d")}, "w")
    case = dataclasses.replace(case, stop_time=0.5)
    spec = runner.RunSpec(windrive, str(tmp_path / "out"), c.channels, 1.0, False, ("torsional.lss_torque",),
                          timeout=60.0, gears=gears.Gears("P"))  # fmt: skip
    r = runner.run_case(case, spec)
    assert r["status"] == "failed" and r["returncode"] == 1, r["error"]
    assert r["error"].startswith("error: analysis: torsional.mesh_force_sun_planet_1 not in the series"), r["error"]
    assert r["stats"] == {}
    assert json.loads((tmp_path / "out" / "cases" / f"{case.id}.json").read_text())["status"] == "failed"


def test_the_probe_stops_a_campaign_whose_series_gears_cannot_rate(tmp_path, windrive):
    """Should the cases not record a channel windrive gears reads, the scene's 1 ms probe fails before
    any case runs, naming the channel."""
    channels = gears.Gears("P").channels(windrive)
    record = ["torsional.lss_torque", *channels[:-1]]  # the pinion's mesh force unrecorded
    with pytest.raises(CampaignError, match=r"windrive gears cannot rate its series: .*mesh_force_gear_pinion_1"):
        cases.snapshot_scene(SCENE, windrive, tmp_path, record, gears=gears.Gears("P"))
    record = ["torsional.lss_torque", *channels]
    ssp, _ = cases.snapshot_scene(SCENE, windrive, tmp_path, record, gears.Gears("P"))
    assert pathlib.Path(ssp).is_file()


# ---------------------------------------------------------------------------------------------------
# a real campaign

REAL = f"""scene = "{SCENE}"
stop_time = 12.0
transient = 4.0
keep_series = true

[gears]
table = "P"

[[channel]]
name = "torsional.lss_torque"
m = [6]

[[grid]]
rotor.turbulence = ["ntm"]
rotor.wind_speed = [11.5]
rotor.turbulence_intensity = [0.14]
rotor.seed = [1]

[[grid]]
rotor.turbulence = ["none"]
rotor.wind_speed = [11.5]
"""


@pytest.fixture(scope="module")
def real_run(tmp_path_factory):
    return run_campaign(tmp_path_factory.mktemp("gears"), REAL, "gears")


def test_gear_columns_are_windrive_gears_on_the_kept_series(real_run, windrive):
    out, t = real_run
    assert list(t.name) == ["grid-turbulence=ntm,wind_speed=11.5,turbulence_intensity=0.14,seed=1",
                              "grid-turbulence=none,wind_speed=11.5"]  # fmt: skip
    assert (t.status == "ok").all() and (t.analysis_s > 0).all()
    for _, row in t.iterrows():
        series = out / "cases" / row.id / "series.parquet"
        header = pq.read_schema(series).names
        assert header == ["time", "torsional.lss_torque", *gears.Gears("P").channels(windrive)]  # no more
        command = [windrive, "gears", series, "--gearbox", "P", "--fmu", "torsional", "--component", "torsional",
                   "--transient", "4", "--json"]
        theirs = json.loads(subprocess.run(command, capture_output=True, text=True, check=True).stdout)
        assert [tooth["name"] for tooth in theirs] == TEETH
        for tooth in theirs:
            for column, field in gears.COLUMNS.items():
                ours = row[f"gear.{tooth['name']}.{column}"]
                if tooth[field] is None:
                    assert math.isnan(ours), (tooth["name"], column)
                else:
                    assert ours == pytest.approx(tooth[field], rel=1e-12), (tooth["name"], column)
    # damage where windrive rates it: a planet's root on p1, its flanks on ps1 and pr1
    turbulent = t[t["param.rotor.turbulence"] == "ntm"].iloc[0]
    assert turbulent["gear.p1.root_day"] > 0 and math.isnan(turbulent["gear.p1.flank_day"])
    assert turbulent["gear.ps1.flank_day"] > 0 and math.isnan(turbulent["gear.ps1.root_day"])


def test_the_paper_report_runs_on_a_real_table(real_run, tmp_path):
    """The steady and the TI 14 % case at 11.5 m/s are the least the comparison needs: η of the turbulent
    cell is its damage over the steady one's."""
    out, t = real_run
    r = campaign_cli("paper", out, "--out", tmp_path)
    assert r.returncode == 0, r.stderr
    t7 = pd.read_csv(tmp_path / "paper_table7.csv")
    row = t7[(t7.wind_speed == 11.5) & (t7.ti_pct == 14.0)].iloc[0]
    steady = t[t["param.rotor.turbulence"] == "none"].iloc[0]
    turbulent = t[t["param.rotor.turbulence"] == "ntm"].iloc[0]
    expected = (turbulent["gear.r1.root_day"] / steady["gear.r1.root_day"] - 1) * 100
    assert row["r1 bending ours"] == pytest.approx(expected, rel=1e-12)
    t6 = pd.read_csv(tmp_path / "paper_table6.csv")
    assert t6["ours_11.5"].iloc[0] == pytest.approx(turbulent["gear.s1.root_day"], rel=1e-12)
