"""Running a sweep on Dask distributed, writing Parquet as batches finish, and resuming an interrupted sweep.

Without a scheduler address a :class:`distributed.LocalCluster` is started with one single-threaded worker
process per core: one Hopf computation is a few milliseconds of small numpy calls that hold the GIL, so threads
would not run in parallel.  Samples go to the workers in batches (:func:`batch_size`) sized so that each batch
takes about a second: Dask's per-task cost (about a millisecond) then stays far below the work.  The
:class:`~comparisons.sweeps.sample.SweepTask` is scattered to every worker once, not sent with each batch.

Each finished batch is written at once, atomically, to ``OUT.parts/batch-NNNNNN.parquet`` beside ``OUT`` with a
manifest (design fingerprint, task, batch size).  When all batches are there they are joined, sorted by sample,
into ``OUT`` (the manifest in its schema metadata) and the parts folder is removed.  ``resume=True`` reads the
manifest, refuses a different sweep, and computes only the batches whose part files are missing.
"""

from __future__ import annotations

import json
import logging
import math
import os
import shutil
import signal
import threading
import time
from dataclasses import dataclass
from typing import Callable

import pyarrow as pa
import pyarrow.parquet as pq

from comparisons.axles.limits import UsageError
from comparisons.files import atomic_path
from comparisons.sweeps.design import Design
from comparisons.sweeps.sample import SweepTask, evaluate_batch

TARGET_BATCH_S = 1.0
BATCHES_PER_WORKER = 4       # at least, so that the last batches do not leave a worker idle for long
MANIFEST = "manifest.json"
METADATA_KEY = b"shimmy_sweep"
WAIT_FOR_WORKERS_S = 60.0


@dataclass(frozen=True)
class SweepRun:
    """What a finished sweep did: the table (sorted by sample) and how it was computed."""

    table: pa.Table
    out: str
    batches: int
    computed_batches: int
    batch_size: int
    workers: int
    scheduler: str
    elapsed_s: float

    @property
    def samples(self) -> int:
        return self.table.num_rows

    @property
    def failed(self) -> int:
        return sum(1 for s in self.table.column("status").to_pylist() if s != "ok")

    def to_json(self) -> dict:
        computed = self.computed_batches
        return {"out": self.out, "samples": self.samples, "failed": self.failed, "batches": self.batches,
                "computed_batches": computed, "resumed_batches": self.batches - computed,
                "batch_size": self.batch_size, "workers": self.workers, "scheduler": self.scheduler,
                "elapsed_s": self.elapsed_s,
                "samples_per_s": (self.samples * computed / self.batches) / self.elapsed_s if self.elapsed_s > 0
                else None}


def batch_size(task: SweepTask, samples: int, workers: int) -> int:
    """About :data:`TARGET_BATCH_S` of work per batch, and at least :data:`BATCHES_PER_WORKER` batches per worker."""
    by_time = max(1, int(TARGET_BATCH_S / task.cost_s()))
    by_balance = max(1, math.ceil(samples / (BATCHES_PER_WORKER * max(1, workers))))
    return min(by_time, by_balance)


def _manifest(task: SweepTask, design: Design, size: int) -> dict:
    return {"version": 1, "design": design.to_json(), "fingerprint": design.fingerprint(), "task": task.to_json(),
            "batch_size": size}


def _same_sweep(a: dict, b: dict) -> bool:
    keys = ("fingerprint", "task")
    return all(json.dumps(a.get(k), sort_keys=True) == json.dumps(b.get(k), sort_keys=True) for k in keys)


def _part(parts: str, batch: int) -> str:
    return os.path.join(parts, f"batch-{batch:06d}.parquet")


def _write_table(path: str, table: pa.Table) -> None:
    with atomic_path(path) as tmp:
        pq.write_table(table, tmp)


def _main_thread() -> bool:
    return threading.current_thread() is threading.main_thread()


class DaskCluster:
    """A Dask client on ``scheduler`` or on a fresh local cluster (closed on exit).  ``processes=False``: one
    single-threaded worker inside this process, for small sweeps where starting worker processes (each importing
    numpy, scipy and Exudyn) would cost more than the work."""

    def __init__(self, scheduler: str | None, workers: int | None, processes: bool = True):
        from distributed import Client, LocalCluster
        self.cluster = None
        if scheduler:
            try:
                self.client = Client(scheduler, timeout="10s")
            except (OSError, TimeoutError) as exc:
                raise UsageError(f"--scheduler {scheduler}: cannot connect ({exc})") from None
            try:   # a scheduler without workers would hold the sweep forever
                self.client.wait_for_workers(1, timeout=WAIT_FOR_WORKERS_S)
            except TimeoutError:
                self.client.close()
                raise UsageError(f"--scheduler {scheduler}: no worker joined within {WAIT_FOR_WORKERS_S:g} s "
                                 f"(start one with 'dask worker {scheduler}')") from None
        else:
            n = (workers or os.cpu_count() or 1) if processes else 1
            # Worker processes are started with Ctrl-C ignored (inherited across spawn, and Python then installs no
            # KeyboardInterrupt handler): a Ctrl-C at the terminal reaches the whole process group, and only this
            # process should answer it, by closing the cluster and keeping the finished batches.  So a Ctrl-C in
            # the few seconds the cluster takes to start is ignored here too.
            previous = signal.signal(signal.SIGINT, signal.SIG_IGN) if processes and _main_thread() else None
            try:
                self.cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=processes,
                                            dashboard_address=None, silence_logs=logging.ERROR)
            finally:
                if previous is not None:
                    signal.signal(signal.SIGINT, previous)
            self.client = Client(self.cluster)
        self.address = self.client.scheduler.address
        self.workers = max(1, sum(w["nthreads"] for w in self.client.scheduler_info()["workers"].values()))

    def __enter__(self):
        return self

    def __exit__(self, *exc) -> None:
        self.client.close()
        if self.cluster is not None:
            self.cluster.close()


def _existing(out: str, manifest: dict, resume: bool) -> tuple[dict | None, bool]:
    """(manifest of the sweep to continue or None for a new one, whether ``out`` already holds it complete);
    checked before any cluster is started and without touching a file."""
    parts = out + ".parts"
    mpath = os.path.join(parts, MANIFEST)
    if os.path.exists(mpath):
        if not resume:
            raise UsageError(f"{parts} holds an interrupted sweep: --resume continues it (or delete the folder)")
        with open(mpath, encoding="utf-8") as fh:
            found = json.load(fh)
        if not _same_sweep(found, manifest):
            raise UsageError(f"--resume: {parts} holds a different sweep (other inputs, samples, seed or outputs)")
        return found, False
    if resume and os.path.exists(out):
        try:
            found = json.loads((pq.read_schema(out).metadata or {}).get(METADATA_KEY, b"{}"))
        except (OSError, pa.ArrowInvalid, ValueError):
            raise UsageError(f"--resume: {out} is not a sweep's Parquet file") from None
        if not _same_sweep(found, manifest):
            raise UsageError(f"--resume: {out} holds a different sweep (other inputs, samples, seed or outputs)")
        return found, True
    if resume:
        raise UsageError(f"--resume: neither {out} nor {parts} exists: nothing to resume")
    return None, False


def _start(parts: str, manifest: dict) -> None:
    os.makedirs(parts, exist_ok=True)
    with atomic_path(os.path.join(parts, MANIFEST)) as tmp, open(tmp, "w", encoding="utf-8") as fh:
        json.dump(manifest, fh, indent=1)


def run_sweep(task: SweepTask, design: Design, out: str, *, scheduler: str | None = None, workers: int | None = None,
              size: int | None = None, resume: bool = False,
              progress: Callable[[int, int], None] | None = None) -> SweepRun:
    """Evaluate every sample of ``design`` on Dask, batches written to Parquet as they finish; see module docs."""
    t0 = time.perf_counter()
    n = len(design)
    manifest = _manifest(task, design, size)
    found, complete = _existing(out, manifest, resume)
    if complete:
        return SweepRun(pq.read_table(out), out, math.ceil(n / found["batch_size"]), 0, found["batch_size"], 0, "",
                        time.perf_counter() - t0)
    parts = out + ".parts"
    with DaskCluster(scheduler, workers) as cluster:
        if found is None:
            manifest["batch_size"] = size or batch_size(task, n, cluster.workers)
            _start(parts, manifest)
        else:
            manifest = found
        size = manifest["batch_size"]
        batches = math.ceil(n / size)
        todo = [b for b in range(batches) if not os.path.exists(_part(parts, b))]
        done = n - sum(min(size, n - b * size) for b in todo)
        if progress is not None:
            progress(done, n)
        if todo:
            from distributed import as_completed
            shared = cluster.client.scatter(task, broadcast=True)
            tag = manifest["fingerprint"][:12]
            futures = [cluster.client.submit(evaluate_batch, shared, b, b * size,
                                             design.values[b * size:(b + 1) * size], pure=False,
                                             key=f"shimmy-sweep-{tag}-batch-{b}") for b in todo]
            for fut in as_completed(futures):
                table = fut.result()
                _write_table(_part(parts, int(table.column("batch")[0].as_py())), table)
                done += table.num_rows
                fut.release()
                if progress is not None:
                    progress(done, n)
    tables = [pq.read_table(_part(parts, b)) for b in range(batches)]
    table = pa.concat_tables(tables).sort_by("sample")
    meta = {METADATA_KEY: json.dumps(manifest).encode()}
    _write_table(out, table.replace_schema_metadata(meta))
    shutil.rmtree(parts)
    return SweepRun(table, out, batches, len(todo), size, cluster.workers, cluster.address, time.perf_counter() - t0)
