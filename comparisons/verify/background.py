"""Work that ``shimmy verify`` starts early in a second process and collects later.

The full geometry's branches at the plan's bistable case on another axle cost minutes on one core; started after
the plan, they overlap the sections that come before their own on the machine's second core.  Each job gets a
spawned process of its own (not forked: it builds its own Exudyn systems), a daemon, so that an interrupted verify
leaves none behind.  A job's exception, or the death of its process, is raised again where its result is
collected, so that the section that needs it reports it.
"""

from __future__ import annotations

import multiprocessing
from typing import Callable


class BackgroundJobError(RuntimeError):
    """A background job's process ended without a result."""


def _run(connection, job: Callable, args: tuple) -> None:
    try:
        outcome = ("ok", job(*args))
    except BaseException as exc:  # sent to the parent, which raises it where the result is collected
        outcome = ("error", exc)
    try:
        connection.send(outcome)
    except Exception as exc:     # the result or the exception does not pickle
        connection.send(("error", BackgroundJobError(f"its result could not be sent back: {exc}")))
    connection.close()


class Background:
    """Named jobs, each in a process of its own: :meth:`submit` early, :meth:`result` when a section needs it."""

    def __init__(self) -> None:
        self._jobs: dict[str, tuple] = {}

    def submit(self, key: str, job: Callable, *args) -> None:
        """Start ``job(*args)`` (a module-level function of picklable arguments) under ``key``."""
        if key in self._jobs:
            raise ValueError(f"background job {key!r} was already started")
        context = multiprocessing.get_context("spawn")
        receive, send = context.Pipe(duplex=False)
        process = context.Process(target=_run, args=(send, job, args), daemon=True, name=f"shimmy-{key}")
        process.start()
        send.close()
        self._jobs[key] = (process, receive)

    def started(self, key: str) -> bool:
        return key in self._jobs

    def result(self, key: str):
        """The job's return value, waiting for it; its exception raised here if it failed."""
        process, receive = self._jobs.pop(key)
        try:
            status, value = receive.recv()
        except EOFError:
            process.join()
            raise BackgroundJobError(f"background job {key!r} ended without a result "
                                     f"(exit code {process.exitcode})") from None
        finally:
            receive.close()
        process.join()
        if status == "error":
            raise value
        return value

    def close(self) -> None:
        """Stop every job nobody collected."""
        for process, receive in self._jobs.values():
            process.terminate()
            process.join()
            receive.close()
        self._jobs.clear()

    def __enter__(self) -> "Background":
        return self

    def __exit__(self, *exc) -> None:
        self.close()
