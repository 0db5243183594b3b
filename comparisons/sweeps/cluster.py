"""The Dask cluster of a sweep: connecting to a scheduler or starting a local cluster, and telling a lost scheduler
from a batch that failed.

Without a scheduler address a :class:`distributed.LocalCluster` is started with one single-threaded worker
process per core: one Hopf computation is a few milliseconds of small numpy calls that hold the GIL, so threads
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
import threading
import time

from comparisons.axles.limits import UsageError

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


def _main_thread() -> bool:
    return threading.current_thread() is threading.main_thread()


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
    from distributed import LocalCluster

    def start():
        # CRITICAL: the worker processes log an ERROR traceback when the cluster closes under them (after a
        # Ctrl-C, a lost batch); what happened is said in one line, and a failed sample carries its own error.
        return LocalCluster(n_workers=n, threads_per_worker=1, processes=processes, dashboard_address=None,
                            silence_logs=logging.CRITICAL)
    if not processes or not _main_thread():
        return start()
    # Started from a thread that blocks SIGINT: the cluster's threads inherit the mask and the worker processes
    # they spawn keep it through exec, so a Ctrl-C at the terminal (sent to the whole process group) reaches only
    # this process, whose main thread stays free to answer it within a second.
    box: dict = {}
    given_up = threading.Event()

    def target() -> None:
        signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})
        try:
            box["cluster"] = start()
        except BaseException as exc:  # handed to the main thread below
            box["error"] = exc
        if given_up.is_set() and "cluster" in box:
            box["cluster"].close()
    thread = threading.Thread(target=target, name="shimmy-cluster-start", daemon=True)
    thread.start()
    try:
        while thread.is_alive():
            thread.join(0.05)
    except BaseException:
        given_up.set()
        raise
    if "error" in box:
        raise box["error"]
    return box["cluster"]


class DaskCluster:
    """A Dask client on ``scheduler`` or on a fresh local cluster (closed on exit).  ``processes=False``: one
    single-threaded worker inside this process, for small sweeps where starting worker processes (each importing
    numpy, scipy and Exudyn) would cost more than the work."""

    def __init__(self, scheduler: str | None, workers: int | None, processes: bool = True):
        from distributed import Client
        self.cluster = None
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
            self.cluster = _local_cluster(local_workers(workers, processes), processes)
            self.client = Client(self.cluster)
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
        if self.cluster is not None:
            self.cluster.close()


def local_workers(workers: int | None, processes: bool = True) -> int:
    return (workers or os.cpu_count() or 1) if processes else 1
