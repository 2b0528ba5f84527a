"""Where the campaign driver finds `windrive`, in a developer checkout (target/) and as the windrive wheel
installs it (the venv's bin/); the installed case is simulated here by patching the checkout test."""

import os
import pathlib
import stat
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "python"))

from windrive_campaign import __main__ as cli  # noqa: E402
from windrive_campaign import cluster, schema  # noqa: E402
from windrive_campaign.errors import CampaignError  # noqa: E402


def executable(path: pathlib.Path) -> pathlib.Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text("#!/bin/sh\n")
    path.chmod(path.stat().st_mode | stat.S_IXUSR)
    return path


def test_in_the_checkout_the_driver_runs_target_release(windrive, monkeypatch):
    monkeypatch.delenv("WINDRIVE", raising=False)
    assert cluster.IN_CHECKOUT
    assert cli._windrive(None) == windrive


def test_installed_the_driver_runs_the_windrive_beside_its_python(tmp_path, monkeypatch):
    monkeypatch.setattr(cluster, "IN_CHECKOUT", False)
    monkeypatch.delenv("WINDRIVE", raising=False)
    monkeypatch.setenv("PATH", str(tmp_path / "nowhere"))
    scripts = lambda name, scheme=None: str(tmp_path / (scheme or "venv") / "bin")  # noqa: E731
    monkeypatch.setattr(cli.sysconfig, "get_path", scripts)
    monkeypatch.setattr(cli.sys, "executable", str(tmp_path / "other" / "python"))
    with pytest.raises(CampaignError, match=r"no windrive binary beside .* nor on PATH: the windrive wheel installs"):
        cli._windrive(None)
    user = executable(tmp_path / f"{os.name}_user" / "bin" / "windrive")  # pip install --user
    assert cli._windrive(None) == str(user)
    venv = executable(tmp_path / "venv" / "bin" / "windrive")
    assert cli._windrive(None) == str(venv)
    given = executable(tmp_path / "given" / "windrive")
    monkeypatch.setenv("WINDRIVE", str(given))
    assert cli._windrive(None) == str(given)


def test_installed_slurm_workers_import_the_wheel_not_a_pythonpath(monkeypatch):
    monkeypatch.setattr(cluster, "IN_CHECKOUT", False)
    c = schema.load(ROOT / "campaigns" / "c-dlc12.toml")
    slurm = cluster.slurm(c.slurm, c.path)
    try:
        script = slurm.job_script()
    finally:
        slurm.close()
    assert "PYTHONPATH" not in script
    assert "windrive wheel installed" in cluster.import_fix() and sys.executable in cluster.import_fix()
