"""The entry of two-parameter cycle work: the curve through a located cycle fold, torus or period-doubling point,
by the defining system of its kind.
"""

from __future__ import annotations

from bifurcation.continuation import ContinuationSettings
from bifurcation.cycle_curves.result import CycleCurve
from bifurcation.cycles.problem import CycleSettings
from bifurcation.problem import Family, clip_window
from bifurcation.special_points import (
    PointKind,
    SpecialPoint,
)


def cycle_bifurcation_curve(family: Family, point: SpecialPoint, lo: float, hi: float, p_min: float,
                            p_max: float, settings: CycleSettings = CycleSettings(),
                            continuation: ContinuationSettings | None = None, accept_hook=None) -> CycleCurve:
    """The curve of cycle folds, torus or period-doubling points through ``point`` (from a branch of
    ``family`` in its primary parameter at fixed q), followed both ways in the window [p_min, p_max] x [lo, hi] by
    its defining system; ``accept_hook(cycle)`` after each accepted point (a long curve's progress)."""
    from bifurcation.cycle_curves.bordered import FOLD_SETTINGS
    from bifurcation.cycle_curves.fold import fold_curve, period_doubling_curve
    from bifurcation.cycle_curves.torus import torus_curve

    follow = {PointKind.CYCLE_FOLD: fold_curve, PointKind.PERIOD_DOUBLING: period_doubling_curve,
              PointKind.TORUS: torus_curve}.get(point.kind)
    if follow is None:
        raise ValueError(f"no two-parameter continuation for {point.kind.value}")
    return follow(family, point, lo, hi, *clip_window(family, p_min, p_max), settings, continuation or FOLD_SETTINGS,
                  accept_hook=accept_hook)
