"""A windrive rating command (`windrive gears`, `windrive bearings`) asked which channels it reads. One
place for the subprocess, its timeout and its errors, so `[gears]` (gears.py) and `[bearings]`
(bearings.py) fail the same way. The ratings themselves run in each case's `windrive run --analyse`.
"""

from __future__ import annotations

import subprocess

ERROR_CHARS = 4000  # of windrive's stderr kept, as for a failed run
CHANNELS_TIMEOUT_S = 60.0  # `windrive <tool> --channels` reads a description: milliseconds


def output(command: list[str], timeout: float, error: type[Exception]) -> str:
    """The stdout of `command` (`windrive <tool> …`); `error` with windrive's stderr when it fails or
    times out."""
    tool = f"windrive {command[1]}"
    try:
        r = subprocess.run(command, capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        raise error(f"{tool} gave no result within the timeout of {timeout} s") from None
    if r.returncode != 0:
        raise error((r.stderr.strip() or f"{tool} exited with {r.returncode}")[-ERROR_CHARS:])
    return r.stdout


def channels(command: list[str], error: type[Exception]) -> tuple[str, ...]:
    """The channels `command` (`windrive <tool> --channels …`) prints, one per line: asked of the binary
    rather than copied into Python, where a copy would go stale with the descriptions. A table or
    gearbox windrive refuses fails here, before any case runs, with its message."""
    return tuple(output(command, CHANNELS_TIMEOUT_S, error).split())
