"""A wall-clock budget for a continuation: the branches' accept hook raises :class:`OutOfTime` once the deadline
has passed, naming where the branch was, so that a study can report the computation as stopped (over budget) with
that place instead of running on for minutes (violent cycles that lift a wheel need hundreds of cycles on 640 mesh
intervals).  What was stopped is never read as a result: the callers report it as incomplete."""

from __future__ import annotations

import math
import time

from axles.units import kmh


class OutOfTime(Exception):
    """The budget ran out; the message says where the branch was."""


def deadline_watch(deadline: float, state_names: tuple[str, ...]):
    """An accept hook (a cycle -> None) that raises :class:`OutOfTime` once ``time.monotonic()`` is past
    ``deadline``, and remembers whether any cycle it saw was stable (its ``stable`` attribute, a list of one bool:
    a computed stable cycle is a fact even when the computation stops)."""
    seen = [False]

    def watch(cycle) -> None:
        seen[0] = seen[0] or bool(cycle.stable)
        if time.monotonic() > deadline:
            raise OutOfTime(f"a branch at {kmh(cycle.p):.1f} km/h, max|{state_names[0]}| "
                            f"{math.degrees(float(cycle.amplitude[0])):.2f} deg, {cycle.orbit.intervals} mesh "
                            f"intervals")

    watch.stable = seen
    return watch
