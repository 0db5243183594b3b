"""The ``shimmy`` command: dispatches to :mod:`comparisons.cli.commands`; every failure is one line on stderr.

Exit codes: :data:`EXIT_CODES` (the table in ``docs/cli.md`` is generated from it by ``tools/docs_tables.py``).
"""

from __future__ import annotations

import argparse
import contextlib
import importlib
import importlib.util
import os
import re
import signal
import sys
import threading
import time
import traceback

# Only the standard library, axles.text and .files here: the signal handlers are installed before the model packages load.
from axles.text import printable as one_line   # user input echoed in a message stays one line
from comparisons.files import (
    FAULTED_TEMPORARIES,
    LIVE_TEMPORARIES,
    STUCK_WRITERS,
    OutputFault,
    OutputPathError,
    check_outputs,
    remove_live_temporaries,
)

COMMANDS = ("verify", "hopf", "curves", "cycles", "modes", "margins", "simulate", "assumptions", "figures", "params", "bench", "sweep")

EXIT_FAILED = 1
EXIT_USAGE = 2
EXIT_INCOMPLETE = 3
EXIT_WRITE = 74
EXIT_INTERRUPTED = 130
EXIT_TERMINATED = 143
EXIT_UNAVAILABLE = 4          # the value of comparisons.cli.commands.figures.EXIT_UNAVAILABLE (tests/docs checks it)
# One list of the exit codes with their meanings, so that the documented table cannot drift from the code.
EXIT_CODES = {
    0: "done",
    EXIT_FAILED: "`verify` found a failed check (a FAIL row in the report)",
    EXIT_USAGE: "bad input: an option, a value outside its physical range (the line names the range), an output path "
                "that cannot be written (checked before the work)",
    EXIT_INCOMPLETE: "the computation did not complete: a continuation or simulation stopped early (what was computed "
                     "is printed, marked incomplete), no convergence, a non-finite number or an overflow (the line "
                     "names the function)",
    EXIT_UNAVAILABLE: "`figures` was asked for a figure it cannot make",
    EXIT_WRITE: "an output could not be written: disk full, read-only file system, stdout full or closed, a broken "
                "pipe (`shimmy: write error: ...`); no temporary file is left, and a fault in writing is never "
                "reported as a failed check",
    EXIT_INTERRUPTED: "interrupted (Ctrl-C): stops within a second with `shimmy: interrupted`; temporary files "
                      "removed, completed outputs kept (`sweep` first closes its Dask cluster, up to 10 s, and says "
                      "which batches it kept)",
    EXIT_TERMINATED: "terminated (SIGTERM): as 130, with `shimmy: terminated`",
}
GRACE_S = 0.5                 # after a signal: time given to unwind normally before the hard exit
# Commands that answer an interrupt themselves: sweep closes its Dask cluster and says which batches it kept.
GRACE_BY_COMMAND = {"sweep": 10.0}
# Output options checked before any work, by attribute name; recordings are read back, so no device for them.
# A command whose --out is a file (sweep) adds it as ``file_outputs`` in its parser's defaults.
OUTPUT_OPTIONS = (("plot", "--plot"), ("rerun", "--rerun"), ("series", "--series"), ("write", "--write"),
                  ("write_tir", "--write-tir"))
RECORDING_OPTIONS = ("--rerun",)


INVALID_CHOICE = re.compile(r"invalid choice: '([^']*)' \(choose from (.*)\)$")


def option_names(parser: argparse.ArgumentParser) -> list[str]:
    return [name for action in parser._actions for name in action.option_strings]


class _Parser(argparse.ArgumentParser):
    """One line per error, with the closest option, command or choice to a misspelt one."""

    commands: dict[str, argparse.ArgumentParser] = {}

    def parse_args(self, args=None, namespace=None):
        namespace, extras = self.parse_known_args(args, namespace)
        if extras:
            from axles.axle_file import did_you_mean
            # the command's own parser knows its options; argparse reports them on the top-level one
            parser = self.commands.get(getattr(namespace, "command", None), self)
            hints = [did_you_mean(a.split("=", 1)[0], option_names(parser)) for a in extras if a.startswith("-")]
            self.error(f"unrecognized arguments: {' '.join(extras)}{''.join(h for h in hints if h)}")
        return namespace

    def format_help(self) -> str:
        """What the command is for first, then its usage and options (argparse puts the usage first)."""
        text = super().format_help()
        usage, _, rest = text.partition("\n\n")
        if not self.description or not rest.startswith(self.description[:20]):
            return text
        description, _, options = rest.partition("\n\n")
        return f"{description}\n\n{usage}\n\n{options}"

    def error(self, message: str) -> None:  # one line, not usage + message
        found = INVALID_CHOICE.search(message)
        if found:
            from axles.axle_file import did_you_mean
            message += did_you_mean(found.group(1), re.findall(r"'([^']*)'", found.group(2)))
        _say(f"shimmy: error: {message}")
        raise SystemExit(2)


def described(add_parser):
    """``sub.add_parser`` that gives every command's ``--help`` a description: what the command is for (its
    one-line help in the command list, unless the command writes a longer one)."""
    def add(name: str, **kwargs):
        text = kwargs.get("help") or ""
        kwargs.setdefault("description", (text[:1].upper() + text[1:] + ".") if text else None)
        return add_parser(name, **kwargs)
    return add


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="shimmy", description="Truck wheel shimmy: reduced model, bifurcations, multibody model")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND", parser_class=_Parser)
    sub.add_parser = described(sub.add_parser)
    parser.commands = sub.choices
    for name in COMMANDS:
        # A command whose module is not written yet is simply not offered.
        if importlib.util.find_spec(f"comparisons.cli.commands.{name}") is not None:
            importlib.import_module(f"comparisons.cli.commands.{name}").add_parser(sub)
    return parser


class Interrupted(BaseException):
    """SIGTERM, raised in the main thread like KeyboardInterrupt is for SIGINT."""


def _say(line: str) -> None:
    """One line on stderr, whatever state stderr is in."""
    line = one_line(line)
    try:
        sys.stderr.write(line + "\n")
        sys.stderr.flush()
    except (OSError, ValueError, AttributeError):
        try:
            os.write(2, (line + "\n").encode("utf-8", "replace"))
        except OSError:
            pass


def _stop_children(wait: float = 0.1) -> None:
    """Terminate worker processes (figures): they remove their own temporary files on SIGTERM."""
    import multiprocessing
    children = multiprocessing.active_children()
    for child in children:
        child.terminate()
    deadline = time.monotonic() + wait
    for child in children:
        child.join(max(0.0, deadline - time.monotonic()))
        if child.is_alive():
            child.kill()


def hard_exit(code: int, line: str | None) -> None:
    """Leave now: stop workers, remove temporary files, say ``line``, exit without waiting for any thread."""
    try:
        _stop_children()
    except Exception:  # noqa: BLE001 - nothing may stop the exit
        pass
    remove_live_temporaries()
    if line:
        _say(line)
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except Exception:  # noqa: BLE001
            pass
    os._exit(code)


class _Signals:
    """SIGINT and SIGTERM: raise in the main thread, and if the run has not ended within GRACE_S (a C extension
    holding the thread, a library that swallows KeyboardInterrupt in a callback), exit from a watchdog thread."""

    def __init__(self) -> None:
        self.code: int | None = None
        self.grace = GRACE_S
        self.done = threading.Event()
        self.previous: dict[int, object] = {}
        self.loading = False        # inside :meth:`while_loading`
        self.pending = False        # a signal came while loading

    def install(self) -> None:
        if threading.current_thread() is not threading.main_thread():
            return
        for sig in (signal.SIGINT, signal.SIGTERM):
            self.previous[sig] = signal.signal(sig, self.handle)
        self.previous_hook = sys.unraisablehook
        sys.unraisablehook = self.unraisable

    def restore(self) -> None:
        self.done.set()
        for sig, handler in self.previous.items():
            signal.signal(sig, handler)
        if self.previous:
            sys.unraisablehook = self.previous_hook

    def unraisable(self, info) -> None:
        """An interrupt raised where Python cannot raise it (a weakref callback of the import system's module locks,
        a finaliser) is printed by Python as 'Exception ignored ...' with a traceback, and the run goes on: leave at
        once instead, as the watchdog would after the grace time."""
        if self.code is not None and isinstance(info.exc_value, (KeyboardInterrupt, Interrupted)):
            hard_exit(self.code, "shimmy: interrupted" if self.code == EXIT_INTERRUPTED else "shimmy: terminated")
        self.previous_hook(info)

    def handle(self, signum, frame) -> None:
        code = EXIT_INTERRUPTED if signum == signal.SIGINT else EXIT_TERMINATED
        line = "shimmy: interrupted" if code == EXIT_INTERRUPTED else "shimmy: terminated"
        if self.code is not None:   # second signal: leave at once
            hard_exit(self.code, line)
        self.code = code
        if self.grace <= GRACE_S:   # workers first: a pool waiting on them would hold the main thread
            try:
                _stop_children(wait=0.0)
            except Exception:  # noqa: BLE001 - the exit must go on
                pass

        def watchdog() -> None:
            if not self.done.wait(self.grace):
                hard_exit(code, line)
        threading.Thread(target=watchdog, name="shimmy-signal-watchdog", daemon=True).start()
        if self.loading:
            self.pending = True
            return
        self._raise()

    def _raise(self) -> None:
        raise KeyboardInterrupt if self.code == EXIT_INTERRUPTED else Interrupted()

    @contextlib.contextmanager
    def while_loading(self):
        """The model packages load: an exception raised inside a C extension's initialisation (Exudyn's, scipy's
        HiGHS wrapper) makes that import fail with an ImportError traceback instead of stopping cleanly.  A signal
        here is acted on when loading is over, or by the watchdog after the grace time, whichever comes first."""
        self.loading = True
        try:
            yield
        finally:
            self.loading = False
        if self.pending:
            self._raise()


def received_signal() -> int | None:
    """The exit code of the signal this run has received (EXIT_INTERRUPTED, EXIT_TERMINATED), None before one, or
    outside :func:`main`: a command that answers an interrupt itself asks it when an error that is not a
    KeyboardInterrupt ends its work (an interrupt inside a library's or the import system's bookkeeping)."""
    owner = getattr(signal.getsignal(signal.SIGINT), "__self__", None)
    return owner.code if isinstance(owner, _Signals) else None


def _where(exc: BaseException) -> str:
    """The innermost frame of this project in the traceback: 'module.function'."""
    place = "?"
    for frame in traceback.extract_tb(exc.__traceback__):
        path = frame.filename.replace(os.sep, "/")
        for package in ("reduced_model/", "mbs_shimmy/", "comparisons/"):
            if package in path:
                module = package + path.rsplit(package, 1)[1]
                place = f"{module[:-3].replace('/', '.')}.{frame.name}"
    return place


def check_output_options(args: argparse.Namespace) -> None:
    """Every output file option of the command, before the work (see :func:`comparisons.files.check_outputs`)."""
    from axles.limits import UsageError
    options = tuple(getattr(args, "file_outputs", ())) + OUTPUT_OPTIONS
    items = [(flag, getattr(args, attr)) for attr, flag in options if getattr(args, attr, None) is not None]
    try:
        check_outputs(items, RECORDING_OPTIONS)
    except OutputPathError as exc:
        raise UsageError(str(exc)) from None


def parse_command(argv: list[str] | None, parser: argparse.ArgumentParser | None = None) -> argparse.Namespace:
    """The parsed command line, completed with its typed values: ``tyre_pressures`` (the one typed pressure of the
    command, from here to the tyre formula) and ``braking`` (the one typed braking).  The only place a Namespace is
    written."""
    from comparisons.cli.options import braking_of, pressures_of
    args = (parser or build_parser()).parse_args(argv)
    args.tyre_pressures = pressures_of(args)
    args.braking = braking_of(args)
    return args


def _run(args: argparse.Namespace) -> int:
    check_output_options(args)
    code = int(args.run(args) or 0)
    if sys.stdout is None:
        raise OutputFault("stdout is closed")
    sys.stdout.flush()   # here, not at exit: a full or closed stdout must be reported like any other write
    return code


def _silence_stdout() -> None:
    """After a stdout fault: nothing more may be written there (the interpreter's final flush would fail again)."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, 1)
        os.close(devnull)
    except OSError:
        pass
    sys.stdout = open(os.devnull, "w")


def main(argv: list[str] | None = None) -> int:
    for stream in (sys.stdout, sys.stderr):   # file names with undecodable bytes are printed as they are
        if stream is not None and hasattr(stream, "reconfigure"):
            try:
                stream.reconfigure(errors="surrogateescape")
            except (ValueError, OSError):
                pass
    signals = _Signals()
    signals.install()
    try:        # from the handlers on, every statement is inside: an interrupt anywhere ends in one line
        os.environ["SHIMMY_RUN_ID"] = str(os.getpid())   # worker processes tag their temporary files with it
        # Rerun's Rust side logs its own errors on stderr (read once, when it loads); faults are reported in one line.
        os.environ.setdefault("RUST_LOG", "off")
        if sys.stdout is None:
            raise OutputFault("stdout is closed")
        import numpy as np

        from axles.axle import interface_text
        from axles.limits import UsageError
        from bifurcation.special_points import ConvergenceError
        from axles.parameters import ParameterError
        try:
            with signals.while_loading():
                parser = build_parser()
            args = parse_command(argv, parser)
            signals.grace = GRACE_BY_COMMAND.get(args.command, GRACE_S)
            args.argv = list(sys.argv[1:] if argv is None else argv)    # echoed in reports
            return _run(args)
        except (UsageError, ParameterError) as exc:
            _say(f"shimmy: error: {interface_text(exc)}")
            return EXIT_USAGE
        except ConvergenceError as exc:
            _say(f"shimmy: failed: {interface_text(exc)}")
            return EXIT_INCOMPLETE
        except (FloatingPointError, OverflowError, ZeroDivisionError, np.linalg.LinAlgError) as exc:
            _say(f"shimmy: failed: numerical {type(exc).__name__} in {_where(exc)}: {exc}")
            return EXIT_INCOMPLETE
        except OSError as exc:
            if _stdout_fault(exc):
                raise OutputFault(f"cannot write to stdout: {exc.strerror}") from None
            raise
    except OutputFault as exc:
        remove_live_temporaries()
        if "stdout" in exc.message:
            _silence_stdout()
        _say(f"shimmy: write error: {exc.message}")
        return EXIT_WRITE
    except BaseException as exc:
        # After a signal the signal decides: an interrupt raised inside the import system's bookkeeping comes out
        # as another error (a KeyError from CPython's _ModuleLock.acquire, seen once in 1000 runs of the tests).
        code = (EXIT_INTERRUPTED if isinstance(exc, KeyboardInterrupt) else
                EXIT_TERMINATED if isinstance(exc, Interrupted) else signals.code)
        if code is None:
            raise
        _stop_children()
        remove_live_temporaries()
        _say("shimmy: interrupted" if code == EXIT_INTERRUPTED else "shimmy: terminated")
        return code
    finally:
        signals.restore()


def _stdout_fault(exc: OSError) -> bool:
    """An error of writing stdout (the only writes that carry no file name: the files go through .files)."""
    import errno
    return exc.errno in (errno.ENOSPC, errno.EPIPE, errno.EBADF, errno.EIO, errno.ECONNRESET) and not exc.filename


def entry() -> None:
    """The console script: :func:`main`, then leave without waiting on a writer thread that never returned."""
    code = main()
    if STUCK_WRITERS or LIVE_TEMPORARIES or FAULTED_TEMPORARIES:
        time.sleep(0.2)   # a failed writer's thread may still create its file: remove it after that
        hard_exit(code, None)
    if code in (EXIT_INTERRUPTED, EXIT_TERMINATED):
        # A KeyboardInterrupt that hit a C extension's PyRun_String while it was imported marks the interpreter,
        # which would then end itself by SIGINT (status -2) however the interrupt was handled: leave directly.
        hard_exit(code, None)
    try:
        sys.stdout.flush()
    except (OSError, ValueError, AttributeError):
        _silence_stdout()
        _say("shimmy: write error: cannot write to stdout")
        code = EXIT_WRITE
    sys.exit(code)


if __name__ == "__main__":
    entry()
