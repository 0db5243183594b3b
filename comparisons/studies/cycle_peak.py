"""The largest limit cycle of a model over a speed window, from its own continued cycle branches.

Every branch of cycles born at a Hopf point of straight running in the window is continued in the speed
(:func:`bifurcation.cycles.branches.cycle_diagram`, on :class:`reduced_model.family.SpeedFamily` or
on the Exudyn model through :class:`mbs_shimmy.linearisation.MbsFamily`).  On each branch the computed cycle of
largest max|theta1| is refined by successive parabolic interpolation: the parabola through it and its two
neighbours (speed, max|theta1|) puts the maximum at its vertex, where the cycle is solved by Newton's method at that
fixed speed (:func:`bifurcation.cycles.branches.cycle_at`: an orbit of the model, with its own
Floquet multipliers); the largest three around it give the next parabola, until a vertex falls within
:data:`SPEED_TOL` of the largest cycle (at most :data:`MAX_NEWTON` solves; on the paper's axle 3-4, within 1e-11 of
Brent's maximum along the branch, :func:`bifurcation.cycles.branches.branch_peak`, which takes 8-9).
The computed cycle stands (``Refinement.COMPUTED``) where the largest is a branch end (the window's boundary or the
cycle next to a Hopf end), where the three cycles straddle a fold (their speeds are not monotone), or where Newton
fails.

The model's peak is the largest of its branches' peaks.  A branch that did not complete (its continuation failed:
``BranchStatus``) gives no peak, and then neither does the model: the status is ``INCOMPLETE`` and the amplitude
None, whatever the other branches found (a half branch is not a whole one).  Without a Hopf point in the window no
cycle is born there: ``NO_CYCLE`` with max|theta1| 0 (straight running; a cycle not connected to a Hopf point of
the window is not searched for).

The mode of a cycle is labelled by :class:`reduced_model.modes.ModeClassifier`'s thresholds, as the simulations
are: yaw below both its max|psi|/max|theta1| ratio and frequency splits, tramp above both, mixed otherwise.
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass, field

import numpy as np

from bifurcation.cycles.branches import cycle_at, cycle_diagram
from bifurcation.cycles.problem import CycleBranch, CycleDiagram, CyclePoint, CycleSettings
from bifurcation.messages import Message
from bifurcation.problem import Family
from bifurcation.special_points import BranchStatus, ConvergenceError
from reduced_model.modes import ModeClassifier

NAME = "theta1"
MAX_NEWTON = 6          # cycles solved at vertices per branch
SPEED_TOL = 1e-4        # m/s: a vertex this close to the best cycle ends the refinement


class PeakStatus(enum.Enum):
    FOUND = "found"              # every branch complete; the largest cycle over them
    NO_CYCLE = "no_cycle"        # no Hopf point in the window: no branch, max|theta1| 0
    INCOMPLETE = "incomplete"    # a branch did not complete: no peak


class Refinement(enum.Enum):
    PARABOLA = "parabola"        # Newton at the vertices of successive parabolas through the largest cycles
    COMPUTED = "computed"        # the largest computed cycle of the continuation itself


def cycle_mode(cycle: CyclePoint, classifier: ModeClassifier = ModeClassifier()) -> str:
    """"yaw", "tramp" or "mixed", by the classifier's ratio and frequency splits."""
    theta1, psi = cycle.max_abs("theta1"), cycle.max_abs("psi")
    return classifier.mode_name(psi / theta1 if theta1 > 0.0 else math.nan, cycle.frequency_hz)


@dataclass(frozen=True)
class BranchPeak:
    """One continued branch: where it was born and ended, how, and its largest cycle (None if incomplete)."""

    start: float                     # m/s, the Hopf point it was born at
    end: float | None                # m/s, the Hopf point it returned to
    status: BranchStatus
    message: Message                 # the toolkit's
    cycles: int                      # computed cycles
    cycle: CyclePoint | None = field(default=None, compare=False, repr=False)
    refinement: Refinement | None = None

    @property
    def complete(self) -> bool:
        return self.status.is_complete


@dataclass(frozen=True)
class CyclePeak:
    """The largest max|theta1| of a model's cycles over the window (module docstring), SI."""

    status: PeakStatus
    branches: tuple[BranchPeak, ...]
    best: BranchPeak | None = None   # the branch that carries the peak (FOUND only)

    @property
    def cycle(self) -> CyclePoint | None:
        return self.best.cycle if self.best is not None else None

    @property
    def theta1(self) -> float | None:
        """max|theta1| of the peak cycle, rad; 0 without a cycle; None when incomplete."""
        if self.status is PeakStatus.NO_CYCLE:
            return 0.0
        return self.cycle.max_abs(NAME) if self.cycle is not None else None

    @property
    def psi(self) -> float | None:
        return self.cycle.max_abs("psi") if self.cycle is not None else None

    @property
    def speed(self) -> float | None:
        return self.cycle.p if self.cycle is not None else None

    @property
    def frequency_hz(self) -> float | None:
        return self.cycle.frequency_hz if self.cycle is not None else None

    @property
    def mode(self) -> str | None:
        return cycle_mode(self.cycle) if self.cycle is not None else None

    @property
    def stable(self) -> bool | None:
        return self.cycle.stable if self.cycle is not None else None

    @property
    def refinement(self) -> Refinement | None:
        return self.best.refinement if self.best is not None else None


def _vertex(pts: list[tuple[float, float]]) -> float | None:
    """Speed of the vertex of the parabola through three (speed, amplitude) points, or None when they do not
    bracket a maximum (not ordered by speed around the middle one, or not concave)."""
    (p0, a0), (p1, a1), (p2, a2) = pts
    if not (p0 - p1) * (p2 - p1) < 0.0:
        return None
    d01, d12 = (a1 - a0) / (p1 - p0), (a2 - a1) / (p2 - p1)
    curvature = (d12 - d01) / (p2 - p0)
    if not curvature < 0.0:
        return None
    vertex = 0.5 * (p0 + p1) - d01 / (2.0 * curvature)
    return vertex if min(p0, p2) < vertex < max(p0, p2) else None


def refine_peak(family: Family, branch: CycleBranch,
                settings: CycleSettings = CycleSettings()) -> tuple[CyclePoint, Refinement]:
    """The branch's largest cycle by successive parabolic interpolation from the three largest computed ones, or
    the computed one (module docstring)."""
    points = branch.points
    values = [c.max_abs(NAME) for c in points]
    k = int(np.argmax(values))
    top = points[k]
    if k == 0 or k == len(points) - 1 or _vertex([(points[i].p, values[i]) for i in (k - 1, k, k + 1)]) is None:
        return top, Refinement.COMPUTED
    known = [points[k - 1], top, points[k + 1]]       # ordered by speed around the best, which is in the middle
    known.sort(key=lambda c: c.p)
    for _ in range(MAX_NEWTON):
        best = max(known, key=lambda c: c.max_abs(NAME))
        i = known.index(best)
        if i == 0 or i == len(known) - 1:
            return best, Refinement.PARABOLA          # the bracket's end is its largest: no vertex inside
        vertex = _vertex([(c.p, c.max_abs(NAME)) for c in known[i - 1:i + 2]])
        if vertex is None:
            return best, Refinement.COMPUTED
        if abs(vertex - best.p) <= SPEED_TOL:
            return best, Refinement.PARABOLA
        try:
            cycle = cycle_at(family, best, vertex, settings)
        except ConvergenceError:
            return best, Refinement.COMPUTED
        known = sorted(known[i - 1:i + 2] + [cycle], key=lambda c: c.p)
    return max(known, key=lambda c: c.max_abs(NAME)), Refinement.PARABOLA


def peak_of_branch(family: Family, branch: CycleBranch, settings: CycleSettings = CycleSettings()) -> BranchPeak:
    start = branch.start.p if branch.start is not None else math.nan
    end = branch.end.p if branch.end is not None else None
    if not branch.complete or not branch.points:
        return BranchPeak(start, end, branch.status, branch.message, len(branch.points))
    cycle, how = refine_peak(family, branch, settings)
    return BranchPeak(start, end, branch.status, branch.message, len(branch.points), cycle, how)


def peak_of(family: Family, diagram: CycleDiagram, settings: CycleSettings = CycleSettings()) -> CyclePeak:
    """The peak over the branches of a computed diagram."""
    branches = tuple(peak_of_branch(family, b, settings) for b in diagram.branches)
    if not branches:
        return CyclePeak(PeakStatus.NO_CYCLE, ())
    if not all(b.complete and b.cycle is not None for b in branches):
        return CyclePeak(PeakStatus.INCOMPLETE, branches)
    best = max(branches, key=lambda b: b.cycle.max_abs(NAME))
    return CyclePeak(PeakStatus.FOUND, branches, best)


def continued_peak(family: Family, q: float, p_min: float, p_max: float,
                   settings: CycleSettings = CycleSettings()) -> tuple[CyclePeak, CycleDiagram]:
    """Continue every branch born at a Hopf point in [p_min, p_max] (m/s) at q and take the largest cycle; the
    diagram too (its Hopf points serve the caller)."""
    diagram = cycle_diagram(family, q, p_min, p_max, settings)
    return peak_of(family, diagram, settings), diagram
