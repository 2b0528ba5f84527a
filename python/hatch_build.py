"""The windrive wheel's build hook (pyproject.toml, hatchling): puts the release build that is already there
into the wheel instead of compiling anything.

maturin (bindings = "bin") would build the binary again with `cargo rustc --bin windrive`: a graph whose only
root is the LTO'd binary, so cargo compiles every dependency as bitcode only (-C linker-plugin-lto), while
`cargo build --release --workspace` (scripts/test) compiles them as object code and bitcode for the FMU
cdylibs. None of its 120 crates is reused: 12 min 50 s on this 2-core machine against a few seconds here.

What goes in: target/release/windrive as the wheel's script (pip puts it into the venv's bin/), and the FMUs
`windrive pack` wrote to target/fmu/ as windrive_fmus/fmus/ ($CARGO_TARGET_DIR instead of target/ when set).
Missing files stop the build with the command that makes them; scripts/wheel runs them first.
"""

from __future__ import annotations

import importlib.util
import os
import re
import shutil
import subprocess
import sysconfig
from pathlib import Path

from hatchling.builders.hooks.plugin.interface import BuildHookInterface

# What manylinux lets a wheel's binaries link against besides themselves (PEP 600's policy, the part we need)
MANYLINUX_LIBS = {"libc.so.6", "libm.so.6", "libgcc_s.so.1", "libpthread.so.0", "libdl.so.2", "librt.so.1",
                  "ld-linux-x86-64.so.2", "linux-vdso.so.1"}  # fmt: skip


class WindriveWheel(BuildHookInterface):
    PLUGIN_NAME = "custom"

    def initialize(self, version: str, build_data: dict) -> None:
        if self.target_name != "wheel":
            return
        root = Path(self.root)
        target = Path(os.environ.get("CARGO_TARGET_DIR") or "target")
        target = target if target.is_absolute() else root / target
        binary = target / "release" / "windrive"
        names = fmu_names(root)
        fmus = {name: target / "fmu" / f"{name}.fmu" for name in names}
        for path in [binary, *fmus.values()]:
            if not path.is_file():
                raise RuntimeError(
                    f"{path}: missing; the wheel packs the release build as it is: run scripts/wheel, or "
                    "cargo build --release --workspace && target/release/windrive pack"
                )
        build_data["shared_scripts"][str(binary)] = "windrive"
        for name, path in fmus.items():
            build_data["force_include"][str(path)] = f"windrive_fmus/fmus/{name}.fmu"
        build_data["pure_python"] = False
        build_data["tag"] = f"py3-none-{platform_tag(binary)}"


def fmu_names(root: Path) -> list[str]:
    """The FMU crates under fmus/ (as `windrive pack` finds them), which must be windrive_fmus.NAMES."""
    crates = sorted(p.parent.name for p in root.glob("fmus/*/Cargo.toml"))
    spec = importlib.util.spec_from_file_location("windrive_fmus", root / "python" / "windrive_fmus" / "__init__.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    if sorted(module.NAMES) != crates:
        raise RuntimeError(f"fmus/ holds {', '.join(crates)} but windrive_fmus.NAMES lists {', '.join(module.NAMES)}")
    return crates


def platform_tag(binary: Path) -> str:
    """manylinux_2_N for a Linux binary that links only what manylinux allows, N the newest glibc symbol
    version it needs (as auditwheel decides); otherwise this machine's plain tag (linux_x86_64, ...), which
    pip installs here but PyPI refuses."""
    plain = sysconfig.get_platform().replace("-", "_").replace(".", "_")
    if not plain.startswith("linux_") or shutil.which("ldd") is None:
        return plain
    linked = subprocess.run(["ldd", str(binary)], capture_output=True, text=True)
    libs = {line.split()[0].rsplit("/", 1)[-1] for line in linked.stdout.splitlines() if line.strip()}
    if linked.returncode != 0 or not libs <= MANYLINUX_LIBS:
        return plain
    glibc = [int(m) for m in re.findall(rb"GLIBC_2\.(\d+)", binary.read_bytes())]
    return f"manylinux_2_{max(glibc, default=17)}_{plain.removeprefix('linux_')}"
