"""One case on a worker: one `windrive run … --analyse SPEC` subprocess that simulates the case and
analyses its series in the same process (src/analysis/case.rs: statistics, DELs, LDD, and with [gears] or
[bearings] every tooth's or bearing's rating), then the result file.

Runs inside a dask worker process (one thread each: the work is the subprocess). Never raises for a
case's own failure: a non-zero exit (the simulation or the analysis of its series failing), a timeout or
an output it cannot read become a result with status `failed` or `timeout` and the error text, so one bad
case does not stop the campaign. The series reaches the disk only when the campaign keeps it.
"""

from __future__ import annotations

import ctypes
import dataclasses
import datetime
import json
import math
import os
import signal
import socket
import subprocess
import sys
import time
import traceback
from dataclasses import dataclass
from pathlib import Path

from . import bearings, gears, store
from .cases import Case
from .errors import CampaignError
from .schema import Channel

ERROR_CHARS = 4000  # of windrive's stderr kept in a failed case's result


@dataclass(frozen=True)
class RunSpec:
    """What every case of a campaign shares (sent with each task; small)."""

    windrive: str
    out_dir: str
    channels: tuple[Channel, ...]
    feq: float
    keep_series: bool
    record: tuple[str, ...]  # every channel recorded (driver.recorded)
    timeout: float
    gears: gears.Gears | None = None  # the gear table each series is rated with, if any
    bearings: bearings.Bearings | None = None  # the gearbox whose bearings each series rates, if any

    def analysis(self, transient: float) -> dict:
        """The `--analyse` spec of a case (src/analysis/case.rs reads it)."""
        spec: dict = {"transient": transient, "feq": self.feq, "channels": [dataclasses.asdict(c) for c in self.channels]}
        if self.gears is not None:
            spec["gears"] = self.gears.spec()
        if self.bearings is not None:
            spec["bearings"] = self.bearings.spec()
        return spec


# loaded here, not in the forked child: dlopen between fork and exec of a threaded process can deadlock
_LIBC = ctypes.CDLL(None) if sys.platform.startswith("linux") else None
PR_SET_PDEATHSIG = 1


def _die_with_parent():
    """Linux: the windrive child is killed when the worker dies (Ctrl-C, a closed cluster) instead of
    running on, orphaned, to the end of a long case."""
    if _LIBC is not None:
        _LIBC.prctl(PR_SET_PDEATHSIG, signal.SIGKILL)


def check_windrive(path: str, digest: str) -> str | None:
    """On a worker: None when `path` is the binary the campaign snapshotted, else why not (a worker
    that does not share the campaign folder, or sees another file at its path)."""
    from .cases import windrive_digest

    if not Path(path).is_file():
        return f"no windrive at {path}: every worker must see the campaign folder at the same path"
    try:
        found = windrive_digest(path)
    except CampaignError as e:
        return str(e)
    if found != digest:
        return f"{path} differs from the binary the campaign snapshotted (digest {found[:12]}, not {digest[:12]})"
    return None


def run_case(case: Case, spec: RunSpec) -> dict:
    started = time.perf_counter()
    out_dir = Path(spec.out_dir)
    series = None
    if spec.keep_series:  # Parquet: the bits of every value, a fraction of the CSV's size and writing time
        series = store.series_dir(out_dir, case.id) / "series.parquet"
        series.parent.mkdir(parents=True, exist_ok=True)
    result = {
        "case": dataclasses.asdict(case),
        "analysis_digest": case.analysis_digest,
        "status": "ok",
        "error": "",
        "returncode": None,
        "run_s": float("nan"),
        "analysis_s": float("nan"),
        "worker": f"{socket.gethostname()}:{os.getpid()}",
        "stats": {},
    }
    try:
        cmd = case.command(spec.windrive, None if series is None else str(series), list(spec.record))
        cmd += ["--analyse", json.dumps(spec.analysis(case.transient))]
        t0 = time.perf_counter()
        try:
            r = subprocess.run(cmd, capture_output=True, text=True, timeout=spec.timeout, preexec_fn=_die_with_parent)
            result["returncode"] = r.returncode
            if r.returncode != 0:
                result["status"] = "failed"
                result["error"] = (r.stderr.strip() or f"windrive run exited with {r.returncode}")[-ERROR_CHARS:]
        except subprocess.TimeoutExpired:
            result["status"] = "timeout"
            result["error"] = f"windrive run gave no result within the timeout of {spec.timeout} s"
        wall = time.perf_counter() - t0
        result["run_s"] = wall
        if result["status"] == "ok":
            try:
                out = json.loads(r.stdout)
                result["stats"] = {k: _number(v) for k, v in out["statistics"].items()}
                # the analysis ran inside the subprocess: its time is the analysis, the rest the run
                result["analysis_s"] = float(out["analysis_s"])
                result["run_s"] = wall - result["analysis_s"]
            except (ValueError, KeyError, TypeError) as e:
                result["status"] = "failed"
                result["error"] = f"windrive run --analyse: unexpected output ({type(e).__name__}: {e}): {r.stdout[:200]!r}"
    except Exception:  # a bug here must not stop the campaign either: recorded with its traceback
        result["status"] = "failed"
        result["error"] = traceback.format_exc()[-ERROR_CHARS:]
    result["case_s"] = time.perf_counter() - started
    result["finished"] = datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds")
    store.write_result(out_dir, case.id, result)
    return result


def _number(value):
    """A statistic from windrive's JSON: null (not a number, e.g. a tooth it does not rate) as NaN; a
    list (an LDD's bins) element by element."""
    if isinstance(value, list):
        return [_number(v) for v in value]
    return math.nan if value is None else float(value)
