"""Where a curve of cycle bifurcations ends on straight running: the codimension-two point (generalized Hopf or
Hopf-Hopf) located on the Hopf curve through the extrapolated end, by its own test function.
"""

from __future__ import annotations

import numpy as np

from bifurcation.cycle_curves.result import END_KIND
from bifurcation.cycles.problem import CyclePoint
from bifurcation.equilibria.hopf import find_hopf_points
from bifurcation.problem import Family, ProblemError
from bifurcation.special_points import (
    ConvergenceError,
    PointKind,
    PointStatus,
    SpecialPoint,
)


def locate_end(family: Family, kind: PointKind, guess: tuple[float, float], last: CyclePoint, dp: float,
               dq: float, p_min: float, p_max: float) -> SpecialPoint | None:
    """The codimension-two point of straight running where a curve of cycle bifurcations of ``kind`` ends, near
    ``guess`` = (p, q): Hopf points at q = guess[1] within a few curve steps dp of guess[0] (the one with the
    cycle's frequency), the Hopf curve through it continued in a window of a few steps (dp, dq) around the
    guess, and the point of kind END_KIND[kind] located on it by its test function.  None if there is none."""
    from bifurcation.equilibria.hopf_curves import hopf_curve

    p0, q0 = guess
    half_p = max(4.0 * dp, 1e-3 * abs(p0))
    half_q = max(4.0 * dq, 1e-4 * abs(q0))
    p_lo, p_hi = max(p0 - half_p, p_min), min(p0 + half_p, p_max)
    try:
        candidates = find_hopf_points(family, q0, p_lo, p_hi, lyapunov=False)
    except (ProblemError, ConvergenceError):
        return None
    if not candidates:
        return None
    omega = 2.0 * np.pi / last.period
    start = min(candidates, key=lambda h: abs(h.omega - omega))
    try:
        hc = hopf_curve(family, start, q0 - half_q, q0 + half_q, p_lo, p_hi)
    except (ProblemError, ConvergenceError, np.linalg.LinAlgError):
        return None
    found = [p for p in hc.special_points if p.kind is END_KIND[kind] and p.status is PointStatus.LOCATED]
    if not found:
        return None
    return min(found, key=lambda p: ((p.p - p0) / half_p) ** 2 + ((p.q - q0) / half_q) ** 2)
