"""Branches of limit cycles: switching at Hopf points, following with events and user points, diagrams.

Branch switching at a Hopf point uses the normal form for the first amplitude (Kuznetsov, Elements of Applied
Bifurcation Theory, 3rd ed., 2004, sections 3.5 and 10.3.1): with A q = i w q, |q| = 1, p^H q = 1 and
mu'(p) = Re p^H A_p q, the orbit near the Hopf point is x = 2 Re(z q e^(i w t)) with |z|^2 = -mu' (p - p_H) /
(l1 w), so a first amplitude |z| fixes the first value of the primary parameter; the guess is then corrected by
Newton with the projection on the critical eigenfunction held fixed (AUTO's branch switching, Doedel's notes).

Along a branch the cycle folds, torus and period-doubling points (test functions in :mod:`bifurcation.cycles.problem`)
are located by Brent's method along the corrected branch, as in :mod:`bifurcation.equilibria.hopf_curves`; so are the
orbits at requested parameter values (AUTO's user points).  A branch that shrinks onto the equilibrium ends at
the Hopf point solved from the equilibrium's defining system.
"""

from __future__ import annotations

import dataclasses
from typing import Callable

import numpy as np
import scipy.optimize

from bifurcation.continuation import Branch, Stop, continue_curve, correct, locate_on_step
from bifurcation.cycles import collocation as col
from bifurcation.cycles import mesh_adaptation
from bifurcation.cycles.end_segments import end_segment_points
from bifurcation.cycles.multipliers import (
    classify_multipliers,
    complex_outside,
    negative_outside,
    period_doubling_test,
    torus_test,
)
from bifurcation.cycles.problem import (
    PERIOD_LIMIT,
    CycleBranch,
    CycleDiagram,
    CyclePoint,
    CycleProblem,
    CycleSettings,
    state_scales,
)
from bifurcation.equilibria.hopf import HopfPoint, find_hopf_points, primary_derivative
from bifurcation.messages import Message, message_of
from bifurcation.problem import Family, ProblemError, clip_window, describe
from bifurcation.special_points import (
    BranchStatus,
    ConvergenceError,
    PointKind,
    PointStatus,
    SpecialPoint,
)

# --------------------------------------------------------------------------------------------------------
# Branch switching at a Hopf point
# --------------------------------------------------------------------------------------------------------

def hopf_predictor(family: Family, hopf: HopfPoint, amplitude: float,
                   scales: np.ndarray) -> tuple[float, float, np.ndarray]:
    """(p, |z|, q-eigenvector) of the normal-form cycle whose largest scaled state amplitude is ``amplitude``."""
    A = family.linear_matrix(hopf.p, hopf.q)
    A_p = primary_derivative(family, hopf.p, hopf.q, A)
    q = hopf.eigenvector / np.linalg.norm(hopf.eigenvector)
    _, _, vh = np.linalg.svd(A.T + 1j * hopf.omega * np.eye(A.shape[0]))
    adjoint = vh[-1].conj()                                  # Kuznetsov's p (p here is the parameter)
    adjoint = adjoint / np.conj(np.vdot(adjoint, q))         # p^H q = 1
    mu_prime = float(np.vdot(adjoint, A_p @ q).real)         # d Re(lambda) / dp
    z = amplitude / (2.0 * np.max(np.abs(q) / scales))
    l1 = hopf.first_lyapunov
    if not np.isfinite(l1) or mu_prime == 0.0:
        delta = 0.0
    else:
        delta = -l1 * hopf.omega * z * z / mu_prime
    # Far from the normal form's validity the guess of p is useless; Newton fixes p anyway.
    delta = float(np.clip(delta, -0.05 * family.primary_scale, 0.05 * family.primary_scale))
    return hopf.p + delta, z, q


def start_at_hopf(family: Family, hopf: HopfPoint, settings: CycleSettings = CycleSettings()
                  ) -> tuple[CycleProblem, np.ndarray, np.ndarray]:
    """Problem, first cycle u0 and the direction away from the Hopf point (``ConvergenceError`` on failure)."""
    scales = state_scales(family, hopf.omega)
    period = 2.0 * np.pi / hopf.omega
    p1, z, q = hopf_predictor(family, hopf, settings.start_amplitude, scales)
    mesh = col.uniform_mesh(settings.intervals)

    x0 = family.equilibrium(hopf.p, hopf.q)

    def harmonic(tau):
        return x0[None, :] + 2.0 * (z * q[None, :] * np.exp(2j * np.pi * tau)[:, None]).real

    guess = col.orbit_from_function(harmonic, period, mesh, settings.degree)
    problem = CycleProblem(family, family.primary, hopf.p, hopf.q, guess, scales, family.primary_scale,
                           settings)
    u_pred = problem.pack(guess, p1)
    w = problem.weights()
    direction = np.concatenate([guess.nodes.ravel(), [0.0, 0.0]])
    direction /= np.linalg.norm(direction * w)
    result = correct(problem, u_pred, direction, w, settings.continuation, blocks=problem.blocks_of_unknowns())
    if result is None:
        raise ConvergenceError(Message.of("branch switching at the Hopf point at ", describe(family, hopf.p),
                                          ": Newton did not converge on the first cycle"))
    u0 = result[0]
    problem.set_reference(problem.orbit_of(u0))
    u0 = problem.meet_tolerance(u0, np.concatenate([u0[:-2], [0.0, 0.0]]))
    u_hopf = np.concatenate([np.zeros(problem.size), [period, hopf.p]])
    return problem, u0, u0 - u_hopf


# --------------------------------------------------------------------------------------------------------
# Following a branch
# --------------------------------------------------------------------------------------------------------

def _special(kind: PointKind, problem: CycleProblem, u: np.ndarray, bracket, status: PointStatus) -> SpecialPoint:
    point = problem.point(u)
    return SpecialPoint(kind=kind, p=point.p, q=point.q, bracket=bracket, status=status,
                        data={"period": point.period, "amplitude": point.amplitude,
                              "multipliers": point.multipliers, "free": problem.free, "cycle": point})


@dataclasses.dataclass
class BranchFollowing:
    """What :func:`follow_branch` has found so far, owned by it and updated after each accepted step: the problem
    it follows stays free of continuation state.

    ``records``, ``arclength`` and ``amplitudes`` run in step with the accepted points; ``tangent`` is the last
    accepted tangent (carried onto a new mesh when the problem re-meshes), ``steps_since_adapt`` the accepted
    points since the mesh was last adapted; ``user`` holds (arclength, orbit) at
    the requested parameter values; ``end`` is the Hopf point the branch returned to, if any."""

    records: list[CyclePoint]
    arclength: list[float]
    amplitudes: list[float]
    user: list[tuple[float, CyclePoint]]
    special: list[SpecialPoint] = dataclasses.field(default_factory=list)
    tangent: np.ndarray | None = None
    steps_since_adapt: int = 0
    end: HopfPoint | None = None


def follow_branch(problem: CycleProblem, u0: np.ndarray, direction: np.ndarray, lo: float, hi: float,
                  hopf: tuple[HopfPoint, ...] = (), start: HopfPoint | None = None,
                  accept_hook: Callable[[CyclePoint], Stop | None] | None = None, at: tuple[float, ...] = (),
                  max_step: float | None = None) -> CycleBranch:
    """Pseudo-arclength continuation of cycles from u0 until the free parameter leaves [lo, hi], the branch
    returns to a Hopf point (its amplitude vanishes), the period blows up, or the continuation fails.

    ``at``: values of the free parameter where the orbits are located on the branch as events (AUTO's user
    points, by Brent's method on the corrected branch: the continuation's own orbits), every time the branch
    passes them; between a Hopf end and the nearest computed cycle they come from Newton at fixed parameter.
    ``max_step`` bounds the change of the free parameter per continuation step (denser output).
    ``accept_hook(cycle)`` after each accepted cycle; a :class:`~bifurcation.continuation.Stop` it returns ends the
    branch there with that status and message (a caller's time budget: ``BranchStatus.STOPPED``)."""
    # The number of unknowns changes with the mesh: the free parameter and the period are always the last two.
    ip, iT = -1, -2
    settings = problem.settings
    start_period = float(u0[iT])
    targets = tuple(float(v) for v in at)
    state = BranchFollowing(records=[problem.point(u0)], arclength=[0.0], amplitudes=[problem.scaled_rms(u0)],
                            user=[(0.0, problem.point(u0)) for v in targets if v == u0[ip]])

    def where(u) -> Message:
        p, q = problem.parameters(u[ip])
        return describe(problem.family, p, None if problem.free == problem.family.primary else q)

    def locate(branch: Branch, k: int, s_hi: float, fun, kind: PointKind) -> None:
        s0 = state.arclength[k]
        u, _, ok = locate_on_step(branch, k, s_hi, fun)
        state.special.append(_special(kind, problem, u, (s0, s0 + s_hi),
                                      PointStatus.LOCATED if ok else PointStatus.NOT_CONVERGED))

    def nontrivial(u):
        return classify_multipliers(problem.multipliers(u))[0]

    def accept(branch: Branch) -> Stop | None:
        k = len(branch.points) - 2
        u_new = branch.points[-1]
        step = branch.steps[-1]
        state.tangent = branch.tangents[-1]
        verdict = None
        for bound, side in ((lo, -1), (hi, 1)):
            if side * (u_new[ip] - bound) <= 0.0:
                continue
            if side * (branch.points[k][ip] - bound) >= 0.0:
                branch.points.pop(), branch.tangents.pop(), branch.steps.pop()
                return Stop(BranchStatus.COMPLETE, Message.of("ends on the window boundary at ", where(branch.points[-1])))
            try:
                s = scipy.optimize.brentq(lambda s: branch.point_at(k, s)[0][ip] - bound, 0.0, step, xtol=1e-12)
                u_cut, t_cut = branch.point_at(k, s)
            except (RuntimeError, ValueError):
                # The corrector failed on the way to the boundary: the accepted point just beyond it ends the
                # branch (a solution all the same), and the message says that the crossing was not located.
                verdict = Stop(BranchStatus.COMPLETE, Message.of("left the window (last cycle at ", where(u_new), ", just "
                                                                 "beyond it; the crossing itself was not located)"))
                break
            u_new = u_cut
            branch.points[-1], branch.tangents[-1], branch.steps[-1] = u_new, t_cut, s
            state.tangent = t_cut
            step = s
            verdict = Stop(BranchStatus.COMPLETE, Message.of("left the window at ", where(u_new)))
            break
        amp = problem.scaled_rms(u_new)
        # Through zero amplitude, i.e. through a Hopf point: the branch goes on as the same orbits shifted by
        # half a period (they satisfy the phase condition too), with a spurious fold at the Hopf point.
        X_old, X_new = branch.points[k][:problem.size], u_new[:problem.size]
        if np.dot(X_old, X_new) < 0.0:
            branch.points.pop(), branch.tangents.pop(), branch.steps.pop()
            return _hopf_end(branch.points, state.amplitudes, state.records[-1]) or Stop(
                BranchStatus.COMPLETE, Message.of("amplitude vanishes near ", where(branch.points[-1]), " (a Hopf point "
                                                 "the defining system of the equilibrium did not converge to)"))
        p_old = branch.points[k][ip]
        for target in targets:
            if (p_old - target) * (u_new[ip] - target) < 0.0 or u_new[ip] == target:
                try:
                    s = step if u_new[ip] == target else scipy.optimize.brentq(
                        lambda s: branch.point_at(k, s)[0][ip] - target, 0.0, step, xtol=1e-13, rtol=1e-12)
                    u_at = u_new if s == step else branch.point_at(k, s)[0]
                    state.user.append((state.arclength[-1] + s, problem.point(u_at)))
                except (RuntimeError, ValueError):
                    pass    # reported as missing by the caller (no orbit at that value on this branch)
        state.arclength.append(state.arclength[-1] + step)
        rec = problem.point(u_new)
        prev = state.records[-1]
        if np.sign(branch.tangents[k][ip]) != np.sign(branch.tangents[-1][ip]):
            locate(branch, k, step, lambda u, t: t[ip], PointKind.CYCLE_FOLD)
        mu_prev, mu_new = prev.nontrivial, rec.nontrivial
        if complex_outside(mu_prev) != complex_outside(mu_new):
            locate(branch, k, step, lambda u, t: torus_test(nontrivial(u)), PointKind.TORUS)
        if negative_outside(mu_prev) != negative_outside(mu_new):
            locate(branch, k, step, lambda u, t: period_doubling_test(nontrivial(u)), PointKind.PERIOD_DOUBLING)
        state.records.append(rec)
        state.amplitudes.append(amp)
        stopped = accept_hook(rec) if accept_hook is not None else None
        if verdict is not None:
            return verdict
        if stopped is not None:
            return stopped
        # Near a Hopf point amp^2 is affine in the parameter: when it extrapolates to zero within one more
        # step of the same size, the Hopf point of the equilibrium is solved for and the branch ends there.
        before = state.amplitudes[-2]
        if len(state.records) > 2 and amp < before and amp ** 2 <= before ** 2 - amp ** 2:
            ended = _hopf_end(branch.points, state.amplitudes, rec)
            if ended is not None:
                return ended
        if u_new[iT] > PERIOD_LIMIT * start_period:
            return Stop(BranchStatus.DEGENERATE, Message.of(f"the period grew to {u_new[iT]:.3g} s at ", where(u_new),
                                                           " (approach to a homoclinic orbit)"))
        return None

    def _hopf_end(points, amps, last: CyclePoint) -> Stop | None:
        """The branch shrinks onto the equilibrium: solve the Hopf defining system from the extrapolated zero of
        amp^2 and the orbit's first harmonic; None when it does not converge near there."""
        u1, u2 = points[-2], points[-1]
        a1, a2 = amps[-2] ** 2, amps[-1] ** 2
        p1, p2 = u1[ip], u2[ip]
        p_end = p2 - a2 * (p2 - p1) / (a2 - a1) if a2 != a1 else p2
        located = end_hopf_point(problem.family, last, p_end) if problem.free == problem.family.primary else None
        if located is None:
            return None
        # The located point must lie where the branch was heading: within the last step (and a bit) of p_end.
        if abs(located.p - p_end) > 2.0 * abs(p2 - p1) + 1e-9 * abs(p_end):
            return None
        match = [h for h in hopf if abs(h.p - located.p) <= 1e-6 * max(1.0, abs(h.p))
                 and abs(h.omega - located.omega) <= 1e-6 * h.omega]
        h = match[0] if match else located
        state.end = h
        return Stop(BranchStatus.COMPLETE, Message.of("returns to the Hopf point at ", describe(problem.family, h.p)))

    def renormalize(u):
        # A re-meshed point replaces the recorded one: the record must carry the mesh that met the tolerance.
        # So do the user points of the step just taken (re-solved at their values on the new mesh).
        state.steps_since_adapt += 1
        result = problem.renormalize(u, state.tangent, state.steps_since_adapt)
        if result is not None:
            state.steps_since_adapt = 0
        if result is not None and state.records and len(result[0]) != len(u):
            state.records[-1] = problem.point(result[0])
            for i in range(len(state.user)):
                s_i, cyc = state.user[i]
                if s_i > state.arclength[-2]:
                    try:
                        state.user[i] = (s_i, cycle_at(problem.family, cyc, cyc.p, settings, mesh=problem.mesh))
                    except ConvergenceError:
                        pass    # keeps its coarser orbit, which says so through its error estimate
        return result

    bound = None
    if max_step is not None:
        def bound(u_old, u_new):
            return abs(u_new[ip] - u_old[ip]) / max_step

    branch = continue_curve(problem, u0, direction, problem.weights, settings.continuation, accept=accept,
                            renormalize=renormalize, blocks=problem.blocks_of_unknowns, step_bound=bound,
                            value=problem.value if problem.family.costly_jacobian else None,
                            tangent_jacobian=problem.smoothed_jacobian if problem.one_sided else None)
    # Requested values between a Hopf end and the nearest computed cycle: Newton at the fixed value from that
    # cycle shrunk towards the Hopf point as the square root of the distance (amp^2 affine near a Hopf point).
    first, last = (state.records[0], state.records[-1]) if state.records else (None, None)
    for hopf_end, near in ((start, first), (state.end, last)):
        if hopf_end is None or near is None or problem.free != problem.family.primary:
            continue
        for target in targets:
            if (hopf_end.p - target) * (near.p - target) < 0.0 and target != near.p:
                try:
                    cyc = cycle_at(problem.family, toward_hopf(near, hopf_end, target), target, settings)
                except ConvergenceError:
                    continue
                state.user.append((-1.0 if near is first else state.arclength[-1] + 1.0, cyc))
    # The segments between the Hopf ends and the nearest computed cycles, tested like the others.
    if state.records and problem.free == problem.family.primary:
        if start is not None:
            state.special += end_segment_points(problem.family, state.records[0], start, settings, 0.0, -1.0)
        if state.end is not None:
            state.special += end_segment_points(problem.family, state.records[-1], state.end, settings,
                                                state.arclength[-1], 1.0)
    if problem.free == problem.family.primary and branch.status is not BranchStatus.STOPPED:
        # the fold's defining system lives with the two-parameter curves that follow it.  A branch its caller
        # stopped (a time budget) keeps its points as located, each cycle's error estimate saying whether it meets
        # the tolerance: on violent cycles of 640 mesh intervals these re-solutions take minutes each.
        from bifurcation.cycle_curves.fold import on_tolerance
        state.special = [on_tolerance(problem.family, s, settings) if s.status is PointStatus.LOCATED else s
                         for s in state.special]
    message = branch.message
    if not branch.status.is_complete:
        message = Message.of(f"{branch.status.value}: ", message, " (last cycle at ", where(branch.points[-1]), ")")
    return CycleBranch(free=problem.free, points=tuple(state.records), special_points=tuple(state.special),
                       status=branch.status, message=message, start=start, end=state.end,
                       user_points=tuple(c for _, c in sorted(state.user, key=lambda x: x[0])))


def toward_hopf(near: CyclePoint, hopf: HopfPoint, p: float) -> CyclePoint:
    """A predictor for the cycle at ``p`` between the computed cycle ``near`` and the Hopf point it runs
    into: the orbit scaled by sqrt((p_H - p) / (p_H - p_near)), the period interpolated to 2 pi / omega_H."""
    lam = (hopf.p - p) / (hopf.p - near.p)
    orbit = near.orbit
    period = 2.0 * np.pi / hopf.omega + lam * (near.period - 2.0 * np.pi / hopf.omega)
    scaled = col.Orbit(mesh=orbit.mesh, nodes=np.sqrt(max(lam, 0.0)) * orbit.nodes, period=period,
                       degree=orbit.degree)
    return dataclasses.replace(near, orbit=scaled, period=period)


def first_harmonic(orbit: col.Orbit) -> np.ndarray:
    """int_0^1 x(tau) exp(-2 pi i tau) dtau by Gauss quadrature on the mesh: the eigenvector direction times
    the amplitude near a Hopf point (x = 2 Re(z q exp(2 pi i tau)))."""
    sch = col.scheme(orbit.degree)
    tau = orbit.mesh[:-1, None] + orbit.widths[:, None] * sch.points[None, :]
    Xc = col.collocation_states(orbit.interval_values(), sch)
    wgt = orbit.widths[:, None] * sch.weights[None, :] * np.exp(-2j * np.pi * tau)
    return np.einsum("jk,jkn->n", wgt, Xc)


def end_hopf_point(family, last: CyclePoint, p_guess: float) -> HopfPoint | None:
    """The Hopf point of the equilibrium a shrinking branch runs into, by Newton on the Hopf defining system
    (:func:`bifurcation.equilibria.hopf.locate_hopf`) from the extrapolated p, the cycle's frequency and its first
    harmonic; None if Newton does not converge."""
    from bifurcation.equilibria.hopf import locate_hopf
    v = first_harmonic(last.orbit)
    try:
        return locate_hopf(family, last.q, p_guess, 2.0 * np.pi / last.period, v)
    except (ConvergenceError, np.linalg.LinAlgError, ProblemError):
        return None


def branch_from_hopf(family: Family, hopf: HopfPoint, p_min: float, p_max: float,
                     others: tuple[HopfPoint, ...] = (), settings: CycleSettings = CycleSettings(),
                     accept_hook=None, at: tuple[float, ...] = (), max_step: float | None = None) -> CycleBranch:
    """The branch of cycles born at ``hopf``, continued in the family's first parameter within [p_min, p_max]
    (never below its ``primary_min``)."""
    p_min, p_max = clip_window(family, p_min, p_max)
    try:
        problem, u0, direction = start_at_hopf(family, hopf, settings)
    except ConvergenceError as exc:
        return CycleBranch(free=family.primary, points=(), special_points=(), status=BranchStatus.NEWTON_FAILED,
                           message=Message.of("newton_failed: ", message_of(exc)), start=hopf)
    return follow_branch(problem, u0, direction, p_min, p_max, hopf=others, start=hopf, accept_hook=accept_hook,
                         at=at, max_step=max_step)


def branch_from_cycle(family: Family, point: CyclePoint, free: str, lo: float, hi: float,
                      sign: float = 1.0, settings: CycleSettings = CycleSettings()) -> CycleBranch:
    """Continue a computed cycle in ``free`` (the family's first or second parameter) within [lo, hi];
    ``sign`` chooses the initial direction of the free parameter."""
    omega = 2.0 * np.pi / point.period
    scales = state_scales(family, omega)
    primary = free == family.primary
    p_scale = family.primary_scale if primary else 0.1 * max(abs(point.q), 1e-12)
    problem = CycleProblem(family, free, point.p, point.q, point.orbit, scales, p_scale, settings)
    if primary:
        lo, hi = clip_window(family, lo, hi)
    p0 = point.p if primary else point.q
    u0 = problem.pack(point.orbit, p0)
    direction = np.zeros_like(u0)
    direction[-1] = sign
    return follow_branch(problem, u0, direction, lo, hi)


def cycle_diagram(family: Family, q: float, p_min: float, p_max: float,
                  settings: CycleSettings = CycleSettings(), progress=None, at: tuple[float, ...] = (),
                  max_step: float | None = None, accept_hook=None) -> CycleDiagram:
    """Every branch of cycles born at a Hopf point of the equilibrium with p in [p_min, p_max] at the second
    parameter q.

    A Hopf point that an earlier branch returned to is not started again.  ``at`` (values of p) and
    ``max_step`` (in p) as in :func:`follow_branch`; ``progress(done, total)`` after each Hopf point,
    ``accept_hook(cycle)`` after each accepted cycle of any branch (a long branch's progress).
    """
    family.validate(q)
    hopf = find_hopf_points(family, q, p_min, p_max)
    branches: list[CycleBranch] = []
    reached: list[HopfPoint] = []
    for i, h in enumerate(hopf):
        if not any(h is r for r in reached):
            b = branch_from_hopf(family, h, p_min, p_max, others=tuple(x for x in hopf if x is not h),
                                 settings=settings, at=at, max_step=max_step, accept_hook=accept_hook)
            branches.append(b)
            if b.end is not None:
                reached.append(b.end)
        if progress is not None:
            progress(i + 1, len(hopf))
    return CycleDiagram(q=q, p_min=p_min, p_max=p_max, hopf=hopf, branches=tuple(branches))


def cycle_at(family: Family, near: CyclePoint, p: float, settings: CycleSettings = CycleSettings(),
             intervals: int | None = None, mesh: np.ndarray | None = None, halvings: int = 3) -> CyclePoint:
    """The cycle at ``p`` (same q) by Newton's method from the nearby cycle ``near`` (T free, p fixed).

    With ``intervals`` the cycle is computed on a uniform mesh of that many intervals, with ``mesh`` on that mesh
    (``near`` is interpolated onto it), otherwise on ``near``'s mesh.  Where Newton's method does not reach p from
    ``near`` in one step, p is approached in up to 2**``halvings`` equal steps, each cycle the start of the next
    (the natural-parameter continuation of Keller's lectures, 1987, section 2.1, on the same equations).  Fails with
    :class:`ConvergenceError` at a fold (where the cycle is not a function of p) or when ``near`` is too far away.
    """
    omega = 2.0 * np.pi / near.period
    if mesh is None and intervals is not None:
        mesh = col.uniform_mesh(intervals)
    orbit = near.orbit if mesh is None else mesh_adaptation.remesh(near.orbit, mesh)
    problem = CycleProblem(family, family.primary, near.p, near.q, orbit, state_scales(family, omega),
                           family.primary_scale, settings)
    u = None
    for steps in (2 ** k for k in range(halvings + 1)):
        u = _newton_towards(problem, problem.pack(orbit, near.p), near.p, p, steps, settings)
        if u is not None:
            break
    if u is None:
        raise ConvergenceError(Message.of("no cycle found at ", describe(family, p), " from the one at ",
                                          describe(family, near.p)))
    if intervals is None and mesh is None:
        fix = np.zeros_like(u)
        fix[-1] = 1.0
        u = problem.meet_tolerance(u, fix)
    return problem.point(u)


def _newton_towards(problem: CycleProblem, u: np.ndarray, p0: float, p: float, steps: int,
                    settings: CycleSettings) -> np.ndarray | None:
    """The discretised cycle at p, reached from the one ``u`` at p0 in ``steps`` equal steps of p with p fixed in
    each Newton solve; None where a solve fails or collapses onto x = 0 (which with any period solves the
    discretised problem too)."""
    w = problem.weights()
    fix_p = np.zeros_like(u)
    fix_p[-1] = 1.0 / w[-1]                           # unit weighted norm: the hyperplane is the given p
    size = problem.scaled_rms(u)
    for k in range(1, steps + 1):
        guess = u.copy()
        guess[-1] = p0 + (p - p0) * k / steps       # the last unknown is p (CycleProblem.pack)
        result = correct(problem, guess, fix_p, w, settings.continuation, blocks=problem.blocks_of_unknowns())
        if result is None or problem.scaled_rms(result[0]) < 1e-3 * size:
            return None
        u = result[0]
    return u


def branch_peak(family: Family, branch: CycleBranch, name: str,
                settings: CycleSettings = CycleSettings()) -> CyclePoint:
    """The cycle where max |x_name| peaks along the branch, maximised over p by Brent's method between
    the neighbours of the largest computed point (a smooth maximum, not at a fold)."""
    values = [p.max_abs(name) for p in branch.points]
    k = int(np.argmax(values))
    if k == 0 or k == len(values) - 1:
        return branch.points[k]
    lo, hi = sorted((branch.points[k - 1].p, branch.points[k + 1].p))
    cache: dict[float, CyclePoint] = {}

    def negative(p):
        cache[p] = cycle_at(family, branch.points[k], p, settings)
        return -cache[p].max_abs(name)

    res = scipy.optimize.minimize_scalar(negative, bounds=(lo, hi), method="bounded",
                                         options={"xatol": 1e-7 * (1.0 + abs(hi))})
    best = cache.get(res.x) or cycle_at(family, branch.points[k], res.x, settings)
    return best if best.max_abs(name) >= values[k] else branch.points[k]
