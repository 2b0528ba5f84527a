"""Which `windrive` binary the campaign runs and asks: --windrive, $WINDRIVE, then target/release/windrive
in a developer checkout, or the `windrive` the wheel installed beside this Python."""

from __future__ import annotations

import os
import shutil
import sys
import sysconfig
from pathlib import Path

from . import cluster as cluster_mod
from .errors import CampaignError

DEFAULT = "$WINDRIVE, else target/release/windrive in a checkout, the wheel's windrive beside this Python once installed"


def windrive(given: str | None = None) -> str:
    """The binary: `given`, $WINDRIVE, then target/release/windrive in a developer checkout, or the
    `windrive` the wheel installed into this Python's scripts folder (its bin/)."""
    chosen = given or os.environ.get("WINDRIVE")
    if chosen or cluster_mod.IN_CHECKOUT:
        path = Path(chosen or cluster_mod.REPO / "target" / "release" / "windrive").resolve()
        if not _executable(path):
            raise CampaignError(f"{path}: no windrive binary (cargo build --release builds it; or --windrive PATH)")
        return str(path)
    for path in _installed():
        if _executable(path):
            return str(path.resolve())
    raise CampaignError(
        f"no windrive binary beside {sys.executable} nor on PATH: the windrive wheel installs one "
        "(pip install windrive-*.whl); or --windrive PATH"
    )


def _installed() -> list[Path]:
    """Where pip puts the wheel's binary: this Python's scripts folder (a venv's bin/), the user scheme's
    (pip install --user), then whatever `windrive` PATH finds."""
    found = [Path(sysconfig.get_path("scripts")) / "windrive", Path(sys.executable).parent / "windrive"]
    try:
        found.append(Path(sysconfig.get_path("scripts", f"{os.name}_user")) / "windrive")
    except KeyError:  # an interpreter without a user scheme
        pass
    on_path = shutil.which("windrive")
    return found + ([Path(on_path)] if on_path else [])


def _executable(path: Path) -> bool:
    return path.is_file() and os.access(path, os.X_OK)
