"""Where the cases run: a LocalCluster on this machine (the default), a running dask scheduler
(`--scheduler ADDRESS`), or Slurm jobs from the campaign's [slurm] profile (`--slurm`).

Every worker has one thread: a case is one `windrive run` subprocess plus a short analysis, so a
worker's thread waits on its child and one worker per core keeps every core busy. Workers elsewhere than
this machine need the campaign folder, the scene snapshot and the windrive binary at the same paths (a
shared file system), and this package importable: on their PYTHONPATH in a developer checkout (the Slurm
profile exports it), or the windrive wheel installed into the Python they run. So does a scheduler started
by hand: it unpickles the tasks, which name this package's functions.
"""

from __future__ import annotations

import logging
import os
import sys
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path

from .errors import CampaignError
from .schema import Slurm

PACKAGE_PARENT = str(Path(__file__).resolve().parents[1])
# A developer checkout (python/ beside the workspace's Cargo.toml) rather than the windrive wheel installed
# into site-packages: it decides which windrive binary runs and how workers are told to import this package.
REPO = Path(PACKAGE_PARENT).parent
IN_CHECKOUT = (REPO / "Cargo.toml").is_file() and (REPO / "fmus").is_dir()


def import_fix() -> str:
    """How a worker that cannot import this package gets it, as an error message ends."""
    if IN_CHECKOUT:
        return f"with PYTHONPATH={PACKAGE_PARENT} (the same path on every node; docs/CAMPAIGNS.md)"
    return f"from a Python with the windrive wheel installed (this one: {sys.executable})"


CLOSE_TIMEOUT_S = 20  # for closing the client and the cluster at the end of a run


@contextmanager
def connected(scheduler: str | None, start: Callable[[], object]) -> Iterator[tuple[object, object | None]]:
    """A dask client, and the cluster this run started or None: of the running scheduler at `scheduler`
    (`--scheduler ADDRESS`), else of the cluster `start()` returns. Both are closed at the end, each
    within CLOSE_TIMEOUT_S: after Ctrl-C a worker may sit in a case that never returns (a blocked
    windrive); its process, and with it the case (PR_SET_PDEATHSIG), goes when the cluster stops."""
    from distributed import Client
    from distributed.utils import silence_logging_cmgr

    # distributed's own logs on errors only, from before the cluster starts until it has stopped: a cluster
    # silences them while it lives, but gives them back their level as the last act of its closing, and a
    # send to a worker that is going, still finishing on the event loop then, logs "Batched Comm Closed"
    # with a traceback (INFO) into the run's output
    with silence_logging_cmgr(logging.ERROR):
        cluster = None
        if scheduler:
            try:
                client = Client(scheduler, timeout="20s")
            except OSError as e:
                raise CampaignError(f"--scheduler {scheduler}: cannot connect: {e}") from None
        else:
            cluster = start()
            client = Client(cluster)
        try:
            yield client, cluster
        finally:
            for close in (client.close, *([cluster.close] if cluster is not None else [])):
                try:
                    close(timeout=CLOSE_TIMEOUT_S)
                except Exception:  # a timeout or a cluster already gone: nothing left to wait for
                    pass


def local(workers: int | None):
    from distributed import LocalCluster

    n = workers or os.cpu_count() or 1
    # no dashboard (it needs bokeh, and a port per campaign); the scheduler's logs only on errors
    return LocalCluster(
        n_workers=n,
        threads_per_worker=1,
        processes=True,
        dashboard_address=None,
        silence_logs=logging.ERROR,
    )


def slurm(profile: Slurm | None, path: Path, log_directory: Path | None = None):
    """A dask-jobqueue SLURMCluster from the profile; jobs are submitted when it is scaled. With
    `log_directory` (the campaign folder's slurm/, which the caller creates), each job writes its output,
    the workers' logs, to JOBNAME-JOBID.out there rather than to slurm-JOBID.out in the driver's current
    folder; an `--output` among the profile's job_extra_directives comes later in the script and wins."""
    if profile is None:
        raise CampaignError(f"{path}: --slurm needs a [slurm] table in the campaign file (docs/CAMPAIGNS.md)")
    from dask_jobqueue import SLURMCluster

    directives = [f"--output={log_directory}/%x-%j.out"] if log_directory is not None else []
    # from a checkout the workers import this package from its python/ folder; an installed wheel brings it
    exports = [f"export PYTHONPATH={PACKAGE_PARENT}${{PYTHONPATH:+:$PYTHONPATH}}"] if IN_CHECKOUT else []
    prologue = [*exports, *profile.job_script_prologue]
    kwargs = dict(
        cores=profile.cores,
        processes=profile.cores,  # one single-threaded worker per core, as locally
        memory=profile.memory,
        walltime=profile.walltime,
        job_extra_directives=[*directives, *profile.job_extra_directives],
        job_script_prologue=prologue,
        python=profile.python or sys.executable,
        # any free port: jobqueue's default 8787 is taken by a second campaign (or any dask) on this
        # machine, and the scheduler then warns on stderr
        scheduler_options={"dashboard_address": ":0"},
        silence_logs=logging.ERROR,
    )
    if profile.queue:
        kwargs["queue"] = profile.queue
    if profile.account:
        kwargs["account"] = profile.account
    if profile.local_directory:
        kwargs["local_directory"] = profile.local_directory
    return SLURMCluster(**kwargs)


def total_threads(client) -> int:
    return sum(w["nthreads"] for w in client.scheduler_info()["workers"].values())
