"""A campaign's folder: one JSON result per case, written atomically, and the Parquet table.

    OUT/campaign.toml          the campaign file as run
    OUT/scenes/*.ssp           scene snapshots (cases.snapshot_scene)
    OUT/bin/windrive-<digest>  the windrive binary the cases run (cases.snapshot_windrive)
    OUT/cases/<id>.json        one finished case (ok, failed or timeout)
    OUT/cases/<id>/series.parquet  its time series, with keep_series = true
    OUT/<name>.parquet         one row per case of the campaign, pending ones included
    OUT/cost.json              the last run's cost figures

A result is written to a temporary name in the same folder and renamed (atomic on POSIX): a crash or
Ctrl-C leaves either the whole result or none, never half a file that a resumed run would trust.
"""

from __future__ import annotations

import json
import math
import os
from pathlib import Path

import pyarrow as pa
import pyarrow.parquet as pq

from .cases import Case, param_text


def cases_dir(out: Path) -> Path:
    return out / "cases"


def series_dir(out: Path, case_id: str) -> Path:
    return cases_dir(out) / case_id


def write_atomic(path: Path, data: bytes):
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    tmp.write_bytes(data)
    os.replace(tmp, path)


def write_result(out: Path, case_id: str, result: dict):
    # NaN is valid for Python's json on the way back in; keep it rather than lose the field
    write_atomic(cases_dir(out) / f"{case_id}.json", json.dumps(result, indent=1).encode())


def load_results(out: Path) -> dict[str, dict]:
    """Every finished case's result by id. A result file that does not parse (written by something
    else, or truncated by a full disk) is ignored: its case runs again."""
    results = {}
    d = cases_dir(out)
    if not d.is_dir():
        return results
    for p in d.glob("*.json"):
        try:
            results[p.stem] = json.loads(p.read_text())
        except (OSError, ValueError):
            continue
    return results


def is_done(case: Case, result: dict | None, retry_failed: bool) -> bool:
    if result is None or result.get("analysis_digest") != case.analysis_digest:
        return False
    return result.get("status") == "ok" or not retry_failed


def _column(values: list):
    """Parameters differ in type between axes and groups (a fidelity "5" next to a wind speed 12.0):
    one type per column, numbers as float64 unless all are integers, anything else as text."""
    present = [v for v in values if v is not None]
    if all(isinstance(v, bool) for v in present):
        return pa.array(values, pa.bool_())
    if all(isinstance(v, int) and not isinstance(v, bool) for v in present):
        return pa.array(values, pa.int64())
    if all(isinstance(v, int | float) and not isinstance(v, bool) for v in present):
        return pa.array([None if v is None else float(v) for v in values], pa.float64())
    return pa.array([None if v is None else param_text(v) for v in values], pa.string())


def table(cases: list[Case], results: dict[str, dict], metadata: dict) -> pa.Table:
    param_names = list(dict.fromkeys(k for c in cases for k in c.params))
    stat_names = list(dict.fromkeys(k for c in cases for k in (results.get(c.id) or {}).get("stats", {})))
    cols: dict[str, list] = {
        k: []
        for k in (
            "id", "name", "group", "status", "error",
            *(f"param.{p}" for p in param_names),
            "wind_speed", "seed", "turbulence_intensity", "probability", "hours", "events",
            "stop_time", "transient", *stat_names,
            "run_s", "analysis_s", "case_s", "returncode", "worker", "finished", "scene",
        )  # fmt: skip
    }
    for c in cases:
        r = results.get(c.id) or {}
        if r and r.get("analysis_digest") != c.analysis_digest:
            r = {}  # analysed under other settings: pending until rerun
        stats = r.get("stats", {})
        row = {
            "id": c.id,
            "name": c.name,
            "group": c.group,
            "status": r.get("status", "pending"),
            "error": r.get("error", ""),
            **{f"param.{p}": c.params.get(p) for p in param_names},
            "wind_speed": c.wind_speed,
            "seed": c.seed,
            "turbulence_intensity": c.turbulence_intensity,
            "probability": c.probability,
            "hours": c.hours,
            "events": c.events,
            "stop_time": c.stop_time,
            "transient": c.transient,
            **{s: stats.get(s) for s in stat_names},
            "run_s": r.get("run_s"),
            "analysis_s": r.get("analysis_s"),
            "case_s": r.get("case_s"),
            "returncode": r.get("returncode"),
            "worker": r.get("worker"),
            "finished": r.get("finished"),
            "scene": c.scene,
        }
        for k, v in row.items():
            cols[k].append(v)
    arrays = {}
    for k, v in cols.items():
        if k.startswith("param."):
            arrays[k] = _column(v)
        elif k.endswith((".ldd_s", ".ldd_rev")):
            arrays[k] = pa.array(v, pa.list_(pa.float64()))
        elif k in ("seed", "returncode"):
            arrays[k] = pa.array(v, pa.int64())
        elif k in ("id", "name", "group", "status", "error", "worker", "finished", "scene"):
            arrays[k] = pa.array(v, pa.string())
        else:
            arrays[k] = pa.array([math.nan if x is None else float(x) for x in v], pa.float64())
    t = pa.table(arrays)
    return t.replace_schema_metadata({"windrive_campaign": json.dumps(metadata)})


def write_table(path: Path, t: pa.Table):
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    pq.write_table(t, tmp)
    os.replace(tmp, path)
