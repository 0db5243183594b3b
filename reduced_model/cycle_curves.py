"""Two-parameter curves of cycle bifurcations in the (V, q) plane (figures 8 and 18): the common result type, the
dispatch to the defining systems and the location of the codimension-two points where the curves end.

Each kind of curve solves its standard defining system on the collocation discretisation (Doedel, Govaerts &
Kuznetsov, SIAM J. Numer. Anal. 41, 2003; Kuznetsov 2004, section 10.3; MatCont): cycle folds and period doublings
in :mod:`reduced_model.cycle_fold_system`, torus points in :mod:`reduced_model.torus_system`.  The curves run until
they leave the (V, q) window or their amplitude vanishes: a fold curve then ends at a generalized Hopf (Bautin)
point of straight running, a torus curve at a Hopf-Hopf point (Kuznetsov 2004, sections 8.3 and 8.6).  That end
point is not taken from the extrapolation to zero amplitude: the Hopf curve through the extrapolated point is
continued in a small window around it (:func:`reduced_model.hopf_curves.hopf_curve`) and the codimension-two point
is located there by its own test function (l1 = 0 for a generalized Hopf point, a second eigenvalue pair crossing
the imaginary axis for a Hopf-Hopf point), to the Hopf continuation's accuracy; the extrapolation only says where
to look.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .continuation import ContinuationSettings
from .cycles import CyclePoint, CycleSettings
from .family import SpeedFamily
from .hopf import MIN_SPEED, hopf_points
from .parameters import ParameterError
from .special_points import BranchStatus, ConvergenceError, PointKind, PointStatus, SpecialPoint

END_KIND = {PointKind.TORUS: PointKind.HOPF_HOPF, PointKind.CYCLE_FOLD: PointKind.GENERALIZED_HOPF}


@dataclass(frozen=True)
class CycleCurve:
    """A curve of cycle folds, torus or period-doubling points in (V, q): arrays along the curve (SI) and how each end ended."""

    kind: PointKind
    param: str
    speeds: np.ndarray
    values: np.ndarray
    amplitudes: np.ndarray      # (k, 8) max |x_i| of the critical cycle
    periods: np.ndarray
    status: tuple[BranchStatus, BranchStatus]
    messages: tuple[str, str]
    ends: tuple[tuple[float, float] | None, tuple[float, float] | None]   # (V, q) where the amplitude vanishes
    end_points: tuple[SpecialPoint | None, SpecialPoint | None] = (None, None)  # the located codim-2 points
    special_points: tuple[SpecialPoint, ...] = ()    # codimension-two points of cycles detected along the curve
    kappas: np.ndarray | None = None    # torus curves: cos theta of the critical pair per point (else NaN)
    errors: np.ndarray | None = None    # estimated collocation error per point, relative to the amplitudes
    tolerances: np.ndarray | None = None    # the tolerance each point was computed for

    @property
    def meets_tolerance(self) -> np.ndarray:
        """Per point: False where the error estimate exceeds the tolerance.  The curves keep the mesh of their
        start point (no remeshing along a bordered system), so this marks, it does not enforce."""
        if self.errors is None:
            return np.ones(len(self.speeds), dtype=bool)
        return ~(self.errors > self.tolerances)

    def points_of(self, kind: PointKind) -> tuple[SpecialPoint, ...]:
        return tuple(p for p in self.special_points if p.kind is kind)

    @property
    def neutral_saddle(self) -> np.ndarray:
        """Per point: True where a torus curve has gone on past a 1:1 or 1:2 resonance (|kappa| > 1): the
        critical multipliers are then a real pair mu, 1/mu, a neutral saddle cycle, not a torus bifurcation."""
        if self.kappas is None:
            return np.zeros(len(self.speeds), dtype=bool)
        return np.abs(self.kappas) > 1.0

    @property
    def complete(self) -> bool:
        return all(s.is_complete for s in self.status)


def cycle_bifurcation_curve(family: SpeedFamily, point: SpecialPoint, lo: float, hi: float, vmin: float,
                            vmax: float, settings: CycleSettings = CycleSettings(),
                            continuation: ContinuationSettings | None = None) -> CycleCurve:
    """The curve of cycle folds, torus or period-doubling points through ``point`` (from a speed branch of
    ``family`` at fixed q), followed both ways in the window [vmin, vmax] x [lo, hi] by its defining system."""
    from .cycle_fold_system import FOLD_SETTINGS, fold_curve, period_doubling_curve
    from .torus_system import torus_curve

    follow = {PointKind.CYCLE_FOLD: fold_curve, PointKind.PERIOD_DOUBLING: period_doubling_curve,
              PointKind.TORUS: torus_curve}.get(point.kind)
    if follow is None:
        raise ValueError(f"no two-parameter continuation for {point.kind.value}")
    return follow(family, point, lo, hi, max(vmin, MIN_SPEED), vmax, settings, continuation or FOLD_SETTINGS)


def locate_end(family: SpeedFamily, kind: PointKind, guess: tuple[float, float], last: CyclePoint, dV: float,
               dq: float, vmin: float, vmax: float) -> SpecialPoint | None:
    """The codimension-two point of straight running where a curve of cycle bifurcations of ``kind`` ends, near
    ``guess`` = (V, q): Hopf points at q = guess[1] within a few curve steps dV of guess[0] (the one with the
    cycle's frequency), the Hopf curve through it continued in a window of a few steps (dV, dq) around the
    guess, and the point of kind END_KIND[kind] located on it by its test function.  None if there is none."""
    from .hopf_curves import hopf_curve

    V0, q0 = guess
    half_V = max(4.0 * dV, 1e-3 * abs(V0))
    half_q = max(4.0 * dq, 1e-4 * abs(q0))
    v_lo, v_hi = max(V0 - half_V, vmin), min(V0 + half_V, vmax)
    try:
        candidates = hopf_points(family, q0, v_lo, v_hi, lyapunov=False)
    except (ParameterError, ConvergenceError):
        return None
    if not candidates:
        return None
    omega = 2.0 * np.pi / last.period
    start = min(candidates, key=lambda h: abs(h.omega - omega))
    try:
        hc = hopf_curve(family, start, q0 - half_q, q0 + half_q, v_lo, v_hi)
    except (ParameterError, ConvergenceError, np.linalg.LinAlgError):
        return None
    found = [p for p in hc.special_points if p.kind is END_KIND[kind] and p.status is PointStatus.LOCATED]
    if not found:
        return None
    return min(found, key=lambda p: ((p.speed - V0) / half_V) ** 2 + ((p.value - q0) / half_q) ** 2)
