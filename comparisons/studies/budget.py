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


def branch_place(cycle, state_names: tuple[str, ...]) -> str:
    """Where a branch was when its budget ran out: speed, size of its last cycle and that cycle's mesh."""
    return (f"{kmh(cycle.p):.1f} km/h, max|{state_names[0]}| {math.degrees(float(cycle.amplitude[0])):.2f} deg, "
            f"{cycle.orbit.intervals} mesh intervals")


class DeadlineWatch:
    """An accept hook for continuations (a cycle -> None) that raises :class:`OutOfTime` once ``time.monotonic()``
    is past ``deadline``; :attr:`stable` says whether any cycle it saw was stable (a computed stable cycle is a fact
    even when the computation stops)."""

    def __init__(self, deadline: float, state_names: tuple[str, ...]):
        self.deadline, self.state_names = deadline, state_names
        self.stable = False

    def __call__(self, cycle) -> None:
        self.stable = self.stable or bool(cycle.stable)
        if time.monotonic() > self.deadline:
            raise OutOfTime(f"a branch at {branch_place(cycle, self.state_names)}")


class BranchBudget:
    """An accept hook for :func:`bifurcation.cycles.branches.cycle_diagram` that gives each branch ``seconds`` of
    wall clock and then ends it (``BranchStatus.STOPPED``, the message saying where it was), keeping what it
    computed; pass :meth:`next_branch` as the diagram's ``progress`` so that each branch starts its own budget.
    A stopped branch is incomplete: its cycles are drawn and reported as computed, never as the whole branch."""

    def __init__(self, seconds: float, state_names: tuple[str, ...]):
        self.seconds, self.state_names = seconds, state_names
        self.start = time.monotonic()

    def next_branch(self, done: int = 0, total: int = 0) -> None:
        self.start = time.monotonic()

    def __call__(self, cycle):
        from bifurcation.continuation import Stop
        from bifurcation.messages import Message
        from bifurcation.special_points import BranchStatus
        if time.monotonic() - self.start <= self.seconds:
            return None
        return Stop(BranchStatus.STOPPED, Message.of(
            f"stopped after its time budget of {self.seconds:g} s, at {branch_place(cycle, self.state_names)}"))
