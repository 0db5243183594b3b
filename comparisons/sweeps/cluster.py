"""The Dask cluster of a sweep: connecting to a scheduler or starting a local cluster, and telling a lost scheduler
from a batch that failed.

Without a scheduler address a scheduler is started in this process with one single-threaded ``dask worker``
process per core, each in a session of its own (so that a terminal's Ctrl-C reaches shimmy only): one Hopf computation is a few milliseconds of small numpy calls that hold the GIL, so threads
would not run in parallel.

A scheduler address is checked before use (:func:`scheduler_address`: scheme ``tcp://``, a host name or IP
address, a port 1-65535), and the scheduler is probed before the Dask client is made (:func:`probe_scheduler`): the
TCP connection and the scheduler's handshake message must arrive within :data:`CONNECT_TIMEOUT_S` together, and
that message may announce at most :data:`HANDSHAKE_MAX_BYTES`.  The client library trusts the sizes a peer
announces (it allocates a buffer of that size first) and waits for a handshake without a deadline; a port that
accepts and never answers, or a server that answers nonsense, is refused here in one line instead.  Any exception
of the client library while connecting is one line too.

Distributed's own loggers are silenced while a sweep runs: when the scheduler goes away they log several
tracebacks from the client's reconnect loop, and what happened is said in one line by the command instead.
"""

from __future__ import annotations

import enum
import importlib
import ipaddress
import logging
import os
import re
import signal
import socket
import struct
import subprocess
import sys
import time
import warnings

from axles.limits import UsageError

CONNECT_TIMEOUT_S = 10.0       # the TCP connection and the scheduler's handshake together
HANDSHAKE_MAX_BYTES = 1 << 20   # a scheduler's handshake is a few hundred bytes
_HOST_LABEL = re.compile(r"(?!-)[A-Za-z0-9-]{1,63}(?<!-)")
WAIT_FOR_WORKERS_S = 60.0
LOST_GRACE_S = 2.0     # a result's connection may close a moment before the client marks the scheduler lost
# A question to a scheduler that has just died waits for the client's reconnection (CONNECT_TIMEOUT_S): bounded
THREADS_QUERY_S = 1.0
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


def scheduler_address(text: str | None) -> tuple[str, str, int] | None:
    """(``tcp://HOST:PORT``, host, port) of a ``--scheduler`` address, None without one; :class:`UsageError`
    (one line) for anything else: blanks, another scheme, no port, a port that is not 1-65535, a bad host."""
    if text is None:
        return None
    what = f"--scheduler {text!r}"
    address = text.strip()
    if not address:
        raise UsageError(f"{what}: an empty address (give tcp://HOST:PORT, or leave the option out for a local "
                         f"cluster)")
    if any(c.isspace() or not c.isprintable() for c in address):
        raise UsageError(f"{what}: blanks or control characters in the address")
    scheme, sep, rest = address.partition("://")
    if not sep:
        scheme, rest = "tcp", address
    scheme = scheme.lower()
    if scheme == "tls":
        raise UsageError(f"{what}: tls:// needs a TLS security context (certificates), which shimmy does not set "
                         f"up; use tcp:// (through an SSH tunnel to a remote scheduler)")
    if scheme != "tcp":
        raise UsageError(f"{what}: the scheme {scheme}:// is not supported (a Dask scheduler listens on "
                         f"tcp://HOST:PORT)")
    if rest.startswith("["):                      # [IPv6]:PORT
        host, close, port_text = rest[1:].partition("]")
        if not close or not port_text.startswith(":"):
            raise UsageError(f"{what}: an IPv6 address needs the form tcp://[ADDRESS]:PORT")
        port_text = port_text[1:]
    else:
        host, colon, port_text = rest.rpartition(":")
        if not colon:
            host, port_text = rest, ""
    if not port_text:
        raise UsageError(f"{what}: no port (tcp://HOST:PORT; a Dask scheduler listens on 8786 by default)")
    if not port_text.isascii() or not port_text.isdigit() or not 1 <= int(port_text) <= 65535:
        raise UsageError(f"{what}: the port must be a whole number within [1, 65535], got '{port_text}'")
    if not _valid_host(host):
        raise UsageError(f"{what}: '{host}' is not a host name or an IP address")
    port = int(port_text)
    shown = f"[{host}]" if ":" in host else host
    return f"tcp://{shown}:{port}", host, port


def _valid_host(host: str) -> bool:
    try:
        ipaddress.ip_address(host)
        return True
    except ValueError:
        pass
    return (0 < len(host) <= 253 and host.isascii()
            and all(_HOST_LABEL.fullmatch(label) for label in host.rstrip(".").split(".")))


def probe_scheduler(host: str, port: int, what: str, timeout: float | None = None) -> None:
    """Connect to ``host:port`` and read the scheduler's handshake within ``timeout`` s (default
    :data:`CONNECT_TIMEOUT_S`), checking the sizes it announces before reading them; :class:`UsageError`
    (one line) when it does not answer as a Dask scheduler does."""
    timeout = CONNECT_TIMEOUT_S if timeout is None else timeout
    deadline = time.monotonic() + timeout
    try:
        sock = socket.create_connection((host, port), timeout=timeout)
    except socket.gaierror as exc:
        raise UsageError(f"{what}: cannot resolve the host '{host}' ({exc.strerror or exc})") from None
    except TimeoutError:
        raise UsageError(f"{what}: cannot connect within {timeout:g} s") from None
    except OSError as exc:
        raise UsageError(f"{what}: cannot connect ({exc.strerror or exc})") from None
    with sock:
        header = _receive(sock, 8, deadline, what, timeout)
        (total,) = struct.unpack("Q", header)     # distributed's framing: byte count, then the frames
        if total > HANDSHAKE_MAX_BYTES or total < 8:
            raise UsageError(f"{what}: not a Dask scheduler (its first message announces {total} bytes; a "
                             f"handshake has at most {HANDSHAKE_MAX_BYTES})")
        body = _receive(sock, total, deadline, what, timeout)
        (frames,) = struct.unpack_from("Q", body)
        if not 1 <= frames <= 64 or 8 * (1 + frames) > total:
            raise UsageError(f"{what}: not a Dask scheduler (its handshake is not framed as Dask frames it)")
        lengths = struct.unpack_from(f"{frames}Q", body, 8)
        if sum(lengths) > HANDSHAKE_MAX_BYTES:
            raise UsageError(f"{what}: not a Dask scheduler (its handshake announces {sum(lengths)} bytes)")


def _receive(sock: socket.socket, n: int, deadline: float, what: str, timeout: float) -> bytes:
    """Exactly ``n`` bytes before ``deadline``, or a :class:`UsageError`."""
    data = bytearray()
    while len(data) < n:
        left = deadline - time.monotonic()
        if left <= 0:
            raise UsageError(f"{what}: connected, but no Dask handshake within {timeout:g} s (is it a Dask "
                             f"scheduler?)")
        sock.settimeout(left)
        try:
            chunk = sock.recv(min(n - len(data), 65536))
        except TimeoutError:
            continue
        except OSError as exc:
            raise UsageError(f"{what}: the connection failed ({exc.strerror or exc})") from None
        if not chunk:
            raise UsageError(f"{what}: the server closed the connection before a Dask handshake (is it a Dask "
                             f"scheduler?)")
        data += chunk
    return bytes(data)


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


def threads_of(client) -> int | None:
    """The worker threads of ``client``'s cluster now, or None when its scheduler does not answer within
    :data:`THREADS_QUERY_S` (a lost scheduler: the batches in flight say so)."""
    if client.status != "running":
        return None
    try:
        return max(1, sum(client.nthreads(callback_timeout=THREADS_QUERY_S).values()))
    except Exception:  # noqa: BLE001 - Dask's and the network's errors alike, and the timeout
        return None


class DaskCluster:
    """A Dask client on ``scheduler`` or on a fresh local cluster (closed on exit).  ``processes=False``: one
    single-threaded worker inside this process, for small sweeps where starting worker processes (each importing
    numpy, scipy and Exudyn) would cost more than the work."""

    def __init__(self, scheduler: str | None, workers: int | None, processes: bool = True):
        from distributed import Client
        self.cluster = None
        self.procs: list[subprocess.Popen] = []
        self.lost = False
        checked = scheduler_address(scheduler)
        if checked is not None:
            address, host, port = checked
            what = f"--scheduler {address}"
            probe_scheduler(host, port, what)
            try:
                self.client = Client(address, timeout=f"{CONNECT_TIMEOUT_S:g}s")
            except Exception as exc:   # noqa: BLE001 - whatever the client library raises: one line
                raise UsageError(f"{what}: cannot connect ({type(exc).__name__}: {exc})") from None
            try:   # a scheduler without workers would hold the sweep forever
                self.client.wait_for_workers(1, timeout=WAIT_FOR_WORKERS_S)
            except Exception:   # noqa: BLE001
                self.client.close()
                raise UsageError(f"{what}: no worker joined within {WAIT_FOR_WORKERS_S:g} s "
                                 f"(start one with 'dask worker {address}')") from None
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
