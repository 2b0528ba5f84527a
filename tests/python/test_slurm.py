"""`--slurm` for real: scripts/slurm-localhost starts a one-node Slurm cluster on this machine (munged,
slurmctld and slurmd, all state in a temporary folder), and a tiny campaign runs its cases on dask
workers that Slurm jobs started from the campaign's [slurm] profile. Checked: every case in the result
store, each run by a worker process a Slurm job's log names, the job logs in the campaign folder, no job
left running once the driver is done; and a job whose workers cannot import the package stops the run
with one line. Skipped where Slurm is not installed (scripts/slurm-localhost install), except under CI,
which installs it. About half a minute on a 2-core machine."""

import os
import pathlib
import re
import shutil
import socket
import subprocess
import sys
import time

import pandas as pd
import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "python"))

from campaign_cli import write_campaign  # noqa: E402

SCRIPT = ROOT / "scripts" / "slurm-localhost"
SCENE = ROOT / "scenes" / "c-normal"


@pytest.fixture(scope="module")
def slurm_conf(tmp_path_factory):
    """A running one-node cluster: its slurm.conf, for SLURM_CONF. Stopped at teardown, whatever happened."""
    if shutil.which("slurmctld", path=f"{os.environ.get('PATH', '')}:/usr/sbin") is None:
        why = "slurmctld is not installed: scripts/slurm-localhost install (as root) installs Debian's Slurm"
        if os.environ.get("CI"):
            pytest.fail(f"{why}; CI must run it before the tests")
        pytest.skip(why)
    folder = tmp_path_factory.mktemp("slurm")
    try:
        # bounds against a hang only: the script itself gives the node 60 s to register
        started = subprocess.run([SCRIPT, "start", folder], capture_output=True, text=True, timeout=180)
        assert started.returncode == 0, started.stderr
        yield folder / "slurm.conf"
    finally:
        stopped = subprocess.run([SCRIPT, "stop", folder], capture_output=True, text=True, timeout=180)
    assert stopped.returncode == 0, stopped.stderr


def run_on_slurm(slurm_conf, tmp_path, slurm_table, grid):
    """`python -m windrive_campaign run FILE --slurm`, from the repository's root as scripts/campaign runs
    it, with SLURM_CONF naming the test cluster (sbatch and scancel read it, and the jobs inherit it)."""
    text = f"""scene = "{SCENE}"
stop_time = 2.0
transient = 0.5
[[channel]]
name = "torsional.lss_torque"
[grid]
{grid}
[slurm]
{slurm_table}"""
    path = write_campaign(tmp_path, text, "on-slurm.toml")
    env = {**os.environ, "PYTHONPATH": str(ROOT / "python"), "SLURM_CONF": str(slurm_conf)}
    command = [sys.executable, "-m", "windrive_campaign", "run", path, "--out", tmp_path / "out", "--slurm"]
    # a bound against a hang only (a job that never starts): the cases take seconds
    return subprocess.run(command, capture_output=True, text=True, env=env, cwd=ROOT, timeout=600)


def scontrol_jobs(slurm_conf) -> dict[str, dict[str, str]]:
    """Every job slurmctld remembers (finished ones for an hour: MinJobAge), as key=value fields."""
    env = {**os.environ, "SLURM_CONF": str(slurm_conf)}
    r = subprocess.run(["scontrol", "-o", "show", "job"], capture_output=True, text=True, env=env, check=True)
    jobs = {}
    for line in r.stdout.splitlines():
        fields = dict(f.split("=", 1) for f in line.split() if "=" in f)
        if "JobId" in fields:
            jobs[fields["JobId"]] = fields
    return jobs


def jobs_done(slurm_conf, ids, seconds=120) -> dict[str, dict[str, str]]:
    """The jobs `ids` once none is pending, running or completing: the driver cancels them as it closes
    its cluster, and their workers log as they stop. Polled, with a bound against a hang only."""
    deadline = time.monotonic() + seconds
    while True:
        jobs = {i: j for i, j in scontrol_jobs(slurm_conf).items() if i in ids}
        busy = [i for i, j in jobs.items() if j["JobState"] in ("PENDING", "RUNNING", "COMPLETING", "CONFIGURING")]
        if not busy or time.monotonic() > deadline:
            return jobs
        time.sleep(0.5)


def test_a_campaign_runs_its_cases_in_slurm_jobs(slurm_conf, tmp_path):
    before = set(ROOT.glob("slurm-*.out"))
    slurm = 'cores = 1\nmemory = "1GB"\nwalltime = "00:10:00"\njobs = 2'
    with socket.socket() as dashboard:
        # dask's default dashboard port taken, as by a second campaign on the machine
        try:
            dashboard.bind(("", 8787))
            dashboard.listen()
        except OSError:
            pass  # taken already
        r = run_on_slurm(slurm_conf, tmp_path, slurm, 'torsional.fidelity = ["2", "5"]\nrotor.seed = [1, 2]')
    assert r.returncode == 0, r.stderr
    assert "4 cases, 0 already done, 4 to run" in r.stderr
    assert "waiting for the first of 2 Slurm jobs to start" in r.stderr
    assert "Traceback" not in r.stderr and "Warning" not in r.stderr, r.stderr
    out = tmp_path / "out"
    t = pd.read_parquet(out / "on-slurm.parquet")
    assert len(t) == 4 and (t.status == "ok").all(), t[["name", "status", "error"]]
    assert len(list((out / "cases").glob("*.json"))) == 4

    # the jobs' output in the campaign folder, one file per job, none in the driver's folder
    logs = {re.fullmatch(r"dask-worker-(\d+)\.out", p.name).group(1): p for p in (out / "slurm").iterdir()}
    assert 1 <= len(logs) <= 2, logs
    assert set(ROOT.glob("slurm-*.out")) == before
    jobs = jobs_done(slurm_conf, set(logs))
    assert set(jobs) == set(logs), f"slurmctld knows jobs {sorted(jobs)}, the logs name {sorted(logs)}"
    for job in jobs.values():
        assert job["JobName"] == "dask-worker" and job["BatchHost"] == socket.gethostname(), job
        assert job["JobState"] in ("CANCELLED", "COMPLETED"), job  # none left behind
    # each case ran in a worker process that a job's worker log names (host:pid in the result)
    text = "".join(p.read_text() for p in logs.values())
    assert "Start worker at" in text
    in_jobs = set(re.findall(r"Worker process (\d+) ", text))
    assert {w.split(":")[1] for w in t.worker} <= in_jobs, (set(t.worker), in_jobs)


def test_slurm_workers_without_the_package_stop_the_run_in_one_line(slurm_conf, tmp_path):
    """The job script's prologue runs after the PYTHONPATH export: unsetting it leaves the workers
    without this package. The driver waits for the first worker and checks it before any case."""
    slurm = 'cores = 1\nmemory = "1GB"\nwalltime = "00:10:00"\njob_script_prologue = ["unset PYTHONPATH"]'
    r = run_on_slurm(slurm_conf, tmp_path, slurm, 'torsional.fidelity = ["2"]')
    assert r.returncode == 2, r.stderr
    last = r.stderr.strip().splitlines()[-1]
    assert last.startswith("error: the Slurm workers: a worker cannot import windrive_campaign"), r.stderr
    assert f"PYTHONPATH={ROOT / 'python'}" in last
    assert "Traceback" not in r.stderr
    assert not list((tmp_path / "out" / "cases").glob("*.json"))
