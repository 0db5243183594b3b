"""Running a sweep on Dask distributed, writing Parquet as batches finish, and resuming an interrupted sweep.

Samples go to the workers in batches (:func:`batch_size`) sized so that each batch takes about a second: Dask's
per-task cost (about a millisecond) then stays far below the work.  The :class:`~comparisons.sweeps.sample.SweepTask`
is sent to the workers once (as the output of one task), not with each batch.  The cluster is
:mod:`comparisons.sweeps.cluster`.

Each finished batch is written at once, atomically and with its checksum, to ``OUT.parts/batch-NNNNNN.parquet``
beside ``OUT`` with a manifest (:mod:`comparisons.sweeps.parts`).  When all batches are there they are joined,
sorted by sample, into ``OUT`` (the manifest in its schema metadata) and the parts folder is removed.
``resume=True`` reads the manifest, refuses a different sweep or a changed axle file, checks every kept part and
computes only the batches that are missing or damaged.  ``OUT.lock`` keeps a second sweep out meanwhile.

What the cluster does to a batch: a worker that dies is replaced and the batch retried by Dask itself; a batch
that kills every worker that tries it (``KilledWorker``) becomes failed rows; a lost scheduler stops the sweep with
:class:`~comparisons.sweeps.cluster.SweepStopped`, the finished batches kept for ``--resume``.
"""

from __future__ import annotations

import contextlib
import json
import math
import os
import shutil
import time
from dataclasses import dataclass
from typing import Callable

import pyarrow as pa
import pyarrow.parquet as pq

from axles.limits import UsageError
from comparisons.sweeps.cluster import (
    DaskCluster,
    StopReason,
    SweepStopped,
    local_workers,
    quiet_distributed,
    restore_logging,
    threads_of,
)
from comparisons.sweeps.design import Design
from comparisons.sweeps.parts import (
    MANIFEST,
    MANIFEST_VERSION,
    DamagedPart,
    SweepLock,
    check_parts,
    part_path,
    parts_folder,
    read_manifest,
    write_manifest,
    write_part,
    write_table,
)
from comparisons.sweeps.sample import SweepTask, evaluate_batch, failed_batch

__all__ = ["DaskCluster", "SweepRun", "batch_size", "run_sweep"]

TARGET_BATCH_S = 1.0
BATCHES_PER_WORKER = 4       # at least, so that the last batches do not leave a worker idle for long
METADATA_KEY = b"shimmy_sweep"


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
    damaged: tuple[DamagedPart, ...] = ()
    killed_batches: tuple[int, ...] = ()     # batches whose every worker died: failed rows

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
                "damaged_batches": [d.to_json() for d in self.damaged], "killed_batches": list(self.killed_batches),
                "batch_size": self.batch_size, "workers": self.workers, "scheduler": self.scheduler,
                "elapsed_s": self.elapsed_s,
                "samples_per_s": (self.samples * computed / self.batches) / self.elapsed_s if self.elapsed_s > 0
                else None}


def batch_size(task: SweepTask, samples: int, workers: int) -> int:
    """About :data:`TARGET_BATCH_S` of work per batch, and at least :data:`BATCHES_PER_WORKER` batches per worker."""
    by_time = max(1, int(TARGET_BATCH_S / task.cost_s()))
    by_balance = max(1, math.ceil(samples / (BATCHES_PER_WORKER * max(1, workers))))
    return min(by_time, by_balance)


def _manifest(task: SweepTask, design: Design, size: int | None) -> dict:
    axle = task.axle
    return {"version": MANIFEST_VERSION, "design": design.to_json(), "fingerprint": design.fingerprint(),
            "task": task.to_json(), "batch_size": size, "axle_file": axle.file, "axle_sha256": axle.sha256}


def _same_sweep(a: dict, b: dict) -> bool:
    keys = ("fingerprint", "task")
    return all(json.dumps(a.get(k), sort_keys=True) == json.dumps(b.get(k), sort_keys=True) for k in keys)


def _check_axle_file(found: dict, manifest: dict, parts: str) -> None:
    """Refuse to continue with an axle file that changed since the sweep began (its kept batches used the old one)."""
    then, now = found.get("axle_sha256"), manifest["axle_sha256"]
    if found.get("axle_file") and found.get("axle_file") == manifest["axle_file"] and then != now:
        raise UsageError(f"--resume: the axle file {manifest['axle_file']} changed since the sweep began (SHA-256 "
                         f"{str(then)[:16]}... then, {str(now)[:16]}... now): restore it, or delete "
                         f"{parts} to start again")


def _existing(out: str, manifest: dict, resume: bool) -> tuple[dict | None, bool]:
    """(manifest of the sweep to continue or None for a new one, whether ``out`` already holds it complete);
    checked before any cluster is started and without touching a file."""
    parts = parts_folder(out)
    if os.path.exists(os.path.join(parts, MANIFEST)):
        if not resume:
            raise UsageError(f"{parts} holds an interrupted sweep: --resume continues it (or delete the folder)")
        found = read_manifest(parts)
        _check_axle_file(found, manifest, parts)
        if not _same_sweep(found, manifest):
            raise UsageError(f"--resume: {parts} holds a different sweep (other inputs, samples, seed or outputs)")
        return found, False
    if resume and os.path.exists(out):
        try:
            found = json.loads((pq.read_schema(out).metadata or {}).get(METADATA_KEY, b"{}"))
        except (OSError, pa.ArrowException, ValueError):
            raise UsageError(f"--resume: {out} is not a sweep's Parquet file") from None
        if not _same_sweep(found, manifest):
            raise UsageError(f"--resume: {out} holds a different sweep (other inputs, samples, seed or outputs)")
        return found, True
    if resume:
        raise UsageError(f"--resume: neither {out} nor {parts} exists: nothing to resume")
    return None, False


def _batch_result(fut, cluster: DaskCluster, task: SweepTask, design: Design, batch: int,
                  size: int) -> tuple[pa.Table, bool]:
    """(the table of one finished future, whether every worker that ran it died): its rows, or failed rows for a
    batch that killed its workers; :class:`SweepStopped` when the cluster itself failed."""
    from distributed.scheduler import KilledWorker
    start = batch * size
    try:
        return fut.result(), False
    except KilledWorker as exc:
        return failed_batch(task, batch, start, design.values[start:start + size], f"KilledWorker: {exc}"), True
    except Exception as exc:  # Dask's and the network's errors alike: is the scheduler gone, or this batch?
        if cluster.scheduler_lost():
            raise SweepStopped(StopReason.SCHEDULER_LOST, f"lost the Dask scheduler {cluster.address}") from None
        raise SweepStopped(StopReason.CLUSTER_ERROR, f"batch {batch} failed on the cluster "
                                                     f"({type(exc).__name__}: {exc})") from None


def run_sweep(task: SweepTask, design: Design, out: str, *, scheduler: str | None = None, workers: int | None = None,
              cluster: DaskCluster | None = None, size: int | None = None, resume: bool = False,
              progress: Callable[[int, int], None] | None = None,
              notice: Callable[[str], None] | None = None) -> SweepRun:
    """Evaluate every sample of ``design`` on Dask, batches written to Parquet as they finish; see module docs.

    ``notice`` is told, one line each, what the run found and did about it (damaged parts, a stale lock).
    ``cluster``: a cluster this process already holds (kept open), instead of a ``scheduler`` address to check and
    connect to or a local cluster to start."""
    own = cluster
    if own is not None:
        scheduler = own.address
    t0 = time.perf_counter()
    n = len(design)
    say = notice or (lambda text: None)
    manifest = _manifest(task, design, size)
    parts = parts_folder(out)
    with SweepLock(out) as lock:
        if lock.stale:
            say(f"took over the stale lock {lock.path} ({lock.stale}): that sweep is no longer running")
        found, complete = _existing(out, manifest, resume)
        if complete:
            return SweepRun(pq.read_table(out), out, math.ceil(n / found["batch_size"]), 0, found["batch_size"], 0,
                            "", time.perf_counter() - t0)
        kept, damaged = set(), []
        new = found is None
        if not new:
            manifest = found
            kept, damaged = check_parts(parts, n, manifest["batch_size"], task.schema(), manifest["fingerprint"])
            for d in damaged:
                say(f"{d.name} is damaged ({d.damage.value}): computed again")
        elif scheduler is None:   # written before the cluster starts, so that an interrupt then can be resumed
            manifest["batch_size"] = size or batch_size(task, n, local_workers(workers))
            write_manifest(parts, manifest)
        levels = quiet_distributed()
        cluster = None
        try:
            with (contextlib.nullcontext(own) if own is not None else DaskCluster(scheduler, workers)) as cluster:
                if new and scheduler is not None:
                    manifest["batch_size"] = size or batch_size(task, n, cluster.workers)
                    write_manifest(parts, manifest)
                todo, killed = _compute(cluster, task, design, parts, manifest, kept, progress)
        finally:
            if cluster is None or not cluster.lost:   # a lost scheduler's client goes on logging until exit
                restore_logging(levels)
        size = manifest["batch_size"]
        batches = math.ceil(n / size)
        table = pa.concat_tables([pq.read_table(part_path(parts, b)).replace_schema_metadata(None)
                                 for b in range(batches)]).sort_by("sample")
        write_table(out, table.replace_schema_metadata({METADATA_KEY: json.dumps(manifest).encode()}))
        shutil.rmtree(parts)
    return SweepRun(table, out, batches, len(todo), size, cluster.workers,
                    cluster.address, time.perf_counter() - t0, tuple(damaged), tuple(killed))


def _the_task(task: SweepTask) -> SweepTask:
    return task


def _compute(cluster: DaskCluster, task: SweepTask, design: Design, parts: str, manifest: dict, kept: set[int],
             progress: Callable[[int, int], None] | None) -> tuple[list[int], list[int]]:
    """Compute and write every batch not in ``kept``; (batches computed, batches whose workers all died)."""
    n, size = len(design), manifest["batch_size"]
    batches = math.ceil(n / size)
    todo = [b for b in range(batches) if b not in kept]
    done = n - sum(min(size, n - b * size) for b in todo)
    if progress is not None:
        progress(done, n)
    killed = []
    if not todo:
        return todo, killed
    from distributed import as_completed
    tag = manifest["fingerprint"][:12]
    # The task as the output of a task, not scattered: when every worker holding it dies, Dask computes it again
    # (a scattered value lost with its last worker cancels every batch that needs it).
    shared = cluster.client.submit(_the_task, task, pure=False, key=f"shimmy-sweep-{tag}-task")
    # On every worker: with it on one alone, the scheduler queued every batch there (where their input was) and
    # left the others idle while a slow sample ran (6 minutes in a 16-sample sweep, docs/sweeps.md).
    from distributed import wait
    wait([shared])
    cluster.client.replicate([shared])
    waiting, batch_of = list(reversed(todo)), {}
    threads = 1

    def submit_more(running) -> None:
        # no more batches in flight than the cluster has threads: the scheduler assigns a task to a worker when it
        # is submitted, and a batch queued behind a slow sample waited there while other workers stood idle
        nonlocal threads
        threads = threads_of(cluster.client) or threads
        while waiting and len(batch_of) < threads:
            b = waiting.pop()
            fut = cluster.client.submit(evaluate_batch, shared, b, b * size, design.values[b * size:(b + 1) * size],
                                        pure=False, key=f"shimmy-sweep-{tag}-batch-{b}")
            batch_of[fut.key] = b
            running.add(fut)

    running = as_completed([])
    submit_more(running)
    for fut in running:
        b = batch_of.pop(fut.key)
        table, died = _batch_result(fut, cluster, task, design, b, size)
        if died:
            killed.append(b)
        write_part(parts, b, table, manifest["fingerprint"])
        done += table.num_rows
        fut.release()
        if progress is not None:
            progress(done, n)
        submit_more(running)
    return todo, sorted(killed)
