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
    grid = minimal(grid='torsional.fidelity = ["2", "5"]\nrotor.seed = [1, 2]')
    swapped = minimal(grid='rotor.seed = [1, 2]\ntorsional.fidelity = ["2", "5"]')
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


def test_a_parameter_set_twice_is_an_error(tmp_path):
    text = minimal(top='params = { "torsional.fidelity" = "5" }')
    c = schema.load(write_campaign(tmp_path, text))
    with pytest.raises(CampaignError, match="torsional.fidelity is set twice"):
        cases.expand(c, {c.scene: ("s", "d")}, "w")


def test_a_case_past_its_timeout_is_killed_and_recorded(tmp_path, windrive):
    """run_case alone (as a worker runs it): windrive killed at the timeout, status and error kept in the
    result file, no temporary series left."""
    from windrive_campaign import runner

    # the rotor plays back a named pipe nothing writes to: windrive blocks opening it, so the case
    # outlasts the timeout on any machine
    held = tmp_path / "held-series.csv"
    os.mkfifo(held)
    grid = f'torsional.fidelity = ["2"]\nrotor.mode = ["playback"]\nrotor.series = ["{held}"]'
    c = schema.load(write_campaign(tmp_path, minimal(grid=grid)))
    (case,) = cases.expand(c, {c.scene: (str(SCENE), "d")}, "w")
    out = str(tmp_path / "out")
    spec = runner.RunSpec(windrive, out, c.channels, 1.0, False, ("torsional.lss_torque",), timeout=0.3)
    r = runner.run_case(case, spec)
    assert r["status"] == "timeout" and "0.3 s" in r["error"] and r["stats"] == {}
    assert json.loads((tmp_path / "out" / "cases" / f"{case.id}.json").read_text())["status"] == "timeout"


def test_cases_lists_every_case_with_its_weight():
    r = campaign_cli("cases", TINY, check_rc=0)
    lines = r.stdout.splitlines()
    assert len(lines) == 1 + 4 + 1
    assert "dlc12-v10-s1" in lines[1] and lines[1].split()[2] == "12215.3"  # h: Weibull(2, 11), [10, 11] m/s
    assert "torsional.fidelity=5" in lines[4]
    assert lines[-1].startswith("4 cases")


# ---------------------------------------------------------------------------------------------------
# real campaigns on a LocalCluster with 2 workers


@pytest.fixture(scope="module")
def tiny_run(tmp_path_factory):
    """tiny.toml plus a grid point windrive refuses (fidelity 7): 5 cases, one failing."""
    tmp = tmp_path_factory.mktemp("tiny")
    text = TINY.read_text().replace('"../scenes/c-normal"', f'"{SCENE}"')
    text = text.replace('torsional.fidelity = ["2", "5"]', 'torsional.fidelity = ["2", "5", "7"]')
    path = write_campaign(tmp, text, "tiny.toml")
    out = tmp / "out"
    r = campaign_cli("run", path, "--out", out, "--workers", 2, check_rc=1)  # 1: a case failed
    return path, out, r


def test_campaign_table_has_every_case_with_weights_and_statistics(tiny_run):
    _, out, r = tiny_run
    assert "5 cases, 0 already done, 5 to run" in r.stderr
    assert "driver overhead" in r.stderr and "cases per hour per core" in r.stderr
    t = pd.read_parquet(out / "tiny.parquet")
    assert len(t) == 5
    ok = t[t.status == "ok"]
    assert sorted(ok.name) == ["dlc12-v10-s1", "dlc12-v12-s1", "grid-fidelity=2", "grid-fidelity=5"]
    dlc = t[t.group == "dlc12"]
    w = scipy.stats.weibull_min(2.0, scale=11.0)
    assert dlc.hours.sum() == pytest.approx((w.cdf(12) - w.cdf(10)) * 8760 * 20, rel=1e-12)
    assert np.isnan(t[t.group == "grid"].hours).all()
    assert list(ok["analysed_s"]) == pytest.approx([1.5] * 4)
    assert (ok["torsional.lss_torque.max"] >= ok["torsional.lss_torque.mean"]).all()
    assert (ok["torsional.lss_torque.del_m6"] > 0).all() and (ok.run_s > 0).all()
    # every analysed second lands in an LDD bin
    assert all(sum(s) == pytest.approx(1.5) for s in ok["torsional.lss_torque.ldd_s"])
    cost = json.loads((out / "cost.json").read_text())
    assert cost["cases"] == 5 and cost["threads"] == 2


def test_a_failed_case_is_recorded_and_the_others_run(tiny_run):
    _, out, _ = tiny_run
    t = pd.read_parquet(out / "tiny.parquet")
    bad = t[t.name == "grid-fidelity=7"].iloc[0]
    assert bad.status == "failed" and bad.returncode == 1
    assert "fidelity" in bad.error and "use 2, 5 or full" in bad.error
    assert (t[t.name != "grid-fidelity=7"].status == "ok").all()


def test_statistics_agree_with_windrive_del_and_ldd(tiny_run, windrive, tmp_path):
    """The kept series of a case, cut at the transient, through `windrive del` and `windrive ldd`."""
    _, out, _ = tiny_run
    t = pd.read_parquet(out / "tiny.parquet")
    row = t[t.name == "dlc12-v12-s1"].iloc[0]
    lines = (out / "cases" / row.id / "series.csv").read_text().splitlines()
    header = lines[0].split(",")
    kept = [ln for ln in lines[1:] if float(ln.split(",")[0]) >= 0.5]
    cut = tmp_path / "cut.csv"
    cut.write_text("\n".join([lines[0], *kept]) + "\n")
    ch = "torsional.lss_torque"
    command = [windrive, "del", cut, "--channel", ch, "--m", "3,6", "--json"]
    theirs = json.loads(subprocess.run(command, capture_output=True, text=True, check=True).stdout)["del"]
    assert row[f"{ch}.del_m3"] == pytest.approx(theirs["3"], rel=1e-12)
    assert row[f"{ch}.del_m6"] == pytest.approx(theirs["6"], rel=1e-12)
    # the LDD over the campaign's fixed bins (tiny.toml: 10 over [0, 2 MN·m]), recomputed with numpy: each
    # sample holds until the next, loads outside the bins count in the end bins
    data = np.loadtxt(cut, delimiter=",", skiprows=1)
    t_, load, speed = (data[:, header.index(c)] for c in ("time", ch, "torsional.rotor_speed"))
    index = np.clip(np.floor((load[:-1] - 0.0) / 2.0e5), 0, 9).astype(int)
    dt = np.diff(t_)
    sec = np.bincount(index, weights=dt, minlength=10)
    rev = np.bincount(index, weights=dt * np.abs(speed[:-1]) / (2 * np.pi), minlength=10)
    assert np.allclose(row[f"{ch}.ldd_s"], sec, rtol=1e-12, atol=1e-15)
    assert np.allclose(row[f"{ch}.ldd_rev"], rev, rtol=1e-12, atol=1e-15)
    # mean, population std and extremes as numpy has them
    assert row[f"{ch}.mean"] == pytest.approx(load.mean(), rel=1e-12)
    assert row[f"{ch}.std"] == pytest.approx(load.std(), rel=1e-9)
    assert (row[f"{ch}.min"], row[f"{ch}.max"]) == (load.min(), load.max())
    assert "torsional.rotor_speed" in header  # recorded for the LDD, kept with the series


def test_resume_runs_only_what_is_missing(tiny_run):
    path, out, _ = tiny_run
    results = out / "cases"
    stamps = {p.name: p.stat().st_mtime_ns for p in results.glob("*.json")}
    assert len(stamps) == 5 and not list(results.glob(".*.tmp"))
    again = campaign_cli("run", path, "--out", out, "--workers", 2, check_rc=1)
    assert "5 already done, 0 to run" in again.stderr  # the failed case is done too, unless retried
    assert {p.name: p.stat().st_mtime_ns for p in results.glob("*.json")} == stamps
    t = pd.read_parquet(out / "tiny.parquet")
    gone = t[t.name == "dlc12-v10-s1"].iloc[0].id
    (results / f"{gone}.json").unlink()
    third = campaign_cli("run", path, "--out", out, "--workers", 2, "--retry-failed", check_rc=1)
    assert "3 already done, 2 to run" in third.stderr, third.stderr
    now = {p.name: p.stat().st_mtime_ns for p in results.glob("*.json")}
    changed = {n for n in now if now[n] != stamps.get(n)}
    failed = t[t.status == "failed"].iloc[0].id
    assert changed == {f"{gone}.json", f"{failed}.json"}


def test_an_interrupted_campaign_resumes(tmp_path):
    """SIGINT to the driver as the first case finishes, while a case it cannot finish runs: it stops with
    130, keeps the finished cases, leaves no windrive running; the same command then runs only the rest.

    The "held" case plays back its rotor torque from a named pipe, so its windrive blocks opening the
    series until something writes to the pipe: nothing does before the SIGINT, whatever the machine's
    speed (a case that merely runs long finished before the signal on a fast machine). For the resume
    the pipe is replaced by a regular file of the same name: the case, its id included, is unchanged."""
    held = tmp_path / "held-series.csv"
    os.mkfifo(held)
    text = f"""
scene = "{SCENE}"
stop_time = 10.0
transient = 1.0
[[channel]]
name = "torsional.lss_torque"
m = [6]
[[event]]
name = "short"
stop_time = 2.0
per_year = 1
[[event]]
name = "held"
per_year = 1
params = {{ "rotor.mode" = "playback", "rotor.series" = "{held}" }}
[[event]]
name = "a"
per_year = 1
params = {{ "rotor.seed" = 3 }}
[[event]]
name = "b"
per_year = 1
params = {{ "rotor.seed" = 4 }}
"""
    path = write_campaign(tmp_path, text, "four.toml")
    out = tmp_path / "out"
    env = {**os.environ, "PYTHONPATH": str(ROOT / "python")}
    p = subprocess.Popen(
        [sys.executable, "-m", "windrive_campaign", "run", str(path), "--out", str(out), "--workers", "2"],
        stderr=subprocess.PIPE, text=True, env=env,
    )  # fmt: skip
    # a bound against a hang only: the short case takes seconds
    deadline = time.monotonic() + 600
    while not list((out / "cases").glob("*.json")) and time.monotonic() < deadline and p.poll() is None:
        time.sleep(0.05)
    assert p.poll() is None, "the driver ended before any case finished"
    p.send_signal(signal.SIGINT)
    _, err = p.communicate(timeout=120)
    assert p.returncode == 130, err
    assert "interrupted" in err
    done = len(list((out / "cases").glob("*.json")))
    assert 1 <= done < 4, err
    assert not list((out / "cases").glob(".*.tmp"))
    t = pd.read_parquet(out / "four.parquet")
    assert (t.status == "pending").sum() == 4 - done
    assert t[t.name == "event-held"].iloc[0].status == "pending"
    # the cases run out/bin/windrive-<digest>: any left running would show its path (the held one waits
    # on the pipe until killed with its worker; polled, as the kill is asynchronous)
    deadline = time.monotonic() + 60
    while (running := _windrive_running(out)) and time.monotonic() < deadline:
        time.sleep(0.1)
    assert not running, f"windrive still running after the driver stopped: {running}"
    held.unlink()
    held.write_text("0,1\n10,1\n")  # rated torque, per unit
    r = campaign_cli("run", path, "--out", out, "--workers", 2, check_rc=0, timeout=600)
    assert f"{done} already done, {4 - done} to run" in r.stderr
    assert (pd.read_parquet(out / "four.parquet").status == "ok").all()


def _windrive_running(out: pathlib.Path) -> str:
    return subprocess.run(["pgrep", "-af", str(out)], capture_output=True, text=True).stdout


# ---------------------------------------------------------------------------------------------------
# Slurm


def test_slurm_profile_writes_a_job_script():
    c = schema.load(ROOT / "campaigns" / "c-dlc12.toml")
    slurm = cluster.slurm(c.slurm, c.path, pathlib.Path("/campaign/slurm"))
    try:
        script = slurm.job_script()
    finally:
        slurm.close()
    assert script.startswith("#!/usr/bin/env bash")
    for line in ("#SBATCH -p compute", "#SBATCH --cpus-per-task=32", "#SBATCH -t 02:00:00", "#SBATCH --mem="):
        assert line in script, script
    assert "#SBATCH --output=/campaign/slurm/%x-%j.out" in script  # the job logs in the campaign folder
    assert f"export PYTHONPATH={ROOT / 'python'}" in script
    assert "--nthreads 1" in script and "--nworkers 32" in script  # one single-threaded worker per core
    with pytest.raises(CampaignError, match=r"--slurm needs a \[slurm\] table"):
        cluster.slurm(None, c.path)


def test_joins_a_running_scheduler(tmp_path):
    """--scheduler ADDRESS: the cases run on a cluster the driver did not start, which outlives it."""
    from distributed import LocalCluster

    path = write_campaign(tmp_path, minimal(grid='torsional.fidelity = ["2", "5"]'))
    with LocalCluster(n_workers=1, threads_per_worker=1, processes=True, dashboard_address=None) as running:
        r = campaign_cli("run", path, "--out", tmp_path / "out", "--scheduler", running.scheduler_address, check_rc=0)
        assert "on 1 worker " in r.stderr, r.stderr
        assert len(running.scheduler_info["workers"]) == 1  # still there after the driver left
    assert (pd.read_parquet(tmp_path / "out" / "c.parquet").status == "ok").all()


# ---------------------------------------------------------------------------------------------------
# Failures a user meets, each one line naming the cause and the fix


def test_a_full_disk_writing_the_table_is_one_line(tmp_path, monkeypatch, capsys):
    """The table is written after the cases: a full disk there says so and how to go on, and keeps
    every result already written."""
    import errno

    from windrive_campaign import __main__ as cli
    from windrive_campaign import store

    path = write_campaign(tmp_path, minimal())
    out = tmp_path / "out"
    campaign_cli("run", path, "--out", out, "--workers", 1, check_rc=0)
    results = sorted(p.name for p in (out / "cases").glob("*.json"))

    def full(table_path, *_):
        raise OSError(errno.ENOSPC, "No space left on device", str(table_path))

    monkeypatch.setattr(store, "write_table", full)
    assert cli.main(["run", str(path), "--out", str(out), "--workers", "1"]) == 2
    err = capsys.readouterr().err
    lines = [x for x in err.splitlines() if x.startswith("error:")]
    assert len(lines) == 1 and "no space left on the device" in lines[0] and "run the same command again" in lines[0]
    assert "Traceback" not in err
    assert sorted(p.name for p in (out / "cases").glob("*.json")) == results


def test_a_worker_without_the_package_is_one_line(tmp_path):
    """A scheduler and worker started as a user starts them, without PYTHONPATH: the driver stops
    before any case with one line naming PYTHONPATH, instead of a traceback per case."""
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    dask = pathlib.Path(sys.executable).with_name("dask")
    info = tmp_path / "scheduler.json"
    scheduler = subprocess.Popen(
        [str(dask), "scheduler", "--scheduler-file", str(info), "--host", "127.0.0.1", "--port", "0",
         "--no-dashboard"],
        cwd=tmp_path, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
    )  # fmt: skip
    worker = None
    try:
        deadline = time.monotonic() + 120  # a bound against a hang only
        while not info.exists() and time.monotonic() < deadline:
            time.sleep(0.1)
        address = json.loads(info.read_text())["address"]
        worker = subprocess.Popen(
            [str(dask), "worker", address, "--nthreads", "1", "--no-dashboard"],
            cwd=tmp_path, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
        )  # fmt: skip
        from distributed import Client

        with Client(address, timeout="60s") as c:
            c.wait_for_workers(1, timeout=120)
        r = campaign_cli("run", write_campaign(tmp_path, minimal()), "--out", tmp_path / "out",
                         "--scheduler", address, check_rc=2)  # fmt: skip
        lines = r.stderr.strip().splitlines()
        assert lines[-1].startswith("error: --scheduler") and "PYTHONPATH=" in lines[-1], r.stderr
        assert "Traceback" not in r.stderr
        assert not list((tmp_path / "out" / "cases").glob("*.json"))
    finally:
        for p in (worker, scheduler):
            if p is not None:
                p.kill()
                p.wait()


def test_a_worker_that_sees_another_windrive_is_named(tmp_path, windrive):
    """What a worker's start-up check says when the campaign's windrive copy is missing or another
    file stands at its path (a node without the shared file system, a rebuilt binary)."""
    digest = cases.windrive_digest(windrive)
    assert runner.check_windrive(windrive, digest) is None
    assert "no windrive at" in runner.check_windrive(str(tmp_path / "nowhere"), digest)
    other = tmp_path / "windrive-other"
    other.write_bytes(pathlib.Path(windrive).read_bytes() + b"\0")
    other.chmod(0o755)
    assert "differs from the binary the campaign snapshotted" in runner.check_windrive(str(other), digest)
