"""`python -m windrive_campaign` as a subprocess, as a user runs it: the package from python/ on the path,
output captured. Shared by the campaign tests (test_campaign.py keeps its own, which also checks the exit
status)."""

import os
import pathlib
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]


def campaign_cli(*args, cwd=None, timeout=120):
    env = {**os.environ, "PYTHONPATH": str(ROOT / "python")}
    return subprocess.run(
        [sys.executable, "-m", "windrive_campaign", *map(str, args)],
        capture_output=True, text=True, env=env, timeout=timeout, cwd=cwd,
    )  # fmt: skip


def write_campaign(tmp_path, text, name="c.toml"):
    """A campaign file in the test's folder."""
    p = tmp_path / name
    p.write_text(text)
    return p


def run_campaign(tmp, text, name):
    """Writes campaign `name` into folder `tmp`, runs it on 2 workers into tmp/out, and returns that
    folder and its Parquet table (the run must succeed)."""
    import pandas as pd

    path = write_campaign(tmp, text, f"{name}.toml")
    out = tmp / "out"
    r = campaign_cli("run", path, "--out", out, "--workers", 2)
    assert r.returncode == 0, r.stderr
    return out, pd.read_parquet(out / f"{name}.parquet")


def one_line_error(r, *fragments):
    """A mistake the campaign reports as it should: exit 2, one line, no traceback, naming `fragments`."""
    assert r.returncode == 2, r.stderr
    assert "Traceback" not in r.stderr and len(r.stderr.strip().splitlines()) == 1, r.stderr
    for f in fragments:
        assert f in r.stderr, r.stderr
