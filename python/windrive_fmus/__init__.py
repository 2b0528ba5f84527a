"""The four windrive FMUs (FMI 2.0 Co-Simulation, linux64) as files on disk.

    from fmpy import simulate_fmu
    from windrive_fmus import fmu_path

    result = simulate_fmu(fmu_path("gearbox6dof"), stop_time=0.2, output_interval=1e-3)

`fmu_path(name)` gives the path of `torsional`, `generator`, `rotor` or `gearbox6dof` as a string, which
fmpy, libcosim, `windrive run` scenes and any other FMI 2.0 importer take. Installed from the windrive
wheel, the FMUs are the ones packed into it (fmus/ beside this file). In a developer checkout they are the
ones `windrive pack` last wrote to target/fmu/ ($CARGO_TARGET_DIR/fmu/ when that is set), so a rebuild
is seen at once.
"""

from __future__ import annotations

import os
from pathlib import Path

__all__ = ["NAMES", "fmu_path"]

NAMES = ("generator", "gearbox6dof", "rotor", "torsional")

_HERE = Path(__file__).resolve().parent
_CHECKOUT = _HERE.parents[1]  # <checkout>/python/windrive_fmus


def in_checkout() -> bool:
    """True when this package is imported from a windrive source tree rather than from an installed wheel."""
    return (_CHECKOUT / "Cargo.toml").is_file() and (_CHECKOUT / "fmus").is_dir()


def fmu_path(name: str) -> str:
    """The path of the FMU `name` (one of NAMES). Raises ValueError for another name and FileNotFoundError
    when the file is missing (in a checkout: not packed yet)."""
    if name not in NAMES:
        raise ValueError(f"{name!r}: no such windrive FMU (one of {', '.join(NAMES)})")
    if in_checkout():
        target = Path(os.environ.get("CARGO_TARGET_DIR") or _CHECKOUT / "target")
        path = target / "fmu" / f"{name}.fmu"
        fix = f"pack it with `cargo run --release -- pack {name}` in {_CHECKOUT}"
    else:
        path = _HERE / "fmus" / f"{name}.fmu"
        fix = "the windrive wheel installed here is incomplete: reinstall it"
    if not path.is_file():
        raise FileNotFoundError(f"{path}: no {name} FMU: {fix}")
    return str(path)
