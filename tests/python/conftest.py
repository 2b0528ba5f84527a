import pathlib
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
FMU = ROOT / "target" / "fmu" / "torsional.fmu"
WINDRIVE = ROOT / "target" / "release" / "windrive"


@pytest.fixture(scope="session")
def fmu_path():
    if not FMU.is_file():
        subprocess.run([str(WINDRIVE), "pack", "torsional"], check=True, cwd=ROOT)
    return str(FMU)


@pytest.fixture(scope="session")
def windrive():
    assert WINDRIVE.is_file(), f"{WINDRIVE} missing: scripts/test builds it"
    return str(WINDRIVE)
