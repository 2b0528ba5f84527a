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
