"""Every FMU of ours (each folder under fmus/, packed by scripts/test) in tools nobody here wrote:
fmpy's validator, the fmu-manipulation-toolbox checker, and a run alone in fmpy with its defaults."""

import pathlib
import subprocess
import sys

import numpy as np
import pytest
from fmpy import read_model_description, simulate_fmu

ROOT = pathlib.Path(__file__).resolve().parents[2]
NAMES = sorted(p.name for p in (ROOT / "fmus").iterdir() if (p / "Cargo.toml").is_file())


@pytest.fixture(params=NAMES)
def fmu(request, windrive):
    path = ROOT / "target" / "fmu" / f"{request.param}.fmu"
    if not path.is_file():
        subprocess.run([windrive, "pack", request.param], check=True, cwd=ROOT)
    return str(path)


def test_fmpy_validate_finds_no_problem(fmu):
    out = subprocess.run([sys.executable, "-m", "fmpy", "validate", fmu], capture_output=True, text=True)
    assert out.returncode == 0 and "No problems found" in out.stdout, out.stdout + out.stderr


def test_fmutool_check_finds_no_problem(fmu):
    fmutool = pathlib.Path(sys.executable).parent / "fmutool"
    out = subprocess.run([str(fmutool), "-input", fmu, "-check"], capture_output=True, text=True)
    assert out.returncode == 0 and "No semantic error" in out.stdout + out.stderr, out.stdout + out.stderr


def test_fmpy_runs_it_alone_with_its_defaults(fmu):
    md = read_model_description(fmu)
    result = simulate_fmu(fmu, output_interval=float(md.defaultExperiment.stepSize))
    assert len(result) > 100
    for name in result.dtype.names:
        assert np.all(np.isfinite(result[name].astype(float))), name
