"""Progress of a long job made of named steps (``shimmy verify``): a tqdm bar naming the running step on a
terminal, otherwise one line per finished step on stderr; never anything on stdout (``--json`` owns it).

Two ways to drive it:

* ``progress(message)``: a message names the step that starts now; ``"done: <step>"`` ends one of the top-level
  steps announced with :meth:`StepProgress.set_steps` (the bar counts those).  This is what
  :func:`comparisons.verify.run.run_verification` calls (its ``announce`` is :meth:`StepProgress.set_steps`).
* ``with progress.step(name): ...`` around a piece of work, or ``progress(done, total)`` for code that counts.
"""

from __future__ import annotations

import contextlib
import sys
import time
from typing import IO, Iterator


class StepProgress:
    def __init__(self, total: int = 0, job: str = "verify", stream: IO[str] | None = None, bar: bool | None = None):
        self.total = total
        self.job = job
        self.stream = stream if stream is not None else sys.stderr
        self.done = 0
        self.started = self._last = time.perf_counter()
        self.use_bar = self.stream.isatty() if bar is None else bar
        self._bar = None
        self._steps: tuple[str, ...] = ()
        self._step_start: dict[str, float] = {}
        self._current: tuple[str, float] | None = None     # the running sub-step and its start

    def __enter__(self) -> "StepProgress":
        if self.use_bar:
            from tqdm import tqdm
            self._bar = tqdm(total=self.total or None, desc=self.job, file=self.stream, leave=False,
                             bar_format="{desc} {n}/{total} {bar} {elapsed}")
        return self

    def __exit__(self, *exc) -> None:
        self._close_substep()
        if self._bar is not None:
            self._bar.close()
            self._bar = None

    # --- named top-level steps and messages ------------------------------------------------------------------

    def set_steps(self, names) -> None:
        """The top-level steps to come (the bar's total)."""
        self._steps = tuple(names)
        self.total = len(self._steps)
        if self._bar is not None:
            self._bar.total = self.total
            self._bar.refresh()

    def message(self, text: str) -> None:
        now = time.perf_counter()
        if text.startswith("done: "):
            self._close_substep()
            name = text[len("done: "):]
            self._finished(name, now - self._step_start.pop(name, self._last))
            return
        self._close_substep()
        if text in self._steps:
            # a step started again (verify's Plan: announced before the scans, its section after them) keeps its
            # first start, so that its time counts all of its work
            self._step_start.setdefault(text, now)
        else:
            self._current = (text, now)
        if self._bar is not None:
            self._bar.set_description_str(f"{self.job}: {text[:90]}")

    def _close_substep(self) -> None:
        if self._current is None:
            return
        text, start = self._current
        self._current = None
        if self._bar is None:
            self.stream.write(f"{self.job}:   {text} ({time.perf_counter() - start:.1f} s)\n")
            self.stream.flush()

    # --- context-managed and counted steps -------------------------------------------------------------------

    @contextlib.contextmanager
    def step(self, name: str) -> Iterator[None]:
        """Show ``name`` while it runs; count it and report it (with its seconds) when it ends."""
        start = time.perf_counter()
        if self._bar is not None:
            self._bar.set_description_str(f"{self.job}: {name}")
        failed = True
        try:
            yield
            failed = False
        finally:
            self._finished(name, time.perf_counter() - start, failed)

    def _finished(self, name: str, seconds: float, failed: bool = False) -> None:
        self.done += 1
        self._last = time.perf_counter()
        self.total = max(self.total, self.done)
        line = f"{self.job}: [{self.done}/{self.total}] {name}: {'failed' if failed else 'done'} in {seconds:.1f} s"
        if self._bar is not None:
            self._bar.total = self.total
            self._bar.update(1)
            self._bar.write(line, file=self.stream)
        else:
            self.stream.write(f"{line} ({time.perf_counter() - self.started:.0f} s so far)\n")
            self.stream.flush()

    def __call__(self, *args) -> None:
        """``progress(message)`` (see the module docstring) or ``progress(done, total)`` after each piece."""
        if len(args) == 1 and isinstance(args[0], str):
            self.message(args[0])
            return
        done, total = args[0], args[1]
        name = args[2] if len(args) > 2 else ""
        self.total = total
        while self.done < done:
            self._finished(name or f"step {self.done + 1}", time.perf_counter() - self._last)


def ticker(bar):
    """A ``progress(done, total)`` callback that moves a :func:`progress` bar."""
    def tick(done: int, total: int) -> None:
        bar.total = total
        bar.n = done
        bar.refresh()
    return tick


# Seconds between two plain progress lines: a job shorter than this prints none.
PLAIN_EVERY_S = 5.0


class PlainProgress:
    """The part of tqdm's interface the commands use (``n``, ``total``, ``update``, ``refresh``,
    ``set_postfix_str``), as plain lines on stderr for a log or a pipe: at most one every ``every`` seconds, so
    that a short job prints nothing, and a last one with the time taken if any was printed."""

    def __init__(self, total: int | None, description: str, stream: IO[str] | None = None,
                 every: float | None = None) -> None:
        self.total = total
        self.n = 0
        self.description = description
        self.stream = stream if stream is not None else sys.stderr
        self.every = PLAIN_EVERY_S if every is None else every
        self.postfix = ""
        self.started = self._said = time.perf_counter()
        self.lines = 0

    def __enter__(self) -> "PlainProgress":
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def _line(self, text: str) -> None:
        try:
            self.stream.write(text + "\n")
            self.stream.flush()
        except (OSError, ValueError):
            pass     # progress is never worth a failure
        self._said = time.perf_counter()
        self.lines += 1

    def _state(self) -> str:
        count = f" {self.n}/{self.total}" if self.total else ""
        postfix = f": {self.postfix}" if self.postfix else ""
        return f"{self.description}{count}{postfix} ({time.perf_counter() - self.started:.0f} s)"

    def refresh(self) -> None:
        if time.perf_counter() - self._said >= self.every:
            self._line(self._state())

    def update(self, k: int = 1) -> None:
        self.n += k
        self.refresh()

    def set_postfix_str(self, text: str, refresh: bool = True) -> None:
        self.postfix = text
        if refresh:
            self.refresh()

    def write(self, text: str, file=None) -> None:
        self._line(text)

    def close(self) -> None:
        if self.lines:
            self._line(f"{self.description}: done in {time.perf_counter() - self.started:.1f} s")
            self.lines = 0


def progress(total: int, description: str, quiet: bool):
    """Progress on stderr: a tqdm bar on a terminal, otherwise (a pipe, a log, or ``quiet`` under --json, whose
    stdout carries the JSON) plain lines at most every :data:`PLAIN_EVERY_S` seconds (:class:`PlainProgress`)."""
    if quiet or not sys.stderr.isatty():
        return PlainProgress(total, description)
    from tqdm import tqdm
    return tqdm(total=total, desc=description, leave=False, file=sys.stderr)
