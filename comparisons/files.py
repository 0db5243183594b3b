"""Output files: checked before the work, written so that a failure or an interrupt never leaves a truncated file
under the final name nor a temporary file behind, and write faults kept apart from results.

* :func:`check_output` proves, before minutes of computing, that a file can be written where asked (folder exists
  and is writable, name and temporary name fit the file system, not a directory, not a device to rename over).
* :func:`atomic_path` yields a temporary name beside the target and renames it over the target on success.  A
  target that exists and is not a regular file (``/dev/null``, a FIFO, a terminal) is never renamed over: the
  writer writes into it directly.
* Every temporary file alive in this process is listed in :data:`LIVE_TEMPORARIES`, so that an interrupt
  (``comparisons.cli``) removes them before exiting.
* A write that fails (disk full, read-only file system, I/O error) raises :class:`OutputFault`, which derives from
  ``BaseException`` like ``KeyboardInterrupt``: the ``except Exception`` handlers that turn a failed computation
  into a FAIL row of a report never turn a fault of the machine into a result.
* :func:`run_writer` runs a writer that may block forever on a failing sink (the Rerun file sink waits on its
  flush when the disk fills) in a thread watched from here: a stalled write ends with :class:`OutputFault`.
"""

from __future__ import annotations

import contextlib
import errno
import os
import re
import secrets
import stat
import threading
import time
from typing import Callable, Iterator

NAME_MAX_DEFAULT = 255          # bytes per name on Linux file systems when pathconf cannot say
_TMP_SUFFIX = ".tmp"
WRITE_ERRNOS = {errno.ENOSPC, errno.EDQUOT, errno.EROFS, errno.EIO, errno.EFBIG, errno.EPIPE, errno.ENXIO}

LIVE_TEMPORARIES: set[str] = set()
_LOCK = threading.Lock()
STUCK_WRITERS: list[threading.Thread] = []   # writer threads that never returned: the process must not wait on them
FAULTED_TEMPORARIES: list[str] = []          # temporary names of failed writers: a writer thread may recreate them
WATCHED_FOLDERS: set[str] = set()            # folders where worker processes of this run write (figures)


def run_id() -> str:
    """The id of this run in temporary names: the command's pid, inherited by its worker processes."""
    return os.environ.get("SHIMMY_RUN_ID") or str(os.getpid())


def watch_folder(path: str) -> None:
    """Workers of this run write temporary files in ``path``: remove them too when the run is interrupted."""
    WATCHED_FOLDERS.add(os.path.abspath(path))


class OutputFault(BaseException):
    """An output could not be written (disk full, read-only, closed stdout): one line, exit code 74.

    A ``BaseException`` on purpose (see the module docstring): it is a fault of the machine, not of a check.
    """

    def __init__(self, message: str) -> None:
        super().__init__(message)
        self.message = message


class OutputPathError(ValueError):
    """An output path that cannot be used; caught before the work and reported as bad input (exit 2)."""


def _name_max(folder: str) -> int:
    try:
        return int(os.pathconf(folder, "PC_NAME_MAX"))
    except (OSError, ValueError):
        return NAME_MAX_DEFAULT


def is_special(path: str) -> bool:
    """True when ``path`` exists and is not a regular file (a device, a FIFO, a socket): never renamed over."""
    try:
        mode = os.stat(path).st_mode
    except OSError:
        return False
    return not stat.S_ISREG(mode) and not stat.S_ISDIR(mode)


def temporary_name(final: str) -> str:
    """A fresh temporary name beside ``final`` that fits the folder's name limit and is plain ASCII.

    Plain ASCII because some writers (Rerun) take the name as UTF-8 text and cannot encode the undecodable bytes
    a file name may carry (``surrogateescape``); the final name is given to ``os.replace`` only, which takes bytes.
    """
    folder, base = os.path.split(final)
    stem = re.sub(r"[^A-Za-z0-9._+-]", "_", base.encode("utf-8", "surrogateescape").decode("ascii", "replace"))
    tag = f".{run_id()}-{secrets.token_hex(4)}"
    room = _name_max(folder or ".") - len(tag) - len(_TMP_SUFFIX) - 1
    return os.path.join(folder, "." + stem[:max(room, 1)] + tag + _TMP_SUFFIX)


def check_output(path: str, what: str = "output", recording: bool = False) -> str:
    """Raise :class:`OutputPathError` (one line) unless ``path`` can take an output file; returns the absolute path.

    ``recording``: the writer must read its file back (Rerun recordings), so a device or pipe is refused too.
    """
    if not path or not path.strip():
        raise OutputPathError(f"{what}: an empty file name")
    final = os.path.abspath(path)
    folder, base = os.path.split(final)
    if os.path.isdir(final) or path.endswith(os.sep):
        raise OutputPathError(f"{what} {path}: a directory is in the way (give a file name)")
    if not os.path.isdir(folder):
        raise OutputPathError(f"{what} {path}: the folder {folder} does not exist")
    name_max = _name_max(folder)
    if len(base.encode("utf-8", "surrogateescape")) > name_max:
        raise OutputPathError(f"{what}: the file name is longer than {name_max} bytes")
    if is_special(final):
        if recording:
            raise OutputPathError(f"{what} {path}: not a regular file (a recording is read back after writing; "
                                  f"give a file name)")
        if not os.access(final, os.W_OK):
            raise OutputPathError(f"{what} {path}: not writable")
        return final
    if os.path.exists(final) and not os.access(final, os.W_OK) and not os.access(folder, os.W_OK):
        raise OutputPathError(f"{what} {path}: not writable")
    if not os.access(folder, os.W_OK | os.X_OK):
        raise OutputPathError(f"{what} {path}: the folder {folder} is not writable")
    try:   # access() says yes to root on a read-only mount: try a real file
        probe = temporary_name(final)
        fd = os.open(probe, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o600)
        os.close(fd)
        os.unlink(probe)
    except OSError as exc:
        raise OutputPathError(f"{what} {path}: cannot write in {folder} ({exc.strerror or exc})") from None
    return final


PATH_MAX_DEFAULT = 4096         # bytes per path on Linux when pathconf cannot say


def shown_path(path: str, limit: int = 120) -> str:
    """``path`` for a message: a path of thousands of bytes is cut in the middle, so the line stays readable."""
    return path if len(path) <= limit else f"{path[:limit // 2]}...{path[-limit // 2:]} ({len(path)} characters)"


def prepare_folder(path: str, what: str = "--out") -> str:
    """Create the output folder ``path`` and prove it writable, or raise :class:`OutputPathError` (one line).

    The path's length and each name's length are checked first, and the folders are made one by one:
    ``os.makedirs`` recurses once per missing folder, so a path of thousands of short names would end in a
    ``RecursionError`` instead of an answer.
    """
    import tempfile
    if not path or not path.strip():
        raise OutputPathError(f"{what}: an empty folder name")
    shown = shown_path(path)
    final = os.path.abspath(path)
    encoded = final.encode("utf-8", "surrogateescape")
    try:
        path_max = int(os.pathconf("/", "PC_PATH_MAX"))
    except (OSError, ValueError):
        path_max = PATH_MAX_DEFAULT
    if len(encoded) >= path_max:
        raise OutputPathError(f"{what} {shown}: the path is {len(encoded)} bytes, longer than the {path_max} the "
                              f"file system takes")
    name_max = _name_max("/")
    if any(len(part.encode("utf-8", "surrogateescape")) > name_max for part in final.split(os.sep)):
        raise OutputPathError(f"{what} {shown}: a folder name is longer than {name_max} bytes")
    if os.path.exists(final) and not os.path.isdir(final):
        raise OutputPathError(f"{what} {shown}: a file is in the way, not a folder")
    try:
        _make_folders(final)
    except OSError as exc:
        raise OutputPathError(f"{what} {shown}: cannot create the folder ({exc.strerror or exc})") from None
    except ValueError as exc:     # a NUL character in the name
        raise OutputPathError(f"{what} {shown}: cannot create the folder ({exc})") from None
    try:
        fd, probe = tempfile.mkstemp(prefix=".write-test-", dir=final)
        os.close(fd)
        os.unlink(probe)
    except OSError as exc:
        raise OutputPathError(f"{what} {shown}: cannot write there ({exc.strerror or exc})") from None
    return final


def _make_folders(final: str) -> None:
    """``os.makedirs(final, exist_ok=True)`` without recursion."""
    missing = []
    head = final
    while not os.path.isdir(head):
        missing.append(head)
        parent = os.path.dirname(head)
        if parent == head:
            break
        head = parent
    for folder in reversed(missing):
        try:
            os.mkdir(folder)
        except FileExistsError:
            if not os.path.isdir(folder):
                raise


def check_outputs(items: list[tuple[str, str | None]], recordings: tuple[str, ...] = ()) -> None:
    """Check every (option, path) pair that is given and that no two options name the same file."""
    seen: dict[str, str] = {}
    for what, path in items:
        if path is None:
            continue
        final = check_output(path, what, recording=what in recordings)
        key = os.path.realpath(final)
        if key in seen and not is_special(final):
            raise OutputPathError(f"{seen[key]} and {what} name the same file {path}: each output needs its own")
        seen[key] = what


def fault_message(path: str, exc: BaseException) -> str:
    reason = getattr(exc, "strerror", None) or str(exc)
    return f"cannot write {path}: {reason}"


def is_write_fault(exc: BaseException) -> bool:
    """An OSError of the storage (full, read-only, I/O), as opposed to a programming error."""
    return isinstance(exc, OSError) and exc.errno in WRITE_ERRNOS


@contextlib.contextmanager
def atomic_path(path: str) -> Iterator[str]:
    """Yield a temporary file name beside ``path``; on success it is renamed to ``path``, else removed.

    The writer writes (and may check) the temporary file; only a complete file ever carries the final name.  A
    target that exists and is not a regular file is yielded itself (written directly, never renamed over).
    Raises IsADirectoryError when a directory is in the way, :class:`OutputFault` when the storage fails.
    """
    final = os.path.abspath(path)
    if os.path.isdir(final):
        raise IsADirectoryError(f"{path} is a directory, not a file")
    if is_special(final):
        try:
            yield final
        except OSError as exc:
            if is_write_fault(exc):
                raise OutputFault(fault_message(path, exc)) from None
            raise
        return
    tmp = temporary_name(final)
    try:
        with _LOCK:
            fd = os.open(tmp, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o600)
            LIVE_TEMPORARIES.add(tmp)
        os.close(fd)
    except OSError as exc:
        if is_write_fault(exc):
            raise OutputFault(fault_message(path, exc)) from None
        raise
    try:
        yield tmp
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)  # the temporary file is created 0600; outputs are for others to read
        os.replace(tmp, final)
    except OSError as exc:
        if is_write_fault(exc):
            raise OutputFault(fault_message(path, exc)) from None
        raise
    finally:
        remove_temporary(tmp)


def remove_temporary(tmp: str) -> None:
    with _LOCK:
        LIVE_TEMPORARIES.discard(tmp)
    with contextlib.suppress(OSError):
        os.unlink(tmp)


def remove_live_temporaries() -> None:
    """Remove every temporary file of this process and of its workers (after a signal, before a hard exit)."""
    for tmp in list(LIVE_TEMPORARIES) + FAULTED_TEMPORARIES:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
    LIVE_TEMPORARIES.clear()
    mark = f".{run_id()}-"
    for folder in WATCHED_FOLDERS:
        with contextlib.suppress(OSError):
            for name in os.listdir(folder):
                if name.startswith(".") and name.endswith(_TMP_SUFFIX) and mark in name:
                    with contextlib.suppress(OSError):
                        os.unlink(os.path.join(folder, name))


def _free_bytes(path: str) -> int | None:
    try:
        st = os.statvfs(os.path.dirname(os.path.abspath(path)) or ".")
    except OSError:
        return None
    return st.f_bavail * st.f_frsize


def run_writer(write: Callable[..., None], tmp: str, *args, stall_s: float = 20.0, **kwargs) -> None:
    """Run ``write(tmp, *args, **kwargs)`` in a watched thread; a write that stalls ends with :class:`OutputFault`.

    Made for the Rerun file sink, whose flush waits forever when its file-writer thread died on a full disk (seen
    in 7 of 20 runs).  The file must grow: with no new byte for ``stall_s`` seconds, or none for a second while
    the file system has no free space left, the writer is given up (its thread is left behind, listed in
    :data:`STUCK_WRITERS`, so that the command exits without waiting for it).  A writer that raises with a full
    or failing disk raises :class:`OutputFault`; other exceptions propagate unchanged.
    """
    outcome: list[BaseException | None] = []
    where = os.path.dirname(os.path.abspath(tmp))
    # The Rust side of Rerun logs its own errors on stderr; the fault is reported here, in one line.
    os.environ.setdefault("RUST_LOG", "off")

    def target() -> None:
        try:
            write(tmp, *args, **kwargs)
            outcome.append(None)
        except BaseException as exc:  # handed to the waiting thread below
            outcome.append(exc)

    thread = threading.Thread(target=target, name="shimmy-writer", daemon=True)
    thread.start()
    size, since = -1, time.monotonic()
    while thread.is_alive():
        thread.join(0.1)
        try:
            now_size = os.stat(tmp).st_size
        except OSError:
            now_size = -1
        now = time.monotonic()
        if now_size != size:
            size, since = now_size, now
            continue
        free = _free_bytes(tmp)
        if now - since > stall_s or (free == 0 and now - since > 1.0):
            STUCK_WRITERS.append(thread)
            FAULTED_TEMPORARIES.append(tmp)
            reason = "no space left on device" if free == 0 else f"the writer stalled for {stall_s:g} s"
            raise OutputFault(f"cannot write in {where}: {reason}")
    exc = outcome[0] if outcome else None
    if exc is None:
        return
    FAULTED_TEMPORARIES.append(tmp)
    if is_write_fault(exc):
        raise OutputFault(f"cannot write in {where}: {exc.strerror or exc}") from None
    text = str(exc)
    if isinstance(exc, RuntimeError) and ("No space left" in text or "write" in text.lower()):
        reason = "no space left on device" if _free_bytes(tmp) == 0 else f"the writer failed ({text})"
        raise OutputFault(f"cannot write in {where}: {reason}") from None
    raise exc


def worker_signals() -> None:
    """Initializer of worker processes: the parent handles Ctrl-C; SIGTERM (sent by the parent when it is
    interrupted) removes the worker's temporary files and ends it quietly."""
    import signal

    def terminate(signum, frame) -> None:
        remove_live_temporaries()
        os._exit(143)

    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, terminate)


@contextlib.contextmanager
def interrupts_blocked() -> Iterator[None]:
    """Block SIGINT while worker processes are started: they inherit the mask through exec, so a Ctrl-C at the
    terminal (sent to the whole process group) cannot hit them before :func:`worker_signals` has run; the
    parent handles it and stops them."""
    import signal
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    old = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, old)


def write_atomically(path: str, text: str) -> None:
    """Write ``text`` to ``path`` through a temporary file: never a truncated file at ``path``."""
    with atomic_path(path) as tmp:
        with open(tmp, "w", encoding="utf-8") as fh:
            fh.write(text)
            fh.flush()
            os.fsync(fh.fileno())
