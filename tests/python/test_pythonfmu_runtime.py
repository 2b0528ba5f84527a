"""A PythonFMU FMU runs in `windrive run` without LD_PRELOAD or PYTHONPATH: the loader meets the missing
Python symbols, loads the runtime of the active virtual environment (VIRTUAL_ENV, as `activate` sets it)
with its module path, says so, and retries. Without a Python to take it from, the error still names the
manual way."""

import os
import subprocess
import sys

import numpy as np
import pytest

from test_master import ROOT, pyfmus, read_csv, write_scene  # noqa: F401 (pyfmus is a fixture)


def bare_env(**extra):
    """The environment of a user who activated the virtual environment and set nothing else."""
    env = {k: v for k, v in os.environ.items() if k not in ("LD_PRELOAD", "PYTHONPATH", "PYTHONHOME")}
    env.update(RUST_BACKTRACE="0", **extra)
    return env


def scene(tmp_path, pyfmus):
    return write_scene(
        tmp_path / "py",
        [
            ("rotor", pyfmus / "PyRotor.fmu", [("rotor_torque", "output")]),
            ("shaft", pyfmus / "PyShaft.fmu", [("torque", "input"), ("shaft_torque", "output")]),
        ],
        [("rotor", "rotor_torque", "shaft", "torque")],
        stop_time=2.0,
    )


def test_pythonfmu_runs_without_ld_preload(tmp_path, windrive, pyfmus):
    out = tmp_path / "py.csv"
    proc = subprocess.run([windrive, "run", str(scene(tmp_path, pyfmus)), "--out", str(out), "--step", "0.01"],
                          capture_output=True, text=True, cwd=ROOT, env=bare_env(VIRTUAL_ENV=sys.prefix))
    assert proc.returncode == 0, proc.stderr
    assert "needs the Python runtime: loaded" in proc.stderr and "libpython" in proc.stderr, proc.stderr
    r = read_csv(out)
    assert len(r) == 201 and np.isfinite(r["shaft.shaft_torque"]).all()
    assert r["rotor.rotor_torque"][-1] > 0


def test_without_a_python_the_manual_way_is_named(tmp_path, windrive, pyfmus):
    env = bare_env(PATH="/nonexistent")
    env.pop("VIRTUAL_ENV", None)
    proc = subprocess.run([str(windrive), "run", str(scene(tmp_path, pyfmus)), "--out", str(tmp_path / "x.csv")],
                          capture_output=True, text=True, cwd=ROOT, env=env)
    assert proc.returncode != 0
    for words in ("undefined symbol", "python3", "LD_PRELOAD", "PYTHONPATH"):
        assert words in proc.stderr, proc.stderr
