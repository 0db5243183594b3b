"""Every reported MBS orbit is a solution of the collocation equations with Exudyn's own right-hand side.

The MBS's cycle continuation evaluates the compiled twin (:mod:`mbs_shimmy.twin`), which equals Exudyn's right-hand
side to rounding (``tests/mbs/test_mbs_twin.py``).  What a report states rests on Exudyn: each orbit's collocation
residual is evaluated by Exudyn, one call per collocation point, and where it is above :data:`RESIDUAL_TOL` the orbit
is Newton-polished on Exudyn's residual with the twin's Jacobian (:meth:`MbsFamily.on_exudyn`, the toolkit's
``cycle_at`` at the orbit's own speed and mesh) and checked again.
"""

from __future__ import annotations

from dataclasses import dataclass

from bifurcation.cycles.branches import cycle_at
from bifurcation.cycles.collocation import collocation_residual
from bifurcation.cycles.problem import CyclePoint

# max |x' - T f(x)| / max |x'| over the collocation points: the continuation's Newton iterations leave about 3e-9
# (the 1.5 bar branch of the full geometry); 1e-7 is well above that and far below the collocation error itself
RESIDUAL_TOL = 1e-7


@dataclass(frozen=True)
class ExudynCheck:
    """An orbit checked on Exudyn: its residual there, whether it had to be polished, the orbit reported."""

    residual: float
    polished: bool
    point: CyclePoint

    @property
    def passed(self) -> bool:
        return self.residual <= RESIDUAL_TOL


def exudyn_residual(family, point: CyclePoint) -> float:
    """The orbit's relative collocation residual with Exudyn's right-hand side (``family.exudyn_rhs``)."""
    return collocation_residual(point.orbit, lambda X: family.exudyn_rhs(X, point.p, point.q))


def checked_on_exudyn(family, point: CyclePoint) -> ExudynCheck:
    """The orbit's residual on Exudyn, polished there first if it is above :data:`RESIDUAL_TOL` (a failed polish
    raises the toolkit's ``ConvergenceError``)."""
    residual = exudyn_residual(family, point)
    if residual <= RESIDUAL_TOL:
        return ExudynCheck(residual, False, point)
    polished = cycle_at(family.on_exudyn(), point, point.p, mesh=point.orbit.mesh)
    return ExudynCheck(exudyn_residual(family, polished), True, polished)


@dataclass(frozen=True)
class CurveCheck:
    """A two-parameter curve's critical cycles checked on Exudyn: each point's residual there.  Not polished: at a
    fold or torus point the cycle at fixed parameters is singular or nearly so, and the curve's own defining system
    is the twin's; a point above :data:`RESIDUAL_TOL` is reported as failing."""

    residuals: tuple[float, ...]

    @property
    def largest(self) -> float:
        return max(self.residuals, default=0.0)

    @property
    def failing(self) -> int:
        return sum(not r <= RESIDUAL_TOL for r in self.residuals)

    def text(self) -> str:
        return (f"{len(self.residuals) - self.failing} of {len(self.residuals)} critical cycles within "
                f"{RESIDUAL_TOL:g} on Exudyn's right-hand side (largest residual {self.largest:.2g})")


def curve_on_exudyn(family, curve) -> CurveCheck:
    """Each critical cycle of ``curve`` (a :class:`~bifurcation.cycle_curves.result.CycleCurve` of an MBS family)
    checked on Exudyn's own right-hand side."""
    return CurveCheck(tuple(exudyn_residual(family, c) for c in curve.cycles))
