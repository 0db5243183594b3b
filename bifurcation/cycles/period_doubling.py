"""Branch switching at a period-doubling point onto the branch of cycles of twice the period.

At a period-doubling (flip) point a non-trivial Floquet multiplier is -1 with eigenfunction phi(t),
phi(t + T) = -phi(t).  Traversed twice, the cycle is a 2T-periodic solution with a double multiplier +1, and the
branch of doubled cycles leaves it along phi extended over [0, 2T] (a pitchfork in the 2T-periodic problem).
Following AUTO (Doedel's notes, "branch switching at period doubling"; Kuznetsov 2004, section 10.3.1), the
doubled orbit x(t) + eps phi(t) on twice the mesh is corrected by Newton with its projection on phi held fixed,
and the new branch is followed by :func:`bifurcation.cycles.branches.follow_branch`.  The eigenfunction comes from the
same condensed collocation blocks as the multipliers (:func:`bifurcation.cycles.collocation.floquet_eigenfunction`).
"""

from __future__ import annotations

import numpy as np

from bifurcation.continuation import correct
from bifurcation.cycles import collocation as col
from bifurcation.cycles.branches import follow_branch
from bifurcation.cycles.problem import (
    CycleBranch,
    CyclePoint,
    CycleProblem,
    CycleSettings,
    state_scales,
)
from bifurcation.messages import Message
from bifurcation.problem import clip_window, describe
from bifurcation.special_points import ConvergenceError, PointKind, SpecialPoint


def doubled_orbit(orbit: col.Orbit, phi: np.ndarray) -> tuple[col.Orbit, np.ndarray]:
    """The orbit traversed twice (period 2T, the mesh repeated in each half of [0, 1]) and phi extended to
    [0, 2T] by phi(t + T) = -phi(t): (orbit, phi node values)."""
    mesh = np.concatenate([0.5 * orbit.mesh[:-1], 0.5 + 0.5 * orbit.mesh])
    nodes = np.concatenate([orbit.nodes, orbit.nodes])
    return (col.Orbit(mesh=mesh, nodes=nodes, period=2.0 * orbit.period, degree=orbit.degree),
            np.concatenate([phi, -phi]))


def branch_from_period_doubling(family, point: SpecialPoint, lo: float, hi: float,
                                settings: CycleSettings = CycleSettings()) -> CycleBranch:
    """The branch of period-doubled cycles born at the located period-doubling ``point`` of a branch in the
    primary parameter, followed in it within [lo, hi] in the direction in which it leaves the point."""
    if point.kind is not PointKind.PERIOD_DOUBLING:
        raise ValueError("branch switching needs a period-doubling point")
    cycle: CyclePoint = point.data["cycle"]
    omega = 2.0 * np.pi / cycle.period
    scales = state_scales(family, omega)
    base = CycleProblem(family, family.primary, cycle.p, cycle.q, cycle.orbit, scales, family.primary_scale,
                        settings)
    u_pd = base.pack(cycle.orbit, cycle.p)
    phi = col.floquet_eigenfunction(base.blocks(u_pd), -1.0)
    orbit2, phi2 = doubled_orbit(cycle.orbit, phi)
    problem = CycleProblem(family, family.primary, cycle.p, cycle.q, orbit2, scales, family.primary_scale,
                           settings)
    size = np.max(np.abs(phi2) / scales[None, :])
    eps = settings.start_amplitude / size
    u_pd2 = problem.pack(orbit2, cycle.p)
    direction = np.concatenate([phi2.ravel(), [0.0, 0.0]])
    w = problem.weights()
    direction /= np.linalg.norm(direction * w)
    result = correct(problem, u_pd2 + eps * np.linalg.norm(phi2.ravel() * w[:-2]) * direction, direction, w,
                     settings.continuation, blocks=problem.blocks_of_unknowns())
    if result is None:
        raise ConvergenceError(Message.of("branch switching at the period doubling at ", describe(family, cycle.p),
                                          ": Newton did not converge on the first doubled cycle"))
    u0 = result[0]
    if abs(np.dot((u0 - u_pd2) * w, direction * w)) < 0.5 * eps * np.linalg.norm(phi2.ravel() * w[:-2]):
        raise ConvergenceError("branch switching at the period doubling fell back onto the original cycle")
    problem.set_reference(problem.orbit_of(u0))
    return follow_branch(problem, u0, u0 - u_pd2, *clip_window(family, lo, hi))
