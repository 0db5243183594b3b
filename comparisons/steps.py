"""Progress of a long job made of named steps (``shimmy verify``): a tqdm bar naming the running step on a
terminal, otherwise one line per finished step on stderr; never anything on stdout (``--json`` owns it).

    with StepProgress(total=12, job="verify") as progress:
        with progress.step("Hopf speeds at 1.5 bar"):
            ...

``progress(done, total)`` also works, for code that only counts.
"""

from __future__ import annotations

import contextlib
import sys
import time
from typing import IO, Iterator


class StepProgress:
    def __init__(self, total: int, job: str, stream: IO[str] | None = None, bar: bool | None = None):
        self.total = total
        self.job = job
        self.stream = stream if stream is not None else sys.stderr
        self.done = 0
        self.started = self._last = time.perf_counter()
        self.use_bar = self.stream.isatty() if bar is None else bar
        self._bar = None

    def __enter__(self) -> "StepProgress":
        if self.use_bar:
            from tqdm import tqdm
            self._bar = tqdm(total=self.total, desc=self.job, file=self.stream, leave=False,
                             bar_format="{desc}: {n}/{total} {bar} {elapsed}<{remaining}")
        return self

    def __exit__(self, *exc) -> None:
        if self._bar is not None:
            self._bar.close()
            self._bar = None

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
        outcome = "failed" if failed else "done"
        if self._bar is not None:
            self._bar.total = self.total
            self._bar.update(1)
            self._bar.write(f"{self.job}: [{self.done}/{self.total}] {name}: {outcome} in {seconds:.1f} s",
                            file=self.stream)
        else:
            self.stream.write(f"{self.job}: [{self.done}/{self.total}] {name}: {outcome} in {seconds:.1f} s "
                              f"({time.perf_counter() - self.started:.0f} s so far)\n")
            self.stream.flush()

    def __call__(self, done: int, total: int, name: str = "") -> None:
        """Counting interface: ``progress(done, total)`` after each finished piece of work."""
        self.total = total
        while self.done < done:
            self._finished(name or f"step {self.done + 1}", time.perf_counter() - self._last)
