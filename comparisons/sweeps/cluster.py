"""The Dask cluster of a sweep: connecting to a scheduler or starting a local cluster, and telling a lost scheduler
from a batch that failed.

Without a scheduler address a scheduler is started in this process with one single-threaded ``dask worker``
process per core, each in a session of its own (so that a terminal's Ctrl-C reaches shimmy only): one Hopf computation is a few milliseconds of small numpy calls that hold the GIL, so threads
would not run in parallel.

Distributed's own loggers are silenced while a sweep runs: when the scheduler goes away they log several
tracebacks from the client's reconnect loop, and what happened is said in one line by the command instead.
"""

from __future__ import annotations

import enum
import importlib
import logging
import os
import signal
import subprocess
import sys
import time
import warnings

from axles.limits import UsageError

CONNECT_TIMEOUT_S = 10.0
WAIT_FOR_WORKERS_S = 60.0
LOST_GRACE_S = 2.0     # a result's connection may close a moment before the client marks the scheduler lost
_QUIET = ("distributed", "tornado", "asyncio")


class StopReason(enum.Enum):
    """Why a sweep stopped before its last batch (its finished batches are kept either way)."""

    SCHEDULER_LOST = "scheduler lost"
    CLUSTER_ERROR = "cluster error"


class SweepStopped(Exception):
    """The cluster failed under a running sweep; ``message`` is one line (without what was kept)."""

    def __init__(self, reason: StopReason, message: str):
        super().__init__(message)
        self.reason, self.message = reason, message


def quiet_distributed() -> dict[str, int]:
    """Silence distributed's loggers (each one: they carry their own levels, so the parent's would not do);
    returns the levels to restore."""
    # Importing distributed configures its loggers (levels, a stderr handler): it must come first, or the
    # levels set here would be overwritten.
    importlib.import_module("distributed")
    levels = {}
    for name, logger in list(logging.root.manager.loggerDict.items()):
        if isinstance(logger, logging.Logger) and name.split(".")[0] in _QUIET:
            levels[name] = logger.level
            logger.setLevel(logging.CRITICAL + 1)
    for name in _QUIET:
        logger = logging.getLogger(name)
        levels.setdefault(name, logger.level)
        logger.setLevel(logging.CRITICAL + 1)
    return levels


def restore_logging(levels: dict[str, int]) -> None:
    for name, level in levels.items():
        logging.getLogger(name).setLevel(level)


def _local_cluster(n: int, processes: bool):
    """(the cluster, its worker processes).  With processes, the scheduler runs here and each worker is a
    ``dask worker`` (with its nanny) in a session of its own: a Ctrl-C at the terminal reaches the terminal's
    process group, so only this process sees it and answers it at once, even while the workers still import."""
    from distributed import LocalCluster
    if not processes:
        return LocalCluster(n_workers=1, threads_per_worker=1, processes=False, dashboard_address=None,
                            silence_logs=logging.CRITICAL), []
    with warnings.catch_warnings():
        # the scheduler's HTTP server (metrics) warns on stderr when its default port is taken: it moves to another
        warnings.simplefilter("ignore", UserWarning)
        cluster = LocalCluster(n_workers=0, processes=False, protocol="tcp", host="127.0.0.1",
                               dashboard_address=None, silence_logs=logging.CRITICAL)
    address = cluster.scheduler_address
    argv = [sys.executable, "-m", "distributed.cli.dask_worker", address, "--nthreads", "1", "--no-dashboard"]
    procs = []
    try:
        for _ in range(n):
            # their logs are dropped: what happens to the sweep is said in one line, a failed sample has its error
            procs.append(subprocess.Popen(argv, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                                          stderr=subprocess.DEVNULL, start_new_session=True))
    except BaseException:
        stop_workers(procs)
        cluster.close()
        raise
    return cluster, procs


def stop_workers(procs: list[subprocess.Popen], grace_s: float = 2.0) -> None:
    """SIGTERM to each worker's session (its nanny and worker process), SIGKILL after ``grace_s``."""
    for sig in (signal.SIGTERM, signal.SIGKILL):
        for p in procs:
            try:
                os.killpg(p.pid, sig)
            except ProcessLookupError:
                pass
        deadline = time.monotonic() + grace_s
        for p in procs:
            try:
                p.wait(max(0.0, deadline - time.monotonic()))
            except subprocess.TimeoutExpired:
                pass
        if all(p.poll() is not None for p in procs):
            return


class DaskCluster:
    """A Dask client on ``scheduler`` or on a fresh local cluster (closed on exit).  ``processes=False``: one
    single-threaded worker inside this process, for small sweeps where starting worker processes (each importing
    numpy, scipy and Exudyn) would cost more than the work."""

    def __init__(self, scheduler: str | None, workers: int | None, processes: bool = True):
        from distributed import Client
        self.cluster = None
        self.procs: list[subprocess.Popen] = []
        self.lost = False
        if scheduler:
            try:
                self.client = Client(scheduler, timeout=f"{CONNECT_TIMEOUT_S:g}s")
            except (OSError, TimeoutError) as exc:
                raise UsageError(f"--scheduler {scheduler}: cannot connect ({exc})") from None
            try:   # a scheduler without workers would hold the sweep forever
                self.client.wait_for_workers(1, timeout=WAIT_FOR_WORKERS_S)
            except (OSError, TimeoutError):
                self.client.close()
                raise UsageError(f"--scheduler {scheduler}: no worker joined within {WAIT_FOR_WORKERS_S:g} s "
                                 f"(start one with 'dask worker {scheduler}')") from None
        else:
            n = local_workers(workers, processes)
            self.cluster, self.procs = _local_cluster(n, processes)
            try:
                self.client = Client(self.cluster)
                try:
                    self.client.wait_for_workers(n, timeout=WAIT_FOR_WORKERS_S)
                except (OSError, TimeoutError):
                    raise SweepStopped(StopReason.CLUSTER_ERROR, f"the {n} local Dask workers did not start "
                                                                f"within {WAIT_FOR_WORKERS_S:g} s") from None
            except BaseException:   # a Ctrl-C while the workers start, or workers that never come
                stop_workers(self.procs, grace_s=0.2)
                self.cluster.close()
                raise
        self.address = self.client.scheduler.address
        self.workers = max(1, sum(w["nthreads"] for w in self.client.scheduler_info()["workers"].values()))

    def scheduler_lost(self) -> bool:
        """Whether the client has lost its scheduler (waiting a moment for it to notice)."""
        deadline = time.monotonic() + LOST_GRACE_S
        while self.client.status == "running" and time.monotonic() < deadline:
            time.sleep(0.05)
        self.lost = self.client.status != "running"
        return self.lost

    def __enter__(self):
        return self

    def __exit__(self, *exc) -> None:
        # With its scheduler gone the client would retry connecting for its whole timeout: closed quickly instead
        try:
            if self.lost:
                self.client.close(timeout=1.0)
            else:
                self.client.close()
        except (OSError, TimeoutError):
            pass
        stop_workers(self.procs)
        if self.cluster is not None:
            self.cluster.close()


def local_workers(workers: int | None, processes: bool = True) -> int:
    return (workers or os.cpu_count() or 1) if processes else 1
