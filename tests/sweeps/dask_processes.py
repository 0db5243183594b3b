"""Real ``dask scheduler`` and ``dask worker`` processes on localhost for the sweep fault tests, and the shimmy
command run as a user runs it (the fixtures are in conftest.py)."""

from __future__ import annotations

import json
import os
import signal
import socket
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
DASK = os.path.join(os.path.dirname(sys.executable), "dask")
PRELOAD = os.path.join(os.path.dirname(os.path.abspath(__file__)), "worker_faults.py")
BATCH_DELAY_S = 0.05
CRASH_PRESSURE = 3.3       # bar: the sample of the killed-worker test; no other test's design holds it


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class Dask:
    """Scheduler and worker processes started by a test; all stopped (SIGKILL if need be) at its end."""

    def __init__(self, folder):
        self.folder = folder
        self.procs: list[subprocess.Popen] = []
        self.env = {**os.environ, "PYTHONPATH": ROOT, "SHIMMY_TEST_BATCH_DELAY_S": str(BATCH_DELAY_S),
                    "SHIMMY_TEST_CRASH_PRESSURE": repr(CRASH_PRESSURE),
                    # a batch is given up after its second worker died (Dask's default is 3 retries)
                    "DASK_DISTRIBUTED__SCHEDULER__ALLOWED_FAILURES": "1",
                    # one task at a time on a one-thread worker: a dying worker then takes only its own batch's
                    # count of deaths up, never a bystander's queued behind it
                    "DASK_DISTRIBUTED__SCHEDULER__WORKER_SATURATION": "1.0"}

    def _start(self, argv: list[str]) -> subprocess.Popen:
        log = open(os.path.join(self.folder, f"dask-{len(self.procs)}.log"), "wb")
        # a session each, so that stop() ends a worker's nanny and its worker processes at once
        proc = subprocess.Popen(argv, stdout=log, stderr=log, env=self.env, cwd=self.folder, start_new_session=True)
        log.close()
        self.procs.append(proc)
        return proc

    def scheduler(self, port: int | None = None) -> tuple[str, subprocess.Popen]:
        port = port or free_port()
        proc = self._start([DASK, "scheduler", "--host", "127.0.0.1", "--port", str(port), "--no-dashboard"])
        address = f"tcp://127.0.0.1:{port}"
        deadline = time.time() + 60
        while time.time() < deadline:
            try:
                socket.create_connection(("127.0.0.1", port), timeout=1).close()
                return address, proc
            except OSError:
                if proc.poll() is not None:
                    raise RuntimeError(f"dask scheduler exited with {proc.returncode}")
                time.sleep(0.1)
        raise RuntimeError("dask scheduler did not listen within 60 s")

    def worker(self, address: str, n: int = 1) -> subprocess.Popen:
        return self._start([DASK, "worker", address, "--nworkers", str(n), "--nthreads", "1", "--no-dashboard",
                            "--preload", PRELOAD])

    def wait_for_workers(self, address: str, n: int) -> list[int]:
        """Pids of the worker processes once ``n`` have joined."""
        from distributed import Client
        with Client(address, timeout="30s") as client:
            client.wait_for_workers(n, timeout=120)
            return sorted(client.run(os.getpid).values())

    def stop(self) -> None:
        """SIGKILL to each process group: nothing of a test cluster is worth a graceful close (8 s per worker)."""
        for p in reversed(self.procs):
            try:
                os.killpg(p.pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
            p.wait()


def shimmy(args: list[str], cwd, timeout: float = 300) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "comparisons.cli", *args], capture_output=True, text=True,
                          cwd=cwd, timeout=timeout, env={**os.environ, "PYTHONPATH": ROOT})


def start_shimmy(args: list[str], cwd) -> subprocess.Popen:
    """In a session of its own, so that a signal can reach it and its workers as a terminal's Ctrl-C does."""
    return subprocess.Popen([sys.executable, "-m", "comparisons.cli", *args], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, cwd=cwd, env={**os.environ, "PYTHONPATH": ROOT},
                            start_new_session=True)


def message(err: str) -> str:
    """The one line of a stopped sweep: no traceback, nothing but progress lines besides."""
    assert "Traceback" not in err, err
    lines = [line for line in err.splitlines() if line.strip() and not line.startswith("sweep: ")]
    assert len(lines) == 1, err
    return lines[0]


def parts_of(folder) -> list[str]:
    return sorted(n for n in os.listdir(folder) if n.startswith("batch-") and n.endswith(".parquet"))


def wait_for_parts(folder, k: int, proc: subprocess.Popen | None = None, timeout: float = 120) -> None:
    deadline = time.time() + timeout
    while time.time() < deadline:
        if os.path.isdir(folder) and len(parts_of(folder)) >= k:
            return
        if proc is not None and proc.poll() is not None:
            raise AssertionError(f"shimmy ended with {proc.returncode} before {k} parts: {proc.stderr.read()}")
        time.sleep(0.02)
    raise AssertionError(f"fewer than {k} parts in {folder} after {timeout} s")


def sweep_json(result: subprocess.CompletedProcess) -> dict:
    assert result.returncode == 0 and "Traceback" not in result.stderr, result.stderr
    return json.loads(result.stdout)
