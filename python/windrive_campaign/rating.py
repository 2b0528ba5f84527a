"""A windrive rating command (`windrive gears`, `windrive bearings`) run on a case's series, its JSON
list turned into table columns. One place for the subprocess, its timeout and its errors, so `[gears]`
(gears.py) and `[bearings]` (bearings.py) fail a case the same way and differ only in their command and
columns.
"""

from __future__ import annotations

import json
import math
import subprocess

ERROR_CHARS = 4000  # of windrive's stderr kept, as for a failed run
CHANNELS_TIMEOUT_S = 60.0  # `windrive <tool> --channels` reads a description: milliseconds


def columns(rated: list[dict], prefix: str, fields: dict[str, str]) -> dict[str, float]:
    """`<prefix>.<name>.<column>` for every rated object and each column -> field of `fields`; JSON's
    null (windrive rates no such thing, or a non-finite number) as NaN."""
    out = {}
    for item in rated:
        for column, field in fields.items():
            value = item[field]
            out[f"{prefix}.{item['name']}.{column}"] = math.nan if value is None else float(value)
    return out


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


def rate(
    command: list[str], prefix: str, fields: dict[str, str], timeout: float, error: type[Exception]
) -> dict[str, float]:
    """Runs `command` (`windrive <tool> … --json`) and returns its columns; `error` as `output`, or when
    it prints something else than the list it should."""
    stdout = output(command, timeout, error)
    try:
        return columns(json.loads(stdout), prefix, fields)
    except (ValueError, KeyError, TypeError) as e:
        raise error(f"windrive {command[1]}: unexpected output ({type(e).__name__}: {e}): {stdout[:200]!r}") from None
