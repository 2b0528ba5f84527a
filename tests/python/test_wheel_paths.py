"""Where the campaign driver finds `windrive` and `windrive_fmus.fmu_path` finds the FMUs, in a developer
checkout (target/) and as the windrive wheel installs them (the venv's bin/, the package's fmus/); the
installed case is simulated here by patching the checkout test, scripts/check-wheel runs the real one."""

import os
import pathlib
import stat
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "python"))

import windrive_fmus  # noqa: E402
from windrive_campaign import binary  # noqa: E402
from windrive_campaign import cluster, schema  # noqa: E402
from windrive_campaign.errors import CampaignError  # noqa: E402


def executable(path: pathlib.Path) -> pathlib.Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text("#!/bin/sh\n")
    path.chmod(path.stat().st_mode | stat.S_IXUSR)
    return path


def test_the_names_are_the_fmu_crates():
    assert sorted(windrive_fmus.NAMES) == sorted(p.parent.name for p in ROOT.glob("fmus/*/Cargo.toml"))


def test_in_the_checkout_fmu_path_is_what_pack_wrote(fmu_path, monkeypatch):
    monkeypatch.delenv("CARGO_TARGET_DIR", raising=False)
    assert windrive_fmus.in_checkout()
    assert windrive_fmus.fmu_path("torsional") == str(ROOT / "target" / "fmu" / "torsional.fmu") == fmu_path


def test_fmu_path_follows_cargo_target_dir_and_says_how_to_pack(tmp_path, monkeypatch):
    monkeypatch.setenv("CARGO_TARGET_DIR", str(tmp_path))
    pack = r"fmu/rotor.fmu: no rotor FMU: pack it with `cargo run --release -- pack rotor`"
    with pytest.raises(FileNotFoundError, match=pack):
        windrive_fmus.fmu_path("rotor")


def test_fmu_path_refuses_another_name():
    names = r"\(one of generator, gearbox6dof, rotor, torsional\)"
    with pytest.raises(ValueError, match=r"'gearbox': no such windrive FMU " + names):
        windrive_fmus.fmu_path("gearbox")


def test_installed_fmu_path_is_in_the_package(tmp_path, monkeypatch):
    monkeypatch.setattr(windrive_fmus, "in_checkout", lambda: False)
    monkeypatch.setattr(windrive_fmus, "_HERE", tmp_path)
    (tmp_path / "fmus").mkdir()
    (tmp_path / "fmus" / "generator.fmu").write_bytes(b"PK")
    assert windrive_fmus.fmu_path("generator") == str(tmp_path / "fmus" / "generator.fmu")
    with pytest.raises(FileNotFoundError, match="the windrive wheel installed here is incomplete"):
        windrive_fmus.fmu_path("rotor")


def test_in_the_checkout_the_driver_runs_target_release(windrive, monkeypatch):
    monkeypatch.delenv("WINDRIVE", raising=False)
    assert cluster.IN_CHECKOUT
    assert binary.windrive(None) == windrive


def test_installed_the_driver_runs_the_windrive_beside_its_python(tmp_path, monkeypatch):
    monkeypatch.setattr(cluster, "IN_CHECKOUT", False)
    monkeypatch.delenv("WINDRIVE", raising=False)
    monkeypatch.setenv("PATH", str(tmp_path / "nowhere"))
    scripts = lambda name, scheme=None: str(tmp_path / (scheme or "venv") / "bin")  # noqa: E731
    monkeypatch.setattr(binary.sysconfig, "get_path", scripts)
    monkeypatch.setattr(binary.sys, "executable", str(tmp_path / "other" / "python"))
    with pytest.raises(CampaignError, match=r"no windrive binary beside .* nor on PATH: the windrive wheel installs"):
        binary.windrive(None)
    user = executable(tmp_path / f"{os.name}_user" / "bin" / "windrive")  # pip install --user
    assert binary.windrive(None) == str(user)
    venv = executable(tmp_path / "venv" / "bin" / "windrive")
    assert binary.windrive(None) == str(venv)
    given = executable(tmp_path / "given" / "windrive")
    monkeypatch.setenv("WINDRIVE", str(given))
    assert binary.windrive(None) == str(given)


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
