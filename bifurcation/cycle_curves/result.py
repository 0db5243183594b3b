"""Two-parameter curves of cycle bifurcations in the (p, q) plane (figures 8 and 18): the common result type, the
dispatch to the defining systems and the location of the codimension-two points where the curves end.

Each kind of curve solves its standard defining system on the collocation discretisation (Doedel, Govaerts &
Kuznetsov, SIAM J. Numer. Anal. 41, 2003; Kuznetsov 2004, section 10.3; MatCont): cycle folds and period doublings
in :mod:`bifurcation.cycle_curves.fold`, torus points in :mod:`bifurcation.cycle_curves.torus`.  The curves run until
they leave the (p, q) window or their amplitude vanishes: a fold curve then ends at a generalized Hopf (Bautin)
point of straight running, a torus curve at a Hopf-Hopf point (Kuznetsov 2004, sections 8.3 and 8.6).  That end
point is not taken from the extrapolation to zero amplitude: the Hopf curve through the extrapolated point is
continued in a small window around it (:func:`bifurcation.equilibria.hopf_curves.hopf_curve`) and the codimension-two point
is located there by its own test function (l1 = 0 for a generalized Hopf point, a second eigenvalue pair crossing
the imaginary axis for a Hopf-Hopf point), to the Hopf continuation's accuracy; the extrapolation only says where
to look.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from bifurcation.messages import Message
from bifurcation.special_points import (
    BranchStatus,
    PointKind,
    SpecialPoint,
)

# A one-parameter point lies on a computed curve when, between two of its points, the curve's p is the point's
# within this fraction and its critical cycle's amplitudes within SAME_CURVE_AMPLITUDE of the point's largest
# (steps of the curves are a few per cent of p; two folds of one kind apart by less would be a cusp's pair)
SAME_CURVE_RTOL = 1e-3
SAME_CURVE_AMPLITUDE = 0.1
END_KIND = {PointKind.TORUS: PointKind.HOPF_HOPF, PointKind.CYCLE_FOLD: PointKind.GENERALIZED_HOPF}


@dataclass(frozen=True)
class Corner:
    """A gap in a curve, stepped over (:func:`bifurcation.continuation.step_over`): where the right-hand side has a
    kink on the critical cycle, the discretised curve jumps where a collocation node crosses it.  The last point
    before and the first after, (p, q) in SI, and the arclength bracket of the step."""

    before: tuple[float, float]
    after: tuple[float, float]
    bracket: tuple[float, float]


@dataclass(frozen=True)
class CycleCurve:
    """A curve of cycle folds, torus or period-doubling points in (p, q): arrays along the curve (SI) and how each end ended."""

    kind: PointKind
    param: str
    ps: np.ndarray
    qs: np.ndarray
    amplitudes: np.ndarray      # (k, n) max |x_i| of the critical cycle
    periods: np.ndarray
    status: tuple[BranchStatus, BranchStatus]
    messages: tuple[Message, Message]
    ends: tuple[tuple[float, float] | None, tuple[float, float] | None]   # (p, q) where the amplitude vanishes
    end_points: tuple[SpecialPoint | None, SpecialPoint | None] = (None, None)  # the located codim-2 points
    special_points: tuple[SpecialPoint, ...] = ()    # codimension-two points of cycles detected along the curve
    kappas: np.ndarray | None = None    # torus curves: cos theta of the critical pair per point (else NaN)
    errors: np.ndarray | None = None    # estimated collocation error per point, relative to the amplitudes
    tolerances: np.ndarray | None = None    # the tolerance each point was computed for
    corners: tuple[Corner, ...] = ()        # gaps stepped over, in the order met (backward half first)
    cycles: tuple = field(default=(), repr=False, compare=False)   # the critical cycle (CyclePoint) per point

    @property
    def meets_tolerance(self) -> np.ndarray:
        """Per point: False where the error estimate exceeds the tolerance.  The curves keep the mesh of their
        start point (no remeshing along a bordered system), so this marks, it does not enforce."""
        if self.errors is None:
            return np.ones(len(self.ps), dtype=bool)
        return ~(self.errors > self.tolerances)

    def points_of(self, kind: PointKind) -> tuple[SpecialPoint, ...]:
        return tuple(p for p in self.special_points if p.kind is kind)

    @property
    def neutral_saddle(self) -> np.ndarray:
        """Per point: True where a torus curve has gone on past a 1:1 or 1:2 resonance (|kappa| > 1): the
        critical multipliers are then a real pair mu, 1/mu, a neutral saddle cycle, not a torus bifurcation."""
        if self.kappas is None:
            return np.zeros(len(self.ps), dtype=bool)
        return np.abs(self.kappas) > 1.0

    @property
    def complete(self) -> bool:
        return all(s.is_complete for s in self.status)

    def passes(self, point: SpecialPoint, rtol: float = SAME_CURVE_RTOL) -> bool:
        """Whether this curve passes through ``point``, a one-parameter point of its kind: on one of its steps
        whose q brackets the point's, p interpolated in q is the point's within ``rtol`` (relative) and the
        critical cycle's amplitudes within SAME_CURVE_AMPLITUDE of the point's largest, so that the point's own
        curve need not be continued again."""
        if point.kind is not self.kind:
            return False
        amplitude = np.asarray(point.data["cycle"].amplitude) if "cycle" in point.data else None
        for i in range(len(self.ps) - 1):
            j = i + 1
            q0, q1 = self.qs[i], self.qs[j]
            if not min(q0, q1) <= point.q <= max(q0, q1):
                continue
            w = 0.0 if q1 == q0 else (point.q - q0) / (q1 - q0)
            if abs(self.ps[i] + w * (self.ps[j] - self.ps[i]) - point.p) > rtol * abs(point.p):
                continue
            if amplitude is None:
                return True
            a = self.amplitudes[i] + w * (self.amplitudes[j] - self.amplitudes[i])
            if np.max(np.abs(a - amplitude)) <= SAME_CURVE_AMPLITUDE * np.max(np.abs(amplitude)):
                return True
        return False




