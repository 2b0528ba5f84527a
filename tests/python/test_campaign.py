"""The load-case campaign driver (python/windrive_campaign, docs/CAMPAIGNS.md): the campaign file's
errors, case expansion and climate weights against scipy and the thesis's operating hours, each case's
in-process analysis against `windrive del` and numpy, and real campaigns on a 2-worker LocalCluster: results,
a failing case, resume after completion, after a deleted result and after SIGINT, the Slurm job script
(test_slurm.py runs a campaign on a real Slurm).
Kept under a minute on a 2-core machine: cases simulate 2 to 10 s."""

import json
import math
import os
import pathlib
import signal
import subprocess
import sys
import time

import numpy as np
import pandas as pd
import pytest
import scipy.stats

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "python"))

from campaign_cli import write_campaign  # noqa: E402
from windrive_campaign import cases, climate, cluster, runner, schema  # noqa: E402
from windrive_campaign.errors import CampaignError  # noqa: E402

TINY = ROOT / "campaigns" / "tiny.toml"
SCENE = ROOT / "scenes" / "c-normal"


def campaign_cli(*args, check_rc=None, timeout=120):
    env = {**os.environ, "PYTHONPATH": str(ROOT / "python")}
    r = subprocess.run(
        [sys.executable, "-m", "windrive_campaign", *map(str, args)],
        capture_output=True,
        text=True,
        env=env,
        timeout=timeout,
    )
    if check_rc is not None:
        assert r.returncode == check_rc, r.stderr
    return r


def minimal(top="", tables="", grid='torsional.fidelity = ["2"]'):
    """A valid campaign of one grid case; `top` adds top-level keys, `tables` tables after [grid]."""
    return f"""scene = "{SCENE}"
stop_time = 2.0
{top}
[[channel]]
name = "torsional.lss_torque"
[grid]
{grid}
{tables}"""


# ---------------------------------------------------------------------------------------------------
# the campaign file


@pytest.mark.parametrize(
    "text, message, line",
    [
        (minimal(top="stop_tmie = 3"), "stop_tmie: unknown key", 3),
        (minimal().replace("stop_time = 2.0", "stop_time = -1"), "stop_time: must be above 0", 2),
        (minimal().replace("stop_time = 2.0", 'stop_time = "2"'), "stop_time: must be a finite number", 2),
        (minimal(top="transient = 5"), "transient: 5.0 s leaves nothing of stop_time = 2.0 s", 3),
        (minimal(tables='[dlc12]\ncut_in = 4\ncut_out = 20\nseeds = 2\nturbulence_class = "D"'),
         "dlc12.turbulence_class: must be one of A, B, C, not 'D'", 12),
        (minimal(tables="[climate]\nrayleigh = { mean = 10 }\n[dlc12]\ncut_in = 4\ncut_out = 20\nseedz = 2"),
         "dlc12.seedz: unknown key", 13),
        (minimal(tables="[climate]\nrayleigh = { mean = 10 }\n[dlc12]\ncut_in = 4\ncut_out = 20\nseeds = 2"),
         "dlc12: give exactly one of turbulence_class", 10),
        (minimal(tables="[dlc12]\ncut_in = 4\ncut_out = 20\nseeds = 2\nturbulence_intensity = 0.1"),
         "add a [climate] table", 8),
        (minimal(tables="[climate]\nweibull = { k = 2, a = 11 }"), "climate.weibull.a: unknown key", 9),
        (minimal(grid='torsional.fidelity = "2"'), "grid.torsional.fidelity: a grid axis is a non-empty list", 7),
        (minimal(grid='fidelity = ["2"]'), "grid.fidelity: a parameter is named component.variable", 7),
        (minimal().replace('name = "torsional.lss_torque"', 'name = "lss_torque"'), "must be component.variable", 5),
        (minimal(tables="[[event]]\nper_year = 3"), "event[1].name: missing", 8),
        (minimal(tables="[[event]]\nname = \"a\"\nper_year = 3\n[[event]]\nname = \"b\"\nper_year = -3"),
         "event[2].per_year: must be at least 0.0", 13),
        (minimal().replace("[[channel]]", "[[channel]]\nm = [3, -6]"), "channel[1].m: Wöhler slopes", 5),
        (minimal(top="stop_time = = 3"), "not valid TOML: Invalid value", 3),
        (minimal(top="stop_time = 3"), "not valid TOML: Cannot overwrite a value", None),  # tomllib gives no line
        (minimal().replace(f'"{SCENE}"', '"nowhere"'), "no such scene folder or .ssp", 1),
        (minimal(grid=""), "the campaign has no load cases", None),
    ],
)
def test_schema_errors_name_file_key_and_line(tmp_path, text, message, line):
    path = write_campaign(tmp_path, text)
    with pytest.raises(CampaignError) as e:
        schema.load(path)
    text = str(e.value)
    assert message in text
    assert text.startswith(f"{path}:{line}:" if line else f"{path}:"), text


def test_a_user_error_is_one_line_without_traceback(tmp_path):
    path = write_campaign(tmp_path, minimal(tables="[dlc12]\nbin_width = 0"))
    r = campaign_cli("run", path, "--out", tmp_path / "out", check_rc=2)
    assert r.stderr.startswith(f"error: {path}:")
    assert "Traceback" not in r.stderr and len(r.stderr.strip().splitlines()) == 1, r.stderr


def test_a_misspelt_channel_stops_the_campaign_before_any_case(tmp_path):
    path = write_campaign(tmp_path, minimal().replace("torsional.lss_torque", "torsional.lss_torqe"))
    r = campaign_cli("run", path, "--out", tmp_path / "out", check_rc=2)
    assert "the scene does not run" in r.stderr and "torsional has no variable lss_torqe" in r.stderr
    assert not (tmp_path / "out" / "cases").exists()


def test_the_example_campaigns_are_valid():
    for p in (ROOT / "campaigns").glob("*.toml"):
        c = schema.load(p)
        assert c.channels and c.scene.is_dir(), p


# ---------------------------------------------------------------------------------------------------
# cases and weights


def test_weibull_bins_tile_cut_in_to_cut_out_as_scipy_counts(windrive):
    k, a = 2.3, 9.7
    cl = schema.Climate(k, a, 20.0, "test")

    def bins_to(cut_out):
        return climate.wind_bins(windrive, schema.Dlc12(4.0, cut_out, 2.0, (1,), "B", None, "rotor"), cl)

    bins = bins_to(25.0)
    assert [b.speed for b in bins] == [4, 6, 8, 10, 12, 14, 16, 18, 20, 22, 24]
    assert bins[0].lo == 4.0 and bins[-1].hi == 25.0
    assert all(b.hi == n.lo for b, n in zip(bins, bins[1:]))
    w = scipy.stats.weibull_min(k, scale=a)
    for b in bins:
        assert b.probability == pytest.approx(w.cdf(b.hi) - w.cdf(b.lo), rel=1e-12)
        assert b.hours == pytest.approx(b.probability * 8760 * 20, rel=1e-12)
        assert b.ntm_turbulence_intensity == pytest.approx(0.14 * (0.75 * b.speed + 5.6) / b.speed, rel=1e-14)
    assert sum(b.probability for b in bins) == pytest.approx(w.cdf(25.0) - w.cdf(4.0), rel=1e-12)
    # a last bin cut short by cut_out is simulated at cut_out, never above
    assert bins_to(23.5)[-1].speed == 23.5


def test_rayleigh_hours_are_the_thesis_operating_hours(tmp_path, windrive):
    """Thesis Table 7.1 (and `windrive life`): 161 950 h in 20 years between 3 and 25 m/s at a Rayleigh
    mean of 10 m/s; the seeds share their bin's hours."""
    text = minimal(
        grid="",
        tables="[climate]\nrayleigh = { mean = 10.0 }\nyears = 20\n"
        "[dlc12]\ncut_in = 3.0\ncut_out = 25.0\nseeds = [7, 8, 9]\nturbulence_class = \"A\"\n",
    )
    c = schema.load(write_campaign(tmp_path, text))
    r = scipy.stats.rayleigh(scale=10.0 * math.sqrt(2 / math.pi))  # mean 10 m/s
    found = cases.expand(c, {c.scene: ("s.ssp", "d")}, "w", windrive)
    assert len(found) == 12 * 3 and {k.seed for k in found} == {7, 8, 9}
    total = sum(k.hours for k in found)
    assert total == pytest.approx(161950, abs=1)
    assert total == pytest.approx((r.cdf(25) - r.cdf(3)) * 8760 * 20, rel=1e-12)
    # IEC NTM, class A: TI = 0.16 (0.75 V + 5.6) / V
    at11 = [k for k in found if k.wind_speed == 11.0]
    assert len(at11) == 3
    assert all(k.turbulence_intensity == pytest.approx(0.16 * (0.75 * 11 + 5.6) / 11, rel=1e-14) for k in at11)
    assert all(k.params["rotor.turbulence_intensity"] == k.turbulence_intensity for k in at11)


def test_case_ids_follow_the_simulation_not_the_file(tmp_path):
    grid = minimal(grid='torsional.fidelity = ["2", "5"]\nrotor.wind_speed = [8.0, 9.0]')
    swapped = minimal(grid='rotor.wind_speed = [8.0, 9.0]\ntorsional.fidelity = ["2", "5"]')
    a = schema.load(write_campaign(tmp_path, grid, "a.toml"))
    swapped = swapped.replace("stop_time = 2.0", "stop_time = 2.0\ntransient = 1.0")
    b = schema.load(write_campaign(tmp_path, swapped, "b.toml"))

    def ids(c, scene="d", windrive="w"):
        return {k.id: k for k in cases.expand(c, {c.scene: ("s", scene)}, windrive)}

    ia, ib = ids(a), ids(b)
    assert len(ia) == 4 and set(ia) == set(ib)  # axes reordered, transient changed: same simulations
    assert all(ia[i].analysis_digest != ib[i].analysis_digest for i in ia)  # but analysed differently
    assert set(ids(a, scene="other")).isdisjoint(ia)  # another scene snapshot
    assert set(ids(a, windrive="other")).isdisjoint(ia)  # another windrive build
    c = schema.load(write_campaign(tmp_path, grid.replace("stop_time = 2.0", "stop_time = 3.0"), "c.toml"))
    assert set(ids(c)).isdisjoint(ia)


def test_a_turbulent_rotors_period_is_the_analysed_window_and_its_seed_its_own(tmp_path):
    """Every window carries its mean wind and its intensity exactly when the series' period is the window
    and its σ is read over that period (src/physics/turbulence.rs), so a seeded rotor gets
    turbulence_period = stop_time - transient and turbulence_scaling = "period", and a new transient is then a new simulation; a period the campaign gives
    stays. Its seed is the case's own: one seed number at two wind speeds or intensities draws
    different seeds, the same case the same one."""
    seeded = minimal(grid="rotor.seed = [1, 2]\nrotor.wind_speed = [10.0, 12.0]\nrotor.turbulence_intensity = [0.1, 0.2]")
    seeded = seeded.replace("stop_time = 2.0", "stop_time = 2.0\ntransient = 0.5")
    c = schema.load(write_campaign(tmp_path, seeded, "a.toml"))
    found = cases.expand(c, {c.scene: ("s", "d")}, "w")
    assert {k.params["rotor.turbulence_period"] for k in found} == {1.5}
    assert {k.params["rotor.turbulence_scaling"] for k in found} == {"period"}  # σ over the window itself
    seeds = [k.params["rotor.seed"] for k in found]
    assert len(set(seeds)) == 8 and all(isinstance(x, int) and 1 <= x < 2**31 for x in seeds)
    assert seeds == [k.params["rotor.seed"] for k in cases.expand(c, {c.scene: ("s", "d")}, "w")]
    later = schema.load(write_campaign(tmp_path, seeded.replace("transient = 0.5", "transient = 1.0"), "b.toml"))
    assert {k.id for k in cases.expand(later, {c.scene: ("s", "d")}, "w")}.isdisjoint(k.id for k in found)
    given = seeded.replace("rotor.seed", "rotor.turbulence_period = [9.0]\nrotor.seed")
    given = schema.load(write_campaign(tmp_path, given, "c.toml"))
    assert {k.params["rotor.turbulence_period"] for k in cases.expand(given, {c.scene: ("s", "d")}, "w")} == {9.0}
    ten = schema.load(write_campaign(tmp_path, seeded.replace("rotor.seed", 'rotor.turbulence_scaling = ["ten_minute"]\nrotor.seed'), "d.toml"))
    assert {k.params["rotor.turbulence_scaling"] for k in cases.expand(ten, {c.scene: ("s", "d")}, "w")} == {"ten_minute"}


def test_dlc12_blows_a_full_field_on_the_blades_unless_the_campaign_says(tmp_path, windrive):
    """[dlc12]'s rotor samples IEC turbulence as a full field on the blades by default (3P, shear, tilt and
    yaw in the loads: docs/WIND.md); `wind_sampling` in [dlc12], or the rotor's parameter in params, chooses
    the rotor-averaged series instead; both at once is the one parameter set twice."""
    dlc = '[climate]\nrayleigh = { mean = 10.0 }\n[dlc12]\ncut_in = 10\ncut_out = 12\nseeds = 1\nturbulence_class = "A"\n'

    def sampling(text, name):
        c = schema.load(write_campaign(tmp_path, minimal(grid="", tables=text), name))
        return {k.params.get("rotor.wind_sampling") for k in cases.expand(c, {c.scene: ("s", "d")}, "w", windrive)}

    assert sampling(dlc, "a.toml") == {"blades"}
    assert sampling(dlc + 'wind_sampling = "rotor_average"\n', "b.toml") == {"rotor_average"}
    params = minimal(grid="", tables=dlc).replace("stop_time = 2.0", 'stop_time = 2.0\nparams = { "rotor.wind_sampling" = "rotor_average" }')
    c = schema.load(write_campaign(tmp_path, params, "c.toml"))
    assert {k.params["rotor.wind_sampling"] for k in cases.expand(c, {c.scene: ("s", "d")}, "w", windrive)} == {"rotor_average"}
    both = params.replace('turbulence_class = "A"', 'turbulence_class = "A"\nwind_sampling = "blades"')
    c = schema.load(write_campaign(tmp_path, both, "d.toml"))
    with pytest.raises(CampaignError, match="rotor.wind_sampling is set twice"):
        cases.expand(c, {c.scene: ("s", "d")}, "w", windrive)
    with pytest.raises(CampaignError, match="wind_sampling.*must be one of blades, rotor_average, not 'bem'"):
        schema.load(write_campaign(tmp_path, minimal(grid="", tables=dlc + 'wind_sampling = "bem"\n'), "e.toml"))


def test_dlc12_defaults_are_iec_windows_and_six_seeds(tmp_path):
    """Without stop_time and seeds, [dlc12] runs IEC 61400-1's 10-minute series after the transient with
    six seeds per bin; given, they stay."""
    text = minimal(grid="", tables="[climate]\nrayleigh = { mean = 10.0 }\n[dlc12]\ncut_in = 4\ncut_out = 6\n"
                   'turbulence_class = "B"\n').replace("stop_time = 2.0", "transient = 30.0")  # fmt: skip
    c = schema.load(write_campaign(tmp_path, text))
    assert (c.stop_time, c.dlc12.seeds) == (630.0, (1, 2, 3, 4, 5, 6))
    given = schema.load(write_campaign(tmp_path, text.replace("transient = 30.0", "stop_time = 40.0") + "seeds = 2\n", "b.toml"))
    assert (given.stop_time, given.dlc12.seeds) == (40.0, (1, 2))


def test_distributed_logs_at_the_clusters_closing_stay_out_of_the_runs_output(monkeypatch):
    # A closing cluster gives distributed's log handlers their level back as its last act, and a send to a
    # worker that is going, still finishing on the event loop, then logged "Batched Comm Closed" with its
    # traceback (INFO) into a Slurm campaign's output (a fresh-clone run of test_slurm.py, 2026-12-02). Here
    # the late send is simulated in the cluster's close(), after which nothing silences it any more.
    import io
    import logging

    import distributed

    seen = io.StringIO()
    handler = logging.StreamHandler(seen)  # one of the handlers the cluster (and `connected`) re-levels
    handler.setLevel(logging.INFO)
    logger = logging.getLogger("distributed")
    level = logger.level
    logger.addHandler(handler)
    logger.setLevel(logging.INFO)
    late = logging.getLogger("distributed.batched")

    def late_send():
        try:
            raise OSError("the worker's comm is closed")
        except OSError:
            late.info("Batched Comm Closed", exc_info=True)

    class Cluster:
        def close(self, timeout):
            late_send()

    class Client:
        def __init__(self, cluster):
            pass

        def close(self, timeout):
            pass

    monkeypatch.setattr(distributed, "Client", Client)
    try:
        with cluster.connected(None, Cluster):
            late_send()
        assert seen.getvalue() == ""
        late_send()  # outside a campaign's cluster distributed's handlers are as they were
        assert "Batched Comm Closed" in seen.getvalue() and "Traceback" in seen.getvalue()
    finally:
        logger.removeHandler(handler)
        logger.setLevel(level)
