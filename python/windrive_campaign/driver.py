"""Runs a campaign: expands it, skips the finished cases, submits the others to the cluster, reports
progress as they complete, writes the Parquet table and the cost figures.

Resuming is the normal path, not a special mode: every run starts by reading the result files, so a
campaign stopped by Ctrl-C, a crash or a lost node is finished by running the same command again.
"""

from __future__ import annotations

import dataclasses
import errno
import json
import sys
import time
from dataclasses import dataclass
from pathlib import Path

from . import bearings, gears
from . import cases as cases_mod
from . import cluster as cluster_mod
from . import store
from .errors import CampaignError
from .runner import RunSpec, check_windrive, run_case
from .schema import Campaign

PROGRESS_INTERVAL_S = 1.0  # at most one progress line a second, besides failures and the last case


@dataclass
class Options:
    out: Path
    windrive: str
    workers: int | None = None
    scheduler: str | None = None
    slurm: bool = False
    retry_failed: bool = False


def _clock(seconds: float) -> str:
    s = int(round(seconds))
    return f"{s // 3600}:{s // 60 % 60:02d}:{s % 60:02d}"


class Progress:
    def __init__(self, total: int, already: int, to_run: int, stream):
        self.total, self.already, self.to_run, self.stream = total, already, to_run, stream
        self.done = self.failed = 0
        self.start = time.perf_counter()
        self.last_print = 0.0

    def update(self, result: dict):
        self.done += 1
        if result["status"] != "ok":
            self.failed += 1
        now = time.perf_counter()
        last = self.done == self.to_run
        if result["status"] == "ok" and not last and now - self.last_print < PROGRESS_INTERVAL_S:
            return
        self.last_print = now
        elapsed = now - self.start
        eta = elapsed / self.done * (self.to_run - self.done)
        line = (
            f"[{self.already + self.done}/{self.total}] {result['case']['name']}: {result['status']}"
            f" | failed {self.failed} | elapsed {_clock(elapsed)} | ETA {_clock(eta)}"
        )
        if result["status"] != "ok":
            line += f"\n    {result['error'].strip().splitlines()[-1] if result['error'].strip() else ''}"
        print(line, file=self.stream, flush=True)


def prepare(c: Campaign, opts: Options) -> tuple[list[cases_mod.Case], str, str, list[str]]:
    """The cases, the windrive copy they run (cases.snapshot_windrive) and its digest, and the
    channels they record."""
    opts.out.mkdir(parents=True, exist_ok=True)
    store.write_atomic(opts.out / "campaign.toml", c.path.read_bytes())
    scenes, record = snapshot_scenes(c, opts.windrive, opts.out)
    windrive, digest = cases_mod.snapshot_windrive(opts.windrive, opts.out)
    return cases_mod.expand(c, scenes, digest, windrive), windrive, digest, record


def snapshot_scenes(c: Campaign, windrive: str, out: Path) -> tuple[dict[Path, tuple[str, str]], list[str]]:
    """Every scene of the campaign snapshot (cases.snapshot_scene), its probe recording and rated as the
    cases will be; and those recorded channels (`recorded`, asked of windrive once)."""
    record = recorded(c, windrive)
    scenes = {
        p: cases_mod.snapshot_scene(p, windrive, out, record, c.gears, c.bearings) for p in cases_mod.scene_paths(c)
    }
    return scenes, record


def recorded(c: Campaign, windrive: str | None = None) -> list[str]:
    """The channels each case records: the analysed ones, their LDD speeds, what `windrive gears` reads
    with [gears], what `windrive bearings` reads with [bearings] (both asked of `windrive`, which a
    campaign with either needs here), and `record`. A table or gearbox windrive refuses stops the
    campaign here, before any case runs, with windrive's message."""
    rated: list[str] = []
    for tool, section in (("gears", c.gears), ("bearings", c.bearings)):
        if section is None:
            continue
        if windrive is None:
            raise ValueError(f"recorded: a campaign with [{tool}] needs the windrive binary to name its channels")
        try:
            rated += section.channels(windrive)
        except (gears.GearsError, bearings.BearingsError) as e:
            raise CampaignError(f"{c.path}: {cases_mod.section(section)}: windrive {tool} cannot rate it: "
                                f"{e}") from None  # fmt: skip
    analysed = [n for ch in c.channels for n in (ch.name, *([ch.ldd.speed] if ch.ldd else []))]
    return list(dict.fromkeys([*analysed, *rated, *c.record]))


def run(c: Campaign, opts: Options, stream=sys.stderr) -> int:
    """Returns the exit status: 0 when every case is ok, 1 when some failed, 130 when interrupted."""
    try:
        return _run(c, opts, stream)
    except OSError as e:
        if e.errno == errno.ENOSPC:
            raise CampaignError(
                f"{e.filename or opts.out}: no space left on the device: free some and run the same command "
                "again (every finished case's result is kept)"
            ) from None
        raise


def _run(c: Campaign, opts: Options, stream) -> int:
    all_cases, windrive, digest, record = prepare(c, opts)
    results = store.load_results(opts.out)
    todo = [k for k in all_cases if not store.is_done(k, results.get(k.id), opts.retry_failed)]
    already = len(all_cases) - len(todo)
    print(
        f"campaign {c.name}: {len(all_cases)} cases, {already} already done, {len(todo)} to run; results in {opts.out}",
        file=stream,
        flush=True,
    )
    spec = RunSpec(
        windrive=windrive,
        out_dir=str(opts.out),
        channels=c.channels,
        feq=c.feq,
        keep_series=c.keep_series,
        record=tuple(record),
        timeout=c.timeout,
        gears=c.gears,
        bearings=c.bearings,
    )
    interrupted = False
    cost = None
    if todo:
        try:
            cost = _run_cases(c, opts, todo, spec, digest, len(all_cases), already, stream)
        except KeyboardInterrupt:
            interrupted = True
            print("interrupted: finished cases are kept; run the same command again to resume", file=stream)
    results = store.load_results(opts.out)
    table_path = opts.out / f"{c.name}.parquet"
    store.write_table(table_path, store.table(all_cases, results, _metadata(c)))
    counts = {}
    for k in all_cases:
        r = results.get(k.id)
        status = r["status"] if r and r.get("analysis_digest") == k.analysis_digest else "pending"
        counts[status] = counts.get(status, 0) + 1
    print(f"table: {table_path} ({', '.join(f'{n} {s}' for s, n in sorted(counts.items()))})", file=stream)
    if cost is not None:
        store.write_atomic(opts.out / "cost.json", json.dumps(cost, indent=1).encode())
        print(format_cost(cost), file=stream)
    if interrupted:
        return 130
    return 0 if counts.get("ok", 0) == len(all_cases) else 1


def _run_cases(c, opts, todo, spec, digest, total, already, stream) -> dict | None:
    from distributed import as_completed

    t_cluster = time.perf_counter()

    def start():
        if opts.slurm:
            (opts.out / "slurm").mkdir(exist_ok=True)
            cluster = cluster_mod.slurm(c.slurm, c.path, opts.out / "slurm")
            cluster.scale(jobs=c.slurm.jobs)
            return cluster
        return cluster_mod.local(opts.workers)

    with cluster_mod.connected(opts.scheduler, start) as (client, _):
        if opts.slurm:
            # the start-up check needs a worker to run on; the cases could not start before one anyway
            print(f"waiting for the first of {c.slurm.jobs} Slurm jobs to start (squeue lists them; their "
                  f"logs: {opts.out / 'slurm'})", file=stream, flush=True)  # fmt: skip
            client.wait_for_workers(1)
        _check_workers(client, spec.windrive, digest, opts)
        threads = cluster_mod.total_threads(client)
        startup = time.perf_counter() - t_cluster
        progress = Progress(total, already, len(todo), stream)
        t0 = time.perf_counter()
        by_key = {}
        # the key is the case id: dask never runs two tasks of one case at once, and a case id shows in
        # the dashboard and the logs of a shared scheduler
        futures = client.map(run_case, todo, spec=spec, key=[f"case-{k.id}" for k in todo], pure=False)
        for k, f in zip(todo, futures):
            by_key[f.key] = k
        finished = []
        for f in as_completed(futures):
            try:
                r = f.result()
            except Exception as e:
                # not the case's failure (run_case records those itself) but the cluster's: a worker
                # lost, a scheduler that cannot unpickle the task. No result file: the case stays
                # pending and the next run tries it again.
                r = _lost(by_key[f.key], e)
            finished.append(r)
            progress.update(r)
        wall = time.perf_counter() - t0
        # the threads at the end: on a shared scheduler or Slurm, workers may join during the run
        threads = max(threads, cluster_mod.total_threads(client))
        return _cost(finished, wall, threads, startup)


def _check_workers(client, windrive: str, digest: str, opts: Options) -> None:
    """Before any case runs, every worker can import this package, and sees the campaign's windrive
    copy: each failure is one line naming the cause and the fix instead of a traceback per case."""
    where = f"--scheduler {opts.scheduler}" if opts.scheduler else ("the Slurm workers" if opts.slurm else "the workers")
    try:
        found = client.run(check_windrive, windrive, digest)
    except Exception as e:  # raised on a worker and re-raised here: whatever it is, it stops every case
        text = f"{type(e).__name__}: {e}"
        if "windrive_campaign" in text and ("No module" in text or "ModuleNotFound" in text):
            raise CampaignError(
                f"{where}: a worker cannot import windrive_campaign: start the scheduler and every worker "
                f"{cluster_mod.import_fix()}"
            ) from None
        raise CampaignError(f"{where}: a worker failed its start-up check: {text.splitlines()[0]}") from None
    wrong = {w: why for w, why in found.items() if why}
    if wrong:
        w, why = next(iter(wrong.items()))
        more = f" (and {len(wrong) - 1} more workers)" if len(wrong) > 1 else ""
        raise CampaignError(f"{where}: worker {w}: {why}{more}")


def _lost(case, error) -> dict:
    if isinstance(error, OSError) and error.errno == errno.ENOSPC:
        why = f"no space left on the device for its result ({error.filename}): free some and run the same command again"
    else:
        why = f"{type(error).__name__}: {error}"
    return {
        "case": dataclasses.asdict(case),
        "analysis_digest": case.analysis_digest,
        "status": "lost",
        "error": f"the cluster could not run the case (left pending): {why}",
        "returncode": None,
        "run_s": float("nan"),
        "analysis_s": float("nan"),
        "case_s": float("nan"),
        "worker": None,
        "stats": {},
    }


def _cost(finished: list[dict], wall: float, threads: int, startup: float) -> dict | None:
    """Cases per hour per core and the driver's overhead per case: the wall time each case held a
    worker, wall × threads / cases, against the mean time of its `windrive run` subprocess. The overhead
    covers dask's scheduling and transfer, the subprocess's start, the analysis and the result file; it
    also counts idle workers at the campaign's tail, so measure on a case count many times the workers."""
    timed = [r for r in finished if r["run_s"] == r["run_s"]]  # not NaN: the subprocess ran
    if not timed or wall <= 0:
        return None
    n = len(finished)
    per_case = wall * threads / n
    run_s = sum(r["run_s"] for r in timed) / len(timed)
    analysis = [r["analysis_s"] for r in timed if r["analysis_s"] == r["analysis_s"]]
    in_task = sum(r["case_s"] - r["run_s"] for r in timed) / len(timed)
    per_case_hours = per_case / 3600
    return {
        "cases": n,
        "threads": threads,
        "wall_s": wall,
        "cluster_start_s": startup,
        "worker_s_per_case": per_case,
        "run_s_per_case": run_s,
        "analysis_s_per_case": sum(analysis) / len(analysis) if analysis else None,
        "overhead_s_per_case": per_case - run_s,
        "overhead_fraction": (per_case - run_s) / run_s,
        # of the overhead: inside the task (starting the subprocess, the analysis, the result file) ...
        "in_task_s_per_case": in_task,
        # ... and outside it (dask's scheduling and transfer, workers idle at the campaign's tail)
        "scheduling_and_idle_s_per_case": per_case - run_s - in_task,
        "cases_per_hour_per_core": 1 / per_case_hours,
        "hours_for_10000_cases_on_256_cores": 10000 * per_case_hours / 256,
    }


def format_cost(k: dict) -> str:
    analysis = "" if k["analysis_s_per_case"] is None else f", {k['analysis_s_per_case']:.3f} s of it the analysis"
    return (
        f"cost: {k['cases']} cases in {k['wall_s']:.1f} s on {k['threads']} worker{'s' if k['threads'] != 1 else ''}"
        f" (cluster start {k['cluster_start_s']:.1f} s, not counted)\n"
        f"  per case {k['worker_s_per_case']:.3f} s of a worker: windrive run {k['run_s_per_case']:.3f} s,"
        f" driver overhead {k['overhead_s_per_case']:.3f} s = {100 * k['overhead_fraction']:.1f} %\n"
        f"  overhead in the task {k['in_task_s_per_case']:.3f} s{analysis};"
        f" scheduling and idle workers at the tail {k['scheduling_and_idle_s_per_case']:.3f} s\n"
        f"  {k['cases_per_hour_per_core']:.0f} cases per hour per core;"
        f" 10 000 such cases on 256 cores: {k['hours_for_10000_cases_on_256_cores']:.2f} h"
    )


def _metadata(c: Campaign) -> dict:
    return {
        "campaign": c.name,
        "file": str(c.path),
        "climate": c.climate.source if c.climate else None,
        "years": c.climate.years if c.climate else None,
        "feq_hz": c.feq,
        "ldd_bins": {
            ch.name: {"speed": ch.ldd.speed, "min": ch.ldd.min, "max": ch.ldd.max, "bins": ch.ldd.bins}
            for ch in c.channels
            if ch.ldd
        },
    }
