"""Two-parameter Hopf curves in the (p, q) plane by pseudo-arclength continuation of the Hopf defining system.

Unknowns u = (Re v, Im v, omega, p, q); equations (A(p, q) - i omega I) v = 0 and c^H v = 1, the reference c being
reset to the current eigenvector after each accepted point.  Curves are followed through their folds (the
arclength parametrisation does not care which way the curve faces).  Along each curve three test functions are
watched and their zeros located by Brent's method on the corrected curve (Govaerts 2000, ch. 4; Kuznetsov 2004,
ch. 8 and 10):

* ``hopf_fold``: the q-component of the tangent (a fold of the curve in q, where two Hopf points of a one-parameter
  sweep in p meet and an oscillation mode vanishes, like the paper's F1),
* ``hopf_hopf`` / ``zero_hopf``: the real part of another eigenvalue, when the count of unstable eigenvalues other
  than the tracked pair changes,
* ``generalized_hopf``: the first Lyapunov coefficient (the paper's DH points), or where f has a kink at the
  equilibrium the kink coefficient that takes its place (:func:`bifurcation.equilibria.hopf.kink_coefficient`).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import scipy.optimize

from bifurcation.continuation import Branch, ContinuationSettings, Stop, continue_curve, tangent
from bifurcation.equilibria.hopf import (
    HopfPoint,
    find_hopf_points,
    hopf_jacobian,
    kink_coefficient,
    hopf_residual,
    parameter_derivative,
    primary_derivative,
)
from bifurcation.equilibria.normal_form import first_lyapunov_coefficient
from bifurcation.messages import Message
from bifurcation.problem import Family, ProblemError, clip_window, describe
from bifurcation.special_points import BranchStatus, PointKind, PointStatus, SpecialPoint

OMEGA_SCALE = 30.0    # rad/s per unit of arclength
VECTOR_WEIGHT = 0.02
MIN_OMEGA = 1e-3      # rad/s; below this the curve is ending in a Bogdanov-Takens-like point


@dataclass(frozen=True)
class HopfCurve:
    """One Hopf curve: arrays along arclength (SI), how it ended at each end, and the points found on it."""

    ps: np.ndarray
    qs: np.ndarray
    omegas: np.ndarray
    # per point l1, or where f has a kink at the equilibrium the kink coefficient a that decides there instead
    criticality_coefficient: np.ndarray
    status: tuple[BranchStatus, BranchStatus]  # backward end, forward end
    messages: tuple[Message, Message]
    special_points: tuple[SpecialPoint, ...] = field(default=())

    @property
    def complete(self) -> bool:
        return all(s.is_complete for s in self.status)


@dataclass(frozen=True)
class HopfDiagram:
    param: str
    lo: float
    hi: float
    p_min: float
    p_max: float
    curves: tuple[HopfCurve, ...]
    special_points: tuple[SpecialPoint, ...]

    @property
    def complete(self) -> bool:
        return all(c.complete for c in self.curves)

    def points_of(self, kind: PointKind) -> tuple[SpecialPoint, ...]:
        return tuple(p for p in self.special_points if p.kind is kind)


class _HopfProblem:
    """The residual of the Hopf system in (v, omega, p, q) with a movable phase reference c."""

    def __init__(self, family: Family, q_scale: float, v: np.ndarray):
        self.family = family
        self.q_scale = q_scale
        self.n = family.n
        self.set_reference(v)

    def set_reference(self, v: np.ndarray) -> None:
        v = v / np.linalg.norm(v)
        self.cr, self.ci = v.real.copy(), v.imag.copy()

    def unpack(self, u):
        n = self.n
        return u[:n], u[n:2 * n], u[2 * n], u[2 * n + 1], u[2 * n + 2]

    def __call__(self, u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        vr, vi, w, p, q = self.unpack(u)
        try:
            A = self.family.linear_matrix(p, q)
            A_p = primary_derivative(self.family, p, q, A)
            A_q = parameter_derivative(self.family, p, q, self.q_scale, A)
        except ProblemError:
            nan = np.full(2 * self.n + 2, np.nan)
            return nan, np.full((2 * self.n + 2, 2 * self.n + 3), np.nan)
        return (hopf_residual(A, vr, vi, w, self.cr, self.ci),
                hopf_jacobian(A, A_p, vr, vi, w, self.cr, self.ci, A_q))

    def renormalize(self, u: np.ndarray) -> np.ndarray | None:
        """Reset the phase reference to the current eigenvector once it has drifted (None: no change)."""
        vr, vi, w, p, q = self.unpack(u)
        v = vr + 1j * vi
        if abs(np.linalg.norm(v) - 1.0) < 0.05:
            return None
        v = v / np.linalg.norm(v)
        self.set_reference(v)
        return np.concatenate([v.real, v.imag, [w, p, q]])

    def other_eigenvalues(self, u: np.ndarray) -> np.ndarray:
        """Eigenvalues other than the tracked pair +-i omega."""
        _, _, w, p, q = self.unpack(u)
        lam = np.linalg.eigvals(self.family.linear_matrix(p, q))
        for target in (1j * w, -1j * w):
            lam = np.delete(lam, np.argmin(np.abs(lam - target)))
        return lam

    def criticality_coefficient(self, u: np.ndarray) -> float:
        """l1 at the curve point u; where the family says f has a kink at the equilibrium (once but not twice
        differentiable: ``twice_differentiable`` False) the kink coefficient a, which decides the criticality
        there (:func:`bifurcation.equilibria.hopf.kink_coefficient`): a generalized Hopf point is where it
        changes sign."""
        vr, vi, w, p, q = self.unpack(u)
        A = self.family.linear_matrix(p, q)
        x0 = self.family.equilibrium(p, q)
        v = vr + 1j * vi if w > 0 else vr - 1j * vi
        smooth = getattr(self.family, "twice_differentiable", None)
        if smooth is not None and smooth(x0, p, q) is False:
            return kink_coefficient(self.family, x0, p, q, A, abs(w), v)[0]
        return first_lyapunov_coefficient(self.family.multilinear_forms(x0, p, q), A, abs(w), v)


def _weights(family: Family, q_range: float) -> np.ndarray:
    n = family.n
    return np.concatenate([np.full(2 * n, VECTOR_WEIGHT), [1.0 / OMEGA_SCALE, 1.0 / family.primary_scale, 1.0 / q_range]])


def _crossing_eigenvalue(before: np.ndarray, after: np.ndarray) -> complex | None:
    """An eigenvalue (upper half plane) whose real part changed sign between two nearby points."""
    up_b, up_a = before[before.imag >= -1e-12], after[after.imag >= -1e-12]
    for lam in up_b:
        match = up_a[np.argmin(np.abs(up_a - lam))]
        if np.sign(lam.real) != np.sign(match.real):
            return complex(0.5 * (lam + match))
    return None


def _nearest_axis_frequency(problem: _HopfProblem, u: np.ndarray) -> float:
    ev = problem.other_eigenvalues(u)
    return float(abs(ev[np.argmin(np.abs(ev.real))].imag))


def _follow(problem: _HopfProblem, start: np.ndarray, direction: np.ndarray, lo: float, hi: float, p_min: float,
            p_max: float, settings: ContinuationSettings) -> tuple[Branch, list[SpecialPoint], list]:
    """Continue from ``start`` along ``direction``; returns the branch, its special points and per-point l1."""
    n = problem.n
    iq, ip, iw = 2 * n + 2, 2 * n + 1, 2 * n
    w = _weights(problem.family, hi - lo)
    found: list[SpecialPoint] = []
    l1s = [problem.criticality_coefficient(start)]
    others = [problem.other_eigenvalues(start)]
    arclength = [0.0]

    def locate(branch: Branch, k: int, s_hi: float, fun, kind: PointKind, extra=None) -> None:
        s0 = arclength[k]
        try:
            s = scipy.optimize.brentq(lambda s: fun(*branch.point_at(k, s)), 0.0, s_hi, xtol=1e-13, rtol=1e-12)
            u, _ = branch.point_at(k, s)
            status = PointStatus.LOCATED
        except (RuntimeError, ValueError):
            s, u, status = 0.5 * s_hi, branch.points[k], PointStatus.NOT_CONVERGED
        data = {"omega": float(abs(u[iw]))}
        if extra is not None:
            data.update(extra(u))
        found.append(SpecialPoint(kind=kind, p=float(u[ip]), q=float(u[iq]),
                                  bracket=(s0, s0 + s_hi), status=status, data=data))

    def accept(branch: Branch) -> Stop | None:
        k = len(branch.points) - 2
        u_new = branch.points[-1]
        step = branch.steps[-1]
        verdict = None
        # Window boundary: cut the step at the crossing and stop there.
        for idx, bound, side in ((ip, p_min, -1), (ip, p_max, 1), (iq, lo, -1), (iq, hi, 1)):
            if side * (u_new[idx] - bound) <= 0.0:
                continue
            if side * (branch.points[k][idx] - bound) >= 0.0:
                # Started on the boundary and moved out: nothing of this step is inside the window.
                branch.points.pop(), branch.tangents.pop(), branch.steps.pop()
                u_end = branch.points[-1]
                return Stop(BranchStatus.COMPLETE,
                            Message.of("ends on the window boundary at ", describe(problem.family, u_end[ip], u_end[iq])))
            else:
                s = scipy.optimize.brentq(lambda s: branch.point_at(k, s)[0][idx] - bound, 0.0, step,
                                          xtol=1e-13)
                u_new, t_new = branch.point_at(k, s)
                u_new[idx] = bound  # exact, not 1e-13 outside
                branch.points[-1], branch.tangents[-1], branch.steps[-1] = u_new, t_new, s
                step = s
                verdict = Stop(BranchStatus.COMPLETE,
                               Message.of("left the window at ", describe(problem.family, u_new[ip], u_new[iq])))
                break
        arclength.append(arclength[-1] + step)
        l1_new = problem.criticality_coefficient(u_new)
        other_new = problem.other_eigenvalues(u_new)
        if np.sign(branch.tangents[k][iq]) != np.sign(branch.tangents[-1][iq]):
            locate(branch, k, step, lambda u, t: t[iq], PointKind.HOPF_FOLD)
        if np.sign(l1s[-1]) != np.sign(l1_new):
            locate(branch, k, step, lambda u, t: problem.criticality_coefficient(u), PointKind.GENERALIZED_HOPF)
        if np.sum(others[-1].real > 0) != np.sum(other_new.real > 0):
            lam = _crossing_eigenvalue(others[-1], other_new)
            if lam is not None:
                def tau(u, t, target=lam):
                    ev = problem.other_eigenvalues(u)
                    return ev[np.argmin(np.abs(ev.imag - target.imag) + np.abs(ev.real))].real
                kind = PointKind.HOPF_HOPF if abs(lam.imag) > 1e-6 else PointKind.ZERO_HOPF
                locate(branch, k, step, tau, kind, lambda u: {"omega2": _nearest_axis_frequency(problem, u)})
        l1s.append(l1_new)
        others.append(other_new)
        if verdict is not None:
            return verdict
        if abs(u_new[iw]) < MIN_OMEGA:
            return Stop(BranchStatus.DEGENERATE, Message.of("frequency vanished at ", describe(problem.family, u_new[ip])))
        if len(branch.points) > 4:
            a, b = branch.points[-2], branch.points[-1]
            seg = (b - a)[[ip, iq, iw]] * w[[ip, iq, iw]]
            rel = (branch.points[0] - a)[[ip, iq, iw]] * w[[ip, iq, iw]]
            lam = np.clip(np.dot(rel, seg) / max(np.dot(seg, seg), 1e-300), 0.0, 1.0)
            if np.linalg.norm(rel - lam * seg) < 1e-3:
                return Stop(BranchStatus.CLOSED, Message.of("the curve returned to its start"))
        return None

    branch = continue_curve(problem, start, direction, w, settings, accept=accept,
                            renormalize=problem.renormalize)
    return branch, found, l1s


def _start_vector(point: HopfPoint) -> np.ndarray:
    v = point.eigenvector / np.linalg.norm(point.eigenvector)
    return np.concatenate([v.real, v.imag, [point.omega, point.p, point.q]])


def hopf_curve(family: Family, point: HopfPoint, lo: float, hi: float, p_min: float, p_max: float,
               settings: ContinuationSettings = ContinuationSettings(ds=0.02, ds_max=0.06)) -> HopfCurve:
    """The Hopf curve through ``point``, followed both ways until it leaves [p_min, p_max] x [lo, hi] or closes."""
    n = family.n
    scale = max(abs(family.nominal), hi - lo)
    halves = []
    for sign in (+1.0, -1.0):
        problem = _HopfProblem(family, scale, point.eigenvector)
        start = _start_vector(point)
        direction = sign * tangent(problem(start)[1], _weights(family, hi - lo), None)
        branch, found, l1s = _follow(problem, start, direction, lo, hi, p_min, p_max, settings)
        halves.append((branch, found, l1s))
        if branch.status is BranchStatus.CLOSED:
            break
    pts = [np.array(halves[0][0].points)]
    l1 = [np.array(halves[0][2])]
    statuses = [halves[0][0].status]
    messages = [halves[0][0].message]
    special = list(halves[0][1])
    if len(halves) == 2:
        pts.insert(0, np.array(halves[1][0].points)[::-1][:-1])
        l1.insert(0, np.array(halves[1][2])[::-1][:-1])
        statuses.insert(0, halves[1][0].status)
        messages.insert(0, halves[1][0].message)
        special.extend(halves[1][1])
    else:
        statuses.insert(0, BranchStatus.CLOSED)
        messages.insert(0, halves[0][0].message)
    U = np.vstack(pts)
    return HopfCurve(ps=U[:, 2 * n + 1], qs=U[:, 2 * n + 2], omegas=np.abs(U[:, 2 * n]),
                     criticality_coefficient=np.concatenate(l1), status=(statuses[0], statuses[1]),
                     messages=(messages[0], messages[1]), special_points=tuple(special))


def _on_curve(curve: HopfCurve, point: HopfPoint, p_scale: float, q_range: float, tol: float = 5e-3) -> bool:
    """Whether a Hopf point lies on an already computed curve (same place in (p, q), measured in the family's
    scale of p and the window's of q, and same frequency)."""
    P = np.column_stack([curve.ps / p_scale, curve.qs / q_range])
    x = np.array([point.p / p_scale, point.q / q_range])
    if len(P) < 2:  # a curve that stopped at its seed (a corner of the window)
        return bool(np.linalg.norm(P[0] - x) < tol and abs(curve.omegas[0] - point.omega) < 0.02 * point.omega)
    a, b = P[:-1], P[1:]
    seg = b - a
    lam = np.clip(np.einsum("ij,ij->i", x - a, seg) / np.maximum(np.einsum("ij,ij->i", seg, seg), 1e-300), 0, 1)
    dist = np.linalg.norm(a + lam[:, None] * seg - x, axis=1)
    k = int(np.argmin(dist))
    omega = curve.omegas[k] + lam[k] * (curve.omegas[k + 1] - curve.omegas[k])
    return bool(dist[k] < tol and abs(omega - point.omega) < 0.02 * point.omega)


def _dedupe(points: list[SpecialPoint], p_scale: float, q_range: float) -> tuple[SpecialPoint, ...]:
    """One entry per special point: a Hopf-Hopf point lies on two curves and is found on both."""
    kept: list[SpecialPoint] = []
    for p in sorted(points, key=lambda p: (p.kind.value, p.p)):
        if not any(p.kind is k.kind and abs(p.p - k.p) < 1e-4 * p_scale
                   and abs(p.q - k.q) < 1e-4 * q_range for k in kept):
            kept.append(p)
    return tuple(kept)


def hopf_diagram(family: Family, lo: float, hi: float, p_min: float, p_max: float, n_seeds: int = 9,
                 progress=None) -> HopfDiagram:
    """All Hopf curves met on ``n_seeds`` lines q = const in [lo, hi] (plus q = nominal), each followed in full.

    A closed Hopf curve lying strictly between two seed lines would be missed; the seed lines are spaced at
    (hi - lo) / (n_seeds - 1).  The window of the first parameter never reaches below the family's ``primary_min``.
    """
    if not lo < hi:
        raise ProblemError(f"range must have LO < HI, got {lo:g} >= {hi:g}")
    p_min, p_max = clip_window(family, p_min, p_max)
    for q in (lo, hi):
        family.validate(q)
    seeds = list(np.linspace(lo, hi, n_seeds))
    if lo < family.nominal < hi:
        seeds.append(family.nominal)
    curves: list[HopfCurve] = []
    for i, q in enumerate(seeds):
        for point in find_hopf_points(family, q, p_min, p_max):
            if any(_on_curve(c, point, family.primary_scale, hi - lo) for c in curves):
                continue
            curves.append(hopf_curve(family, point, lo, hi, p_min, p_max))
        if progress is not None:
            progress(i + 1, len(seeds))
    special = _dedupe([p for c in curves for p in c.special_points], family.primary_scale, hi - lo)
    return HopfDiagram(param=family.param, lo=lo, hi=hi, p_min=p_min, p_max=p_max, curves=tuple(curves),
                       special_points=special)
