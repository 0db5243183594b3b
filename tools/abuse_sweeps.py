"""The sweep faults of ``tools/abuse.py``: ``shimmy sweep`` against a real ``dask scheduler`` and ``dask worker``
processes started here on localhost, with the fault injected while it runs or into its files between runs.

The cases form a story and run in order: the scheduler killed mid-sweep, then the printed command against a
restarted one; a worker killed; an unreachable scheduler; Ctrl-C, then a part of another sweep and a truncated part
on ``--resume``; a second sweep into a busy ``--out``; a stale lock after ``kill -9``; a batch that kills every
worker; a full disk (tmpfs, root only), then ``--resume`` once space is back; Ctrl-C while the local cluster
starts.  Each completed sweep is checked: every sample once, in order.
"""

from __future__ import annotations

import os
import shlex
import signal
import socket
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DASK = os.path.join(os.path.dirname(sys.executable), "dask")
PRELOAD = os.path.join(ROOT, "tests", "sweeps", "worker_faults.py")   # slow batches, a pressure that kills
SAMPLES, SIZE = 200, 5
CRASH_PRESSURE = 3.3


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def parts_of(out: str) -> list[str]:
    try:
        return sorted(n for n in os.listdir(out + ".parts") if n.startswith("batch-") and n.endswith(".parquet"))
    except OSError:
        return []


def wait_for(condition, timeout: float = 120.0) -> None:
    deadline = time.monotonic() + timeout
    while not condition() and time.monotonic() < deadline:
        time.sleep(0.02)


class Lab:
    """The Dask processes of the sweep cases, on one port that survives a scheduler restart."""

    def __init__(self, scratch: str):
        self.scratch = scratch
        self.port = _free_port()
        self.address = f"tcp://127.0.0.1:{self.port}"
        self.scheduler: subprocess.Popen | None = None
        self.procs: list[subprocess.Popen] = []
        self.background: subprocess.Popen | None = None
        self.env = dict(os.environ, PYTHONPATH=ROOT, SHIMMY_TEST_BATCH_DELAY_S="0.02",
                        SHIMMY_TEST_CRASH_PRESSURE=repr(CRASH_PRESSURE),
                        DASK_DISTRIBUTED__SCHEDULER__ALLOWED_FAILURES="1",
                        DASK_DISTRIBUTED__SCHEDULER__WORKER_SATURATION="1.0")

    def _spawn(self, argv: list[str]) -> subprocess.Popen:
        proc = subprocess.Popen(argv, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=self.env,
                                cwd=self.scratch, start_new_session=True)
        self.procs.append(proc)
        return proc

    def start(self, workers: int = 2) -> None:
        self.scheduler = self._spawn([DASK, "scheduler", "--host", "127.0.0.1", "--port", str(self.port),
                                      "--no-dashboard"])
        self._spawn([DASK, "worker", self.address, "--nworkers", str(workers), "--nthreads", "1",
                     "--no-dashboard", "--preload", PRELOAD])
        self.worker_pids(workers)

    def ensure(self) -> None:
        """Started, for a case run alone (--only)."""
        if self.scheduler is None or self.scheduler.poll() is not None:
            self.start()

    def worker_pids(self, n: int) -> list[int]:
        from distributed import Client
        with Client(self.address, timeout="60s") as client:
            client.wait_for_workers(n, timeout=120)
            return sorted(client.run(os.getpid).values())

    def kill_scheduler(self) -> None:
        self.scheduler.kill()
        self.scheduler.wait()

    def run_in_background(self, argv: list[str]) -> subprocess.Popen:
        self.background = subprocess.Popen([sys.executable, "-m", "comparisons.cli", *argv],
                                           stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, env=self.env,
                                           cwd=ROOT)
        return self.background

    def stop(self) -> None:
        for p in reversed(self.procs):    # a nanny and its worker processes at once
            try:
                os.killpg(p.pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
            p.wait()
        if self.background is not None and self.background.poll() is None:
            self.background.kill()
            self.background.wait()


def _after_parts(out: str, k: int, act):
    def during(proc: subprocess.Popen) -> float:
        wait_for(lambda: len(parts_of(out)) >= k or proc.poll() is not None)
        act(proc)
        return time.monotonic()
    return during


def _complete(out: str, killed: tuple[int, ...] = ()):
    """Every sample once and in order; ok unless its batch killed its workers, as ``killed`` must have."""
    def check(stdout: bytes, stderr: str) -> str:
        import pyarrow.parquet as pq
        try:
            table = pq.read_table(out).to_pylist()
        except OSError as exc:
            return f"no complete output: {exc}"
        if [r["sample"] for r in table] != list(range(len(table))):
            return "samples lost, duplicated or out of order"
        # Dask may give up a bystander batch with the killer: failed as a whole, with KilledWorker
        gone = {r["batch"] for r in table if (r["error"] or "").startswith("KilledWorker: ")}
        bad = [r for r in table if (r["status"] != "ok") != (r["batch"] in gone)
               or (r["sample"] in killed and r["batch"] not in gone)]
        return f"unexpected status of samples {[r['sample'] for r in bad[:5]]} ({bad[0]['error']})" if bad else ""
    return check


def _all(*checks):
    def check(stdout: bytes, stderr: str) -> str:
        return "; ".join(p for p in (c(stdout, stderr) for c in checks) if p)
    return check


def _says(text: str):
    return lambda stdout, stderr: "" if text in stderr else f"stderr does not say '{text}'"


def _foreign_part(out: str) -> None:
    """Put a part written by shimmy for another sweep in place of a kept one (the kept one moved aside)."""
    import numpy as np

    from axles.axle import AxleData
    from comparisons.sweeps.design import make_design, parse_vary
    from comparisons.sweeps.parts import part_path, write_part
    from comparisons.sweeps.sample import SweepTask, evaluate_batch
    parts = out + ".parts"
    b = int(parts_of(out)[0][6:12])
    for suffix in ("", ".sha256"):
        os.replace(part_path(parts, b) + suffix, part_path(parts, b) + suffix + ".mine")
    other = make_design([parse_vary("pressure=1:2:5")], None, None)
    task = SweepTask(AxleData(), (), 2.5, 2.5, other.names)
    write_part(parts, b, evaluate_batch(task, b, b * SIZE, np.asarray(other.values)), other.fingerprint())


def _restore_and_truncate(out: str) -> None:
    parts = out + ".parts"
    for name in os.listdir(parts):
        if name.endswith(".mine"):
            os.replace(os.path.join(parts, name), os.path.join(parts, name[:-len(".mine")]))
    victim = os.path.join(parts, parts_of(out)[-1])
    with open(victim, "r+b") as fh:
        fh.truncate(os.path.getsize(victim) // 2)


def sweep_cases(scratch: str, case_type, lab: Lab, disk: str | None) -> list:
    """The catalogue; ``case_type`` is abuse.Case, ``disk`` a 64 kB tmpfs (None: those cases are left out)."""
    Case = case_type
    sweep = ["sweep", "--vary", f"pressure=0.8:3.2:{SAMPLES}", "--batch-size", str(SIZE)]
    remote = [*sweep, "--scheduler", lab.address]
    # long enough to be running still when a second command has loaded (seconds on a busy machine)
    long = ["sweep", "--vary", "pressure=0.8:3.2:1500", "--batch-size", str(SIZE), "--scheduler", lab.address]
    folder = os.path.join(scratch, "sweeps")
    os.makedirs(folder, exist_ok=True)
    lost, worker, ctrl_c, busy, crash, local = (os.path.join(folder, f"{n}.parquet") for n in
                                                ("lost", "worker", "ctrlc", "busy", "crash", "local"))

    def kill_a_worker(proc) -> None:
        os.kill(lab.worker_pids(2)[0], signal.SIGKILL)

    def busy_first() -> None:
        lab.ensure()
        lab.run_in_background([*long, "--out", busy])
        wait_for(lambda: len(parts_of(busy)) >= 1)

    def first_finished(stdout, stderr) -> str:
        code = lab.background.wait(timeout=300)
        return "" if code == 0 else f"the first sweep ended with {code}"

    def killed_with_9() -> None:
        os.unlink(busy)
        busy_first()
        lab.background.kill()
        lab.background.wait()

    def restart() -> None:
        lab.start()

    def two_workers() -> None:   # the nanny restarts a killed worker: wait for it
        lab.ensure()
        lab.worker_pids(2)

    def more_space() -> None:
        subprocess.run(["mount", "-o", "remount,size=4m", disk], check=True)

    cases = [
        Case("sweep: scheduler killed (kill -9) mid-sweep", [*remote, "--out", lost], (3,), serial=True,
             before=lab.start, during=_after_parts(lost, 3, lambda p: lab.kill_scheduler()), within=10.0,
             check=_says(f"this continues: {shlex.join(['shimmy', *remote, '--out', lost, '--resume'])}")),
        Case("sweep: the printed command once the scheduler is back", [*remote, "--out", lost, "--resume"], (0,),
             serial=True, before=restart, check=_complete(lost)),
        Case("sweep: a worker killed (kill -9) mid-sweep", [*remote, "--out", worker], (0,), serial=True,
             before=two_workers, during=_after_parts(worker, 2, kill_a_worker),
             check=_complete(worker)),
        Case("sweep --scheduler unreachable", [*sweep, "--scheduler", f"tcp://127.0.0.1:{_free_port()}", "--out",
                                               os.path.join(folder, "never.parquet")], (2,), serial=True),
        Case("sweep: Ctrl-C mid-sweep", [*remote, "--out", ctrl_c], (130,), serial=True,
             before=lab.ensure, during=_after_parts(ctrl_c, 3, lambda p: p.send_signal(signal.SIGINT))),
        Case("sweep --resume with a part of another sweep", [*remote, "--out", ctrl_c, "--resume"], (2,),
             serial=True, before=lambda: _foreign_part(ctrl_c), check=_says("is a part of sweep")),
        Case("sweep --resume with a truncated part", [*remote, "--out", ctrl_c, "--resume"], (0,), serial=True,
             before=lambda: _restore_and_truncate(ctrl_c),
             check=_all(_complete(ctrl_c), _says("is damaged (not a readable Parquet file): computed again"))),
        Case("sweep: a second sweep into a busy --out", [*long, "--out", busy], (2,), serial=True,
             before=busy_first, check=_all(_says("another sweep writes there"), first_finished)),
        Case("sweep --resume after kill -9 (a stale lock)", [*long, "--out", busy, "--resume"], (0,),
             serial=True, before=killed_with_9, check=_all(_complete(busy), _says("took over the stale lock"))),
        # pressure 3.3 bar, the last sample, makes the workers exit (the preload): its batch of three fails.  Ten
        # batches for two workers: Dask queues them (one per worker at a time), so no other batch shares its fate.
        Case("sweep: a batch that kills every worker", ["sweep", "--vary", "pressure=0.4:3.3:30", "--batch-size",
                                                        "3", "--scheduler", lab.address, "--out", crash], (0,),
             serial=True, before=two_workers, check=_complete(crash, killed=(27, 28, 29))),
        Case("sweep: Ctrl-C while the local cluster starts", [*sweep, "--workers", "1", "--out", local], (130,),
             serial=True, during=_when_manifest(local), within=1.0),
    ]
    if disk is not None:
        full = os.path.join(disk, "full.parquet")
        cases += [
            Case("sweep onto a full disk", [*remote, "--out", full], (74,), serial=True, watch=(disk,),
                 before=lab.ensure,
                 check=_says("once there is space, this continues: ")),
            Case("sweep --resume once space is back", [*remote, "--out", full, "--resume"], (0,), serial=True,
                 before=more_space,
                 check=_complete(full)),
        ]
    return cases


def _when_manifest(out: str):
    def during(proc: subprocess.Popen) -> float:
        wait_for(lambda: os.path.exists(os.path.join(out + ".parts", "manifest.json")) or proc.poll() is not None)
        time.sleep(0.3)   # the worker process is starting
        proc.send_signal(signal.SIGINT)
        return time.monotonic()
    return during

