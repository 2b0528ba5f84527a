"""One case on a worker: `windrive run` as a subprocess, the analysis of its series, the result file.

Runs inside a dask worker process (one thread each: the work is the subprocess). Never raises for a
case's own failure: a non-zero exit, a timeout, a series the analysis cannot read, `windrive gears`
([gears]) or `windrive bearings` ([bearings]) failing on it become a result with status `failed` or
`timeout` and the error text, so one bad case does not stop the campaign.
"""

from __future__ import annotations

import ctypes
import dataclasses
import datetime
import os
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time
import traceback
from dataclasses import dataclass
from pathlib import Path

from . import analysis, bearings, gears, store
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
    gears: gears.Gears | None = None  # what `windrive gears` rates each series with, if anything
    bearings: bearings.Bearings | None = None  # what `windrive bearings` rates each series with, if anything


# loaded here, not in the forked child: dlopen between fork and exec of a threaded process can deadlock
_LIBC = ctypes.CDLL(None) if sys.platform.startswith("linux") else None
PR_SET_PDEATHSIG = 1


def _die_with_parent():
    """Linux: the windrive child is killed when the worker dies (Ctrl-C, a closed cluster) instead of
    running on, orphaned, to the end of a long case."""
    if _LIBC is not None:
        _LIBC.prctl(PR_SET_PDEATHSIG, signal.SIGKILL)


WORK_PREFIX = "windrive-case-"


def work_dirs(case_ids) -> list[Path]:
    """The temporary series folders of these cases on this machine (run_case's, named by case id)."""
    tmp = Path(tempfile.gettempdir())
    return [p for i in case_ids for p in tmp.glob(f"{WORK_PREFIX}{i}-*")]


def remove_work_dirs(case_ids) -> int:
    """Removes what run_case left in the temporary folder for these cases: nothing when it finished,
    its series when its worker was killed mid-case (no `finally` runs then). Run by the driver on its
    machine and on every worker once the cases are done; returns how many folders it removed."""
    found = work_dirs(case_ids)
    for p in found:
        shutil.rmtree(p, ignore_errors=True)
    return len(found)


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


def warm_up() -> None:
    """Run once on each worker before the campaign's clock starts: the first CSV read and rainflow count
    in a fresh process cost a third of a second of imports and set-up, a per-worker cost (like the
    cluster's start) that would otherwise be booked to the first cases."""
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "warm.csv"
        path.write_text("time,a.x\n0,0\n0.5,1\n1,0\n")
        s = analysis.read_series(str(path), ["a.x"])
        analysis.analyse(s, (Channel("a.x", (3.0,)),), 1.0, 0.0)


def run_case(case: Case, spec: RunSpec) -> dict:
    started = time.perf_counter()
    out_dir = Path(spec.out_dir)
    if spec.keep_series:
        work = store.series_dir(out_dir, case.id)
        work.mkdir(parents=True, exist_ok=True)
    else:
        work = Path(tempfile.mkdtemp(prefix=f"{WORK_PREFIX}{case.id}-"))
    csv = work / "series.csv"
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
        cmd = case.command(spec.windrive, str(csv), list(spec.record))
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
        result["run_s"] = time.perf_counter() - t0
        if result["status"] == "ok":
            t1 = time.perf_counter()  # the ratings count as analysis: they are work on the finished series
            try:
                series = analysis.read_series(str(csv), analysis.needed_columns(spec.channels))
                stats = analysis.analyse(series, spec.channels, spec.feq, case.transient)
                if spec.gears is not None:
                    stats.update(gears.rate(spec.windrive, str(csv), spec.gears, case.transient, spec.timeout))
                if spec.bearings is not None:
                    stats.update(bearings.rate(spec.windrive, str(csv), spec.bearings, case.transient, spec.timeout))
                result["stats"] = stats
            except analysis.AnalysisError as e:
                result["status"] = "failed"
                result["error"] = f"analysis: {e}"
            except (gears.GearsError, bearings.BearingsError) as e:
                result["status"] = "failed"
                result["error"] = str(e)
            result["analysis_s"] = time.perf_counter() - t1
    except Exception:  # a bug here must not stop the campaign either: recorded with its traceback
        result["status"] = "failed"
        result["error"] = traceback.format_exc()[-ERROR_CHARS:]
    finally:
        if not spec.keep_series:
            shutil.rmtree(work, ignore_errors=True)
    result["case_s"] = time.perf_counter() - started
    result["finished"] = datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds")
    store.write_result(out_dir, case.id, result)
    return result
