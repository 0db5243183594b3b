"""The end segments of a cycle branch: from its Hopf start to the first computed cycle and from the last computed
cycle to its Hopf end, tested and located like every other segment.

A branch stops a step short of the Hopf point it runs into (the amplitude extrapolated to zero within one more
step), and its first cycle lies a step away from the Hopf point it was born at, so between a computed cycle and
the Hopf point lies a segment that the step-by-step events of :func:`bifurcation.cycles.branches.
follow_branch` never see.  At the Hopf end the multipliers are known exactly: the zero-amplitude cycle of period
T = 2 pi / omega is the equilibrium, whose monodromy matrix is exp(A T), so its multipliers are exp(lambda_i T)
(Floquet theory of a constant-coefficient system; Kuznetsov, Elements of Applied Bifurcation Theory, 3rd ed.
2004, section 1.5), the critical pair's two being 1.

Along the segment the cycles are solved, not interpolated: the collocation system of the branch plus the
hyperplane <X_near, X>_W = c <X_near, X_near>_W, c in (0, 1], which fixes the orbit's projection on the computed
cycle X_near (c = 1) and goes to zero at the Hopf point (c = 0).  Near a Hopf point the orbit is the critical
eigenfunction times a small amplitude (Kuznetsov 2004, section 3.5), so c measures that amplitude and p - p_H is
of order c^2: c parametrises the segment even through a fold of cycles, where p does not.  The test
functions are those of the branch (a complex pair through the unit circle, a real multiplier through -1, the
primary parameter turning back), evaluated at sub-segment nodes c_k = sqrt(k / SUBDIVISIONS) and located by
Brent's method in c on the solved cycles, with the same status and the same collocation error estimate as a point
located between two computed cycles.
"""

from __future__ import annotations

import numpy as np
import scipy.optimize

from bifurcation.continuation import correct, tangent
from bifurcation.cycles.multipliers import (
    classify_multipliers,
    complex_outside,
    negative_outside,
    period_doubling_test,
    torus_test,
)
from bifurcation.cycles.problem import CyclePoint, CycleProblem, CycleSettings, state_scales
from bifurcation.equilibria.hopf import HopfPoint, primary_derivative
from bifurcation.problem import Family, ProblemError
from bifurcation.special_points import PointKind, PointStatus, SpecialPoint

SUBDIVISIONS = 4       # sub-segments of an end segment, equally spaced in c^2 (roughly in p)


def hopf_multipliers(family: Family, hopf: HopfPoint) -> np.ndarray:
    """exp(lambda_i T), T = 2 pi / omega, by decreasing modulus: the Floquet multipliers of the zero-amplitude
    cycle at ``hopf`` (module docstring), the trivial one included."""
    period = 2.0 * np.pi / hopf.omega
    mu = np.exp(np.linalg.eigvals(family.linear_matrix(hopf.p, hopf.q)) * period)
    return mu[np.argsort(-np.abs(mu))]


def hopf_side(family: Family, hopf: HopfPoint) -> float:
    """sign(p - p_H) of the small cycles near ``hopf``: -l1 / mu' (Kuznetsov 2004, theorem 3.3, with mu' =
    d Re lambda / dp), or -a / mu' where f has a kink at the equilibrium (its kink coefficient a,
    :attr:`~bifurcation.equilibria.hopf.HopfPoint.kink`, decides there: the cycles' amplitude grows linearly
    with p - p_H, and l1's side was the wrong one where their signs differ, which put a fold into the segment that
    is not there or hid one that is); NaN when neither is known."""
    leading = hopf.kink if np.isfinite(hopf.kink) else hopf.first_lyapunov
    if not np.isfinite(leading) or leading == 0.0:
        return float("nan")
    A = family.linear_matrix(hopf.p, hopf.q)
    lam, vecs = np.linalg.eig(A)
    k = int(np.argmin(np.abs(lam - 1j * hopf.omega)))
    lam_l, left = np.linalg.eig(A.T)
    p = left[:, int(np.argmin(np.abs(lam_l - 1j * hopf.omega)))]          # p^T A = i w p^T
    q = vecs[:, k]
    mu_prime = float((p @ primary_derivative(family, hopf.p, hopf.q, A) @ q / (p @ q)).real)
    return float(np.sign(-leading / mu_prime)) if mu_prime != 0.0 else float("nan")


class EndSegment:
    """The cycles u(c) between the computed cycle ``near`` (c = 1) and ``hopf`` (c = 0), module docstring."""

    def __init__(self, family: Family, near: CyclePoint, hopf: HopfPoint, settings: CycleSettings):
        self.family, self.near, self.hopf, self.settings = family, near, hopf, settings
        self.problem = CycleProblem(family, family.primary, near.p, near.q, near.orbit,
                                    state_scales(family, 2.0 * np.pi / near.period), family.primary_scale, settings)
        self.u1 = self.problem.pack(near.orbit, near.p)
        self.w = self.problem.weights()
        size = self.problem.size
        normal = np.concatenate([self.u1[:size], [0.0, 0.0]])
        self.normal = normal / np.linalg.norm(normal * self.w)
        self.P1 = float(np.dot(self.normal * self.w, self.u1 * self.w))    # <t_end, u(1)>_W
        self.solved: dict[float, tuple[np.ndarray, np.ndarray]] = {}
        self._jacobians: dict[float, object] = {}        # at each solved c, for the chord iterations nearby
        self._multipliers: dict[float, np.ndarray] = {}  # taken while the solution's Jacobian is at hand
        self.side = hopf_side(family, hopf)

    def solve(self, c: float) -> tuple[np.ndarray, np.ndarray]:
        """(u, unit tangent) of the cycle at c in (0, 1]; RuntimeError when Newton fails."""
        if c in self.solved:
            return self.solved[c]
        # Predictor from the nearest solved c' (or the computed cycle): nodes scaled by c / c', p and
        # period moved towards the Hopf values as (c / c')^2 (p - p_H and T - T_H are of order c^2).
        c0 = min(self.solved, key=lambda x: abs(x - c)) if self.solved else 1.0
        u0 = self.solved[c0][0] if self.solved else self.u1
        r = c / c0
        size = self.problem.size
        hopf_tail = np.array([2.0 * np.pi / self.hopf.omega, self.hopf.p])
        u_pred = np.concatenate([r * u0[:size], hopf_tail + r * r * (u0[size:] - hopf_tail)])
        # The hyperplane is <t_end, u>_W = c <t_end, u(1)>_W: shift the predictor onto it along the normal.
        u_pred += (c * self.P1 - float(np.dot(self.normal * self.w, u_pred * self.w))) * self.normal
        st = self.settings
        chord = self.problem.value if self.family.costly_jacobian else None
        result = correct(self.problem, u_pred, self.normal, self.w, st.continuation,
                         blocks=self.problem.blocks_of_unknowns(), value=chord, frozen=self._jacobians.get(c0))
        if result is None:
            raise RuntimeError(f"no cycle at c = {c:.6g} of the end segment at the Hopf point")
        u, J, _ = result
        self.solved[c] = (u, tangent(J, self.w, self.normal))
        self._jacobians[c] = J
        self._multipliers[c] = self.problem.multipliers(u)
        return self.solved[c]

    def multipliers(self, c: float) -> np.ndarray:
        """Non-trivial multipliers at c (c = 0: exactly those of the Hopf point)."""
        if c == 0.0:
            mu = hopf_multipliers(self.family, self.hopf)
        else:
            self.solve(c)
            mu = self._multipliers[c]
        return classify_multipliers(mu)[0]

    def fold_test(self, c: float) -> float:
        """(dp/dc) / c: finite at the Hopf point, where p - p_H ~ c^2 (at a kink ~ c: it grows as 1/c, its sign
        kept), and through zero at a fold of cycles.  At c = 0 only its sign is exact (the normal form's side of the
        small cycles, :func:`hopf_side`): Brent needs no more."""
        if c == 0.0:
            if not np.isfinite(self.side):
                return float("nan")
            return self.side * abs(self.fold_test(SUBDIVISIONS ** -0.5))
        t = self.solve(c)[1]
        return float(t[-1] * self.P1 / np.dot(self.normal * self.w, t * self.w)) / c

    def point(self, c: float) -> CyclePoint:
        return self.problem.point(self.solve(c)[0])


def end_segment_points(family: Family, near: CyclePoint, hopf: HopfPoint, settings: CycleSettings,
                       s_near: float, sign: float) -> list[SpecialPoint]:
    """Cycle folds, torus and period-doubling points between the computed cycle ``near`` and the Hopf point
    ``hopf``, located by Brent's method in c (module docstring).  The brackets are placed on the branch's
    arclength: ``near`` at ``s_near``, the Hopf point the segment's weighted length away in the direction
    ``sign``, c in between as c^2."""
    seg = EndSegment(family, near, hopf, settings)
    hopf_u = np.concatenate([np.zeros(seg.problem.size), [2.0 * np.pi / hopf.omega, hopf.p]])
    s1, s0 = s_near, s_near + sign * float(np.linalg.norm((seg.u1 - hopf_u) * seg.w))
    nodes = [float(np.sqrt(k / SUBDIVISIONS)) for k in range(SUBDIVISIONS, -1, -1)]     # 1, ..., 0
    tests = (
        (PointKind.TORUS, complex_outside, lambda c: torus_test(seg.multipliers(c))),
        (PointKind.PERIOD_DOUBLING, negative_outside, lambda c: period_doubling_test(seg.multipliers(c))),
    )

    def position(c: float) -> float:
        return s0 + c * c * (s1 - s0)

    found: list[SpecialPoint] = []
    try:
        for c in nodes[:-1]:
            seg.solve(c)
    except (RuntimeError, ProblemError):
        return found        # the segment cannot be solved: nothing is claimed about it
    for a, b in zip(nodes[:-1], nodes[1:]):
        events = [(kind, test) for kind, count, test in tests if count(seg.multipliers(a)) != count(seg.multipliers(b))]
        fa, fb = seg.fold_test(a), seg.fold_test(b)
        if fa * fb < 0.0:
            events.append((PointKind.CYCLE_FOLD, seg.fold_test))
        for kind, test in events:
            where, status = None, None
            try:
                # A count that changes without a sign change of the test (a complex pair meeting on the real axis
                # outside the circle) brackets nothing: only the bracket is reported.
                if test(a) * test(b) < 0.0:
                    c = scipy.optimize.brentq(test, b, a, xtol=1e-12, rtol=1e-10)
                    if c > 0.0:
                        where, status = seg.point(c), PointStatus.LOCATED
            except (RuntimeError, ValueError, ProblemError):
                pass
            if where is None:
                c, where, status = a, seg.point(a), PointStatus.NOT_CONVERGED
            found.append(SpecialPoint(
                kind=kind, p=where.p, q=where.q,
                bracket=tuple(sorted((position(a), position(b)))), status=status,
                data={"period": where.period, "amplitude": where.amplitude, "multipliers": where.multipliers,
                      "free": family.primary, "cycle": where, "end_segment": True}))
    return found
