"""Following a curve of cycle bifurcations by its bordered defining system (fold, period doubling or torus:
:mod:`~bifurcation.cycle_curves.fold`, :mod:`~bifurcation.cycle_curves.torus`): the
sparse bordered Jacobian, the continuation in (p, q) with its window cuts, the end where the amplitude vanishes,
and the codimension-two points of cycles detected along the way (Doedel, Govaerts & Kuznetsov, SIAM J. Numer.
Anal. 41, 2003; Kuznetsov 2004, section 10.3).
"""

from __future__ import annotations

import dataclasses

import numpy as np
import scipy.optimize
import scipy.sparse

from bifurcation.continuation import ContinuationSettings, Stop, continue_curve, correct, locate_on_step, tangent
from bifurcation.cycles import mesh_adaptation
from bifurcation.cycles.multipliers import (
    complex_outside,
    critical_multipliers,
    flip_critical_multipliers,
    fold_test,
    negative_outside,
    period_doubling_test,
    positive_outside,
    torus_test,
)
from bifurcation.cycles.problem import (
    CyclePoint,
    CycleProblem,
    CycleSettings,
)
from bifurcation.messages import Message
from bifurcation.problem import clip_window, describe
from bifurcation.special_points import BranchStatus, PointKind, PointStatus, SpecialPoint
from bifurcation.factorization import factorize

FD_RELATIVE = 1e-6          # central differences: step relative to the scale of the direction
FOLD_SETTINGS = ContinuationSettings(ds=0.02, ds_min=1e-6, ds_max=0.3, max_steps=300, newton_tol=1e-8,
                                     newton_max_iter=8, max_turn=0.3, grow_iter=4)


# a start point's residual above which it is corrected first (below continue_curve's 1e-6 for "not a solution")
START_RESIDUAL = 1e-8
START_ROUNDS = 4            # re-meshings of a start point that misses the error tolerance
# Newton iterations on a start interpolated onto a new mesh: where the right-hand side has a kink on the orbit Newton
# converges only linearly (up to 15 iterations measured on a multibody model's fold, docs/results.md)
START_ITERATIONS = 25
# Steps over a corner (bifurcation.continuation.step_over) where the family says its right-hand side is only
# piecewise smooth: 1 and 2 times the recent steps (no gap wider than the curve's own steps is stepped over).
CORNER_STEPS = 2
# Newton's steps at the residual's rounding floor where the family is only piecewise smooth, in newton_tol: a fold
# made by a kink at 0.002 deg stalled at weighted steps of 1e-7 to 5e-7 with the collocation residual at 3e-12
# (bifurcation.continuation.ContinuationSettings.floor_tol)
FLOOR_STEPS = 100.0
# Steps of a piecewise smooth family's curve: at its rounding floor Newton takes 5-8 iterations, so its steps stay
# short (the full geometry's fold curve over 0.5-3.5 bar, around its Hopf curve's turn: about 550 steps)
PIECEWISE_MAX_STEPS = 800
END_AMPLITUDE = 0.01        # scaled RMS below which the curve is taken to run into a generalized Hopf point
# ... or, on a curve that starts below it (a fold made by a kink of f sits a few thousandths of a degree from its Hopf
# point, and the fold curve runs on at such amplitudes), this fraction of the largest amplitude it has had: the curve
# must have shrunk towards zero, not merely be small.
END_FRACTION = 0.1
# A step of a piecewise smooth family's curve turns its orbit's node values by at most this angle's cosine: on the
# orbits of a kink's fold (thousandths of a degree, mirror symmetric, so that half a period on is the orbit negated)
# a longer step let the corrector slip half a period, which the curve took for a pass through zero amplitude (a
# multibody axle's fold from 1.5 bar, at 2.03-2.08 bar, where the kink coefficient is 4.5e-5 > 0)
SLIP_COS = 0.5
# Steps ahead within which an extrapolated zero of the amplitude is looked for (end_steps)
END_STEPS = 4.0
# ... and, after an end looked for and not found there, this fraction of the amplitude it was looked for at
RETRY_FRACTION = 0.5


class SparseBordered:
    """A sparse (K + 2) x (K + 3) Jacobian that :func:`bifurcation.continuation.correct` can border."""

    def __init__(self, J: scipy.sparse.spmatrix):
        self.J = J.tocsr()
        self.shape = J.shape
        self._factors = None        # (row, LU) of the last bordered matrix: chord iterations border with one row

    def solve_bordered(self, row: np.ndarray, rhs: np.ndarray) -> np.ndarray:
        if self._factors is None or not np.array_equal(self._factors[0], row):
            A = scipy.sparse.vstack([self.J, scipy.sparse.csr_matrix(row[None, :])]).tocsc()
            try:
                self._factors = (row.copy(), factorize(A))
            except RuntimeError:       # exactly singular
                return np.full(len(rhs), np.nan)
        return self._factors[1].solve(rhs)


# Codimension-two points of cycles along fold and period-doubling curves: (kind, the multipliers left when the
# critical ones are taken out, count among them that changes, test function on all multipliers).
CODIM2 = {PointKind.CYCLE_FOLD: (
    (PointKind.FOLD_FLIP, critical_multipliers, negative_outside,
     lambda mu: period_doubling_test(critical_multipliers(mu))),
    (PointKind.FOLD_NEIMARK_SACKER, critical_multipliers, complex_outside,
     lambda mu: torus_test(critical_multipliers(mu)))),
    PointKind.PERIOD_DOUBLING: (
    (PointKind.FOLD_FLIP, flip_critical_multipliers, positive_outside, fold_test),)}


def curve_q_scale(cycle: CyclePoint) -> float:
    """The second parameter's scale in a curve's norms: a tenth of its value at the start."""
    return 0.1 * max(abs(cycle.q), 1e-12)


def on_adapted_mesh(problem: CycleProblem, cycle: CyclePoint) -> CyclePoint:
    """``cycle`` interpolated onto the mesh its error estimate asks for (``problem``'s
    :meth:`~CycleProblem.needed_intervals` and scales, equidistributed): no longer a solution on that mesh, which
    :func:`start_point` then corrects."""
    N = max(problem.needed_intervals(cycle.orbit), cycle.orbit.intervals + 1)
    mesh = mesh_adaptation.adapted_mesh(cycle.orbit, problem.scales, intervals=N)
    return dataclasses.replace(cycle, orbit=mesh_adaptation.remesh(cycle.orbit, mesh))


def start_point(make_system, cycle: CyclePoint, continuation: ContinuationSettings):
    """(system, U0): the bordered system (``make_system(cycle)``) and its solution at ``cycle``'s second
    parameter, on a mesh that meets the tolerance where Newton gets there.

    A point located on a one-parameter branch lies on that branch's mesh, which the branch adapts only at its
    accepted points: a fold between two of them can miss the tolerance, and its location solves the defining
    system only to the branch's location accuracy.  The curve keeps its start's mesh, so the start is first put on
    a mesh its error estimate asks for (up to :data:`START_ROUNDS` times) and corrected there by Newton on the
    defining system with q fixed: the point of this kind on that mesh."""
    system, U0 = None, None
    continuation = dataclasses.replace(continuation,
                                       newton_max_iter=max(continuation.newton_max_iter, START_ITERATIONS))
    for _ in range(START_ROUNDS):
        candidate = make_system(cycle)
        U = candidate.start(cycle)
        # Two rounds of border updates make the borders the null vectors at the start point.
        candidate.renormalize(U), candidate.renormalize(U)
        iq = candidate.K + 2
        G = candidate(U)[0]
        if not np.max(np.abs(G)) <= START_RESIDUAL * (1.0 + np.max(np.abs(U))):
            fix_q = np.zeros_like(U)
            fix_q[iq] = 1.0
            w = candidate.weights()
            result = correct(candidate, U, fix_q / w[iq], w, continuation)
            if result is None:
                break
            U = result[0]
            candidate.renormalize(U), candidate.renormalize(U)
        system, U0 = candidate, U
        cycle = candidate.point(U)
        if cycle.meets_tolerance:
            break
        cycle = on_adapted_mesh(candidate.cp, cycle)
    if system is None:      # Newton failed at the point as located: the curve says so (continue_curve's start test)
        system = make_system(cycle)
        U0 = system.start(cycle)
        system.renormalize(U0), system.renormalize(U0)
    return system, U0


def end_steps(a_old: float, a_new: float, crossed: bool, piecewise: bool) -> list[float]:
    """Where a curve whose amplitude fell from a_old to a_new on its last step (through zero: ``crossed``) meets
    zero amplitude, in last steps from the point before it: amp^2 affine along the curve (a smooth Hopf normal
    form's r^3 term decides), then on a piecewise smooth family amp itself (where f has a kink at the equilibrium
    its |r| r term does: a fold made by the kink grows linearly from the point).  Only zeros within
    :data:`END_STEPS` steps: with none the curve goes on (a kink's fold shrank to a tenth over 0.04 bar, and its
    zero lay 0.0035 bar, six steps, beyond); through zero, each model's at once, at most END_STEPS on."""
    zeros = []
    for power in (2, 1)[:2 if piecewise else 1]:
        s_new = -a_new ** power if crossed else a_new ** power
        lam = a_old ** power / (a_old ** power - s_new) if a_old ** power != s_new else np.inf
        if crossed or 0.0 < lam <= END_STEPS:
            zeros.append(min(lam, END_STEPS))
    return zeros


def follow_bordered_curve(family, point: SpecialPoint, lo: float, hi: float, p_min: float, p_max: float,
                          settings: CycleSettings, continuation: ContinuationSettings, make_system,
                          accept_hook=None):
    """Follow the curve of ``point``'s kind through it with the bordered system ``make_system(cycle)`` (a
    :class:`FoldSystem` by default; its unknowns end with (p, q) at K + 1, K + 2 and possibly more after them),
    from its start on an adequate mesh (:func:`start_point`); ``accept_hook(cycle)`` after each accepted point."""
    from bifurcation.cycle_curves.ends import locate_end
    from bifurcation.cycle_curves.result import Corner, CycleCurve

    folds = point.kind is PointKind.CYCLE_FOLD
    ends_at_zero = point.kind in (PointKind.CYCLE_FOLD, PointKind.TORUS)
    p_min, p_max = clip_window(family, p_min, p_max)
    system, U0 = start_point(make_system, point.data["cycle"], continuation)
    ip, iq = system.K + 1, system.K + 2
    what = "Hopf-Hopf" if point.kind is PointKind.TORUS else "generalized Hopf"
    weights = system.weights()
    t0 = tangent(system(U0)[1], weights, None)
    start_state = (system.b.copy(), system.c.copy(), system.cp.reference)
    halves = []
    special: list[SpecialPoint] = []
    corners: list[Corner] = []
    # Where f is only piecewise smooth, Newton on the bordered system converges linearly (Jacobian rows across a
    # kink are differences) and chord iterations, at a third of an iteration's cost, lose little; on a smooth
    # family Newton converges quadratically and its last step leaves the point more accurate, so it keeps Newton.
    piecewise = getattr(family, "piecewise_smooth", False)
    if piecewise:
        continuation = dataclasses.replace(continuation, corner_steps=CORNER_STEPS,
                                           floor_tol=FLOOR_STEPS * continuation.newton_tol,
                                           max_steps=max(continuation.max_steps, PIECEWISE_MAX_STEPS))
    for sign in (1.0, -1.0):
        system.b, system.c = start_state[0].copy(), start_state[1].copy()
        system.cp.set_reference(start_state[2])
        points: list[CyclePoint] = [system.point(U0)]
        kappas: list[float] = [system.kappa(U0)]
        ends: list = []
        arclength = [0.0]
        largest = [system.cp.scaled_rms(U0[:iq])]
        retry = [np.inf]        # the amplitude at the last end looked for and not found (accept)

        def accept(branch, points=points, ends=ends, kappas=kappas, largest=largest, retry=retry) -> Stop | None:
            U, U_old = branch.points[-1], branch.points[-2]
            p, q = U[ip], U[iq]
            if len(branch.points) - 1 in branch.corners:
                corners.append(Corner(before=(U_old[ip], U_old[iq]), after=(p, q), bracket=(
                    sign * arclength[-1], sign * (arclength[-1] + branch.steps[-1]))))
            a_old, a_new = system.cp.scaled_rms(U_old[:iq]), system.cp.scaled_rms(U[:iq])
            # Through zero amplitude the collocation goes on with the same orbits shifted by half a period: the
            # curve would come back on itself.
            crossed = np.dot(U_old[:system.K], U[:system.K]) < 0.0
            largest[0] = max(largest[0], a_new)
            small = a_new < min(END_AMPLITUDE, END_FRACTION * largest[0], RETRY_FRACTION * retry[0])
            zeros = end_steps(a_old, a_new, crossed, piecewise) if ends_at_zero and (crossed or small) else []
            found = here = None
            if zeros:
                here = points[-1] if crossed else system.point(U)
                for lam in zeros:
                    guess = (U_old[ip] + lam * (p - U_old[ip]), U_old[iq] + lam * (q - U_old[iq]))
                    found = locate_end(family, point.kind, guess, here, abs(p - U_old[ip]), abs(q - U_old[iq]),
                                       p_min, p_max)
                    if found is not None:
                        break
                if found is None and not crossed:
                    # No end point where the amplitude seemed to vanish: it is only small (a kink's fold at 2.02
                    # bar, 0.0006 deg, a tenth of its largest, where the kink coefficient stays 4.5e-5 > 0), and
                    # the curve goes on, looked at again once its amplitude has halved.
                    retry[0] = a_new
                    zeros = []
            if zeros:
                if not crossed:
                    points.append(here)
                    kappas.append(system.kappa(U))
                ends.append(found)
                if found is not None:
                    # The last step and the rest of the way to the end point: tested like every other step,
                    # against the end point's own value of the test function.
                    k, s_zero = len(branch.points) - 2, lam * branch.steps[-1]
                    for kind, where, ok, bracket in system.end_events(branch, k, s_zero, found):
                        special.append(SpecialPoint(
                            kind=kind, p=where.p, q=where.q,
                            bracket=(sign * (arclength[-1] + bracket[0]), sign * (arclength[-1] + bracket[1])),
                            status=PointStatus.LOCATED if ok else PointStatus.NOT_CONVERGED,
                            data={"cycle": where, "period": where.period, "multipliers": where.multipliers,
                                  "end_segment": True}))
                if found is None:
                    # Said as the last step, not as the extrapolated zero: at zero amplitude the defining system is
                    # solved all along the Hopf curve, so Newton may have slid far along it on this step.
                    return Stop(BranchStatus.COMPLETE, Message.of(
                        "the amplitude vanishes on the last step, from ", describe(family, U_old[ip], U_old[iq]),
                        " to ", describe(family, p, q), f" (no {what} point located there)"))
                return Stop(BranchStatus.COMPLETE,
                            Message.of(f"ends at the {what} point located at ", describe(family, found.p, found.q)))
            for index, bound, side in ((iq, lo, -1), (iq, hi, 1), (ip, p_min, -1), (ip, p_max, 1)):
                if side * (U[index] - bound) <= 0.0:
                    continue
                # Cut the step where it leaves the window (Brent on the corrected curve) and stop there.
                k = len(branch.points) - 2
                try:
                    cut = scipy.optimize.brentq(lambda s: branch.point_at(k, s)[0][index] - bound, 0.0,
                                                branch.steps[-1], xtol=1e-12)
                    U, t = branch.point_at(k, cut)
                    branch.points[-1], branch.tangents[-1], branch.steps[-1] = U, t, cut
                except (RuntimeError, ValueError):
                    pass    # keep the point just outside
                points.append(system.point(U))
                kappas.append(system.kappa(U))
                return Stop(BranchStatus.COMPLETE, Message.of("left the window at ", describe(family, U[ip], U[iq])))
            p_new = here if here is not None else system.point(U)     # computed above where an end was looked for
            k = len(branch.points) - 2
            step = branch.steps[-1]
            # Cusp of cycles: the curve is smooth in (x, T, p, q) but its (p, q) projection turns back, its
            # (p, q) tangent passing through zero: the product with the previous one changes sign.
            pq = slice(ip, iq + 1)
            previous = branch.tangents[k][pq] * weights[pq]
            if folds and np.dot(branch.tangents[-1][pq] * weights[pq], previous) < 0.0:
                u, _, ok = locate_on_step(branch, k, step,
                                          lambda u, t: float(np.dot(t[pq] * weights[pq], previous)))
                where, status = system.point(u), PointStatus.LOCATED if ok else PointStatus.NOT_CONVERGED
                special.append(SpecialPoint(kind=PointKind.CUSP_OF_CYCLES, p=where.p, q=where.q,
                                            bracket=(sign * arclength[-1], sign * (arclength[-1] + step)),
                                            status=status, data={"cycle": where, "period": where.period}))
            for kind, critical, count, test in CODIM2.get(point.kind, ()):
                before, after = (critical(p.multipliers) for p in (points[-1], p_new))
                if count(before) == count(after):
                    continue

                u, _, ok = locate_on_step(branch, k, step,
                                          lambda u, t, test=test: test(system.point(u).multipliers))
                where, status = system.point(u), PointStatus.LOCATED if ok else PointStatus.NOT_CONVERGED
                special.append(SpecialPoint(kind=kind, p=where.p, q=where.q,
                                            bracket=(sign * arclength[-1], sign * (arclength[-1] + step)),
                                            status=status, data={"cycle": where, "period": where.period,
                                                                 "multipliers": where.multipliers}))
            for kind, where, ok in system.events(branch, k, step):
                special.append(SpecialPoint(kind=kind, p=where.p, q=where.q,
                                            bracket=(sign * arclength[-1], sign * (arclength[-1] + step)),
                                            status=PointStatus.LOCATED if ok else PointStatus.NOT_CONVERGED,
                                            data={"cycle": where, "period": where.period,
                                                  "multipliers": where.multipliers}))
            arclength.append(arclength[-1] + step)
            points.append(p_new)
            kappas.append(system.kappa(U))
            if accept_hook is not None:
                accept_hook(p_new)
            return None

        K = system.K

        def orbit_change(u_old, u_new) -> float:
            """A step's turn of the orbit's node values, 1 - cos of their angle, against 1 - SLIP_COS: a slip of
            half a period turns a mirror-symmetric orbit by 180 degrees, a step along the curve by little, whatever
            the orbit's size (a bound on the change itself was Newton's floor on the smallest orbits)."""
            a, b = u_old[:K], u_new[:K]
            cos = float(np.dot(a, b) / max(np.linalg.norm(a) * np.linalg.norm(b), 1e-300))
            return (1.0 - cos) / (1.0 - SLIP_COS)

        branch = continue_curve(system, U0, sign * t0, weights, continuation, accept=accept,
                                renormalize=system.renormalize, value=system.value if piecewise else None,
                                step_bound=orbit_change if piecewise else None)
        halves.append((points, branch.status, branch.message, ends[0] if ends else None, kappas))
    (fwd, s_fwd, m_fwd, e_fwd, k_fwd), (bwd, s_bwd, m_bwd, e_bwd, k_bwd) = halves
    pts = list(reversed(bwd[1:])) + fwd
    return CycleCurve(kind=point.kind, param=family.param,
                      ps=np.array([p.p for p in pts]), qs=np.array([p.q for p in pts]),
                      amplitudes=np.array([p.amplitude for p in pts]), periods=np.array([p.period for p in pts]),
                      status=(s_bwd, s_fwd), messages=(m_bwd, m_fwd),
                      ends=tuple(None if e is None else (e.p, e.q) for e in (e_bwd, e_fwd)),
                      end_points=(e_bwd, e_fwd), special_points=tuple(special), corners=tuple(corners),
                      kappas=np.array(list(reversed(k_bwd[1:])) + k_fwd),
                      errors=np.array([p.error for p in pts]), tolerances=np.array([p.tolerance for p in pts]),
                      cycles=tuple(pts))
