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


# fmpy's logger proxy (fmpy/logging, which formats an FMU's variadic message) forwards to one logger per
# process: the last one `addLoggerProxy` was given. `simulate_fmu(..., logger=f)` gives it a ctypes thunk of
# its own and frees it on return, so the next FMU that logs through fmpy's default callbacks (an error at
# exitInitializationMode, say) calls freed memory and the process dies. Each test therefore ends by pointing
# the proxy back at fmpy's own printer, kept alive here for the whole session.
_FMPY_PRINTER = []


@pytest.fixture(autouse=True)
def _fmpy_default_logger():
    yield
    from ctypes import byref

    from fmpy import fmi2
    from fmpy.logging import addLoggerProxy

    if not _FMPY_PRINTER:
        _FMPY_PRINTER.append(fmi2.fmi2CallbackLoggerTYPE(fmi2.printLogMessage))
    fmi2.defaultCallbacks.logger = _FMPY_PRINTER[0]
    addLoggerProxy(byref(fmi2.defaultCallbacks))
