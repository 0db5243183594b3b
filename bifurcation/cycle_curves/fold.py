"""Curves of cycle folds in two parameters by a minimally augmented system on the collocation discretisation.

Doedel, Govaerts & Kuznetsov, "Computation of periodic solution bifurcations in ODEs using bordered systems",
SIAM J. Numer. Anal. 41 (2003) 401-435; Kuznetsov, Elements of Applied Bifurcation Theory (3rd ed., 2004),
section 10.3.2; MatCont's LPC continuation (Dhooge, Govaerts, Kuznetsov, Meijer & Sautois, Math. Comput. Model.
Dyn. Syst. 14, 2008, 147).

Unknowns U = (x nodes, T, p, q).  Equations: the collocation of x' = T f(x; p, q), the integral phase condition
(:class:`bifurcation.cycles.problem.CycleProblem`), and g(U) = 0, where g is the last component of the solution of the
bordered system

    [ F_x   F_T   b_1 ] [v]   [0]
    [ P_x   0     b_2 ] [S] = [0]
    [ c_1   c_2   0   ] [g]   [1]

with F_x, F_T the collocation Jacobian in the nodes and the period and P_x the phase condition's gradient.  Its
leading (K + 1) x (K + 1) block is singular exactly at a fold of cycles (the discretised (x, T) problem at fixed
parameters loses its isolation), so g = 0 there for any borders that keep the whole matrix regular; the borders
are reset to the current right and left null vectors at every accepted point, as MatCont does.  The gradient
of g is g_U = -w^T M_U z with z = (v, S, g) and w the solution of the transposed system (the same LU factors):
the second derivatives it needs, f_xx[v, .], come from a central difference of the exact (complex-step)
Jacobians in the direction v, and the parameter derivatives from central differences.  The system is solved as
one sparse matrix (SuperLU); the curve is followed by :func:`bifurcation.continuation.continue_curve` and ends
where it leaves the (p, q) window or where its amplitude vanishes, at a generalized Hopf point that is then
located by its own test function (:func:`bifurcation.cycle_curves.result.locate_end`).
"""

from __future__ import annotations

import dataclasses

import numpy as np
import scipy.optimize
import scipy.sparse

from bifurcation.continuation import ContinuationSettings
from bifurcation.cycle_curves.bordered import (
    FD_RELATIVE,
    FOLD_SETTINGS,
    START_RESIDUAL,
    SparseBordered,
    curve_q_scale,
    follow_bordered_curve,
    start_point,
)
from bifurcation.cycles import collocation as col
from bifurcation.cycles.problem import (
    CyclePoint,
    CycleProblem,
    CycleSettings,
    state_scales,
)
from bifurcation.problem import ProblemError
from bifurcation.special_points import PointKind, SpecialPoint
from bifurcation.factorization import factorize


class FoldSystem:
    """H(U) = (collocation, phase condition, g) for U = (x nodes, T, p, q), with its sparse Jacobian.

    ``kind`` CYCLE_FOLD: g from the bordered (x, T) Jacobian of the periodic problem (module docstring);
    PERIOD_DOUBLING: g from the bordered collocation of the variational equation v' = T f_x v with the
    antiperiodic condition v(1) = -v(0) (Doedel, Govaerts & Kuznetsov 2003, the PD system), singular where a
    multiplier is -1."""

    def __init__(self, family, cycle: CyclePoint, q_scale: float, settings: CycleSettings = CycleSettings(),
                 kind: PointKind = PointKind.CYCLE_FOLD):
        omega = 2.0 * np.pi / cycle.period
        self.family = family
        self.kind = kind
        self.cp = CycleProblem(family, family.primary, cycle.p, cycle.q, cycle.orbit,
                               state_scales(family, omega), family.primary_scale, settings, smoothed=True)
        self.q_scale = q_scale
        rng = np.random.default_rng(1)
        self.b = rng.standard_normal(self.dim)
        self.c = rng.standard_normal(self.dim)
        self._cache: tuple[np.ndarray, tuple] | None = None
        self._sides: tuple | None = None      # (p, q), states, (f, f_x) at q +- h (:meth:`_q_sides`)

    @property
    def K(self) -> int:
        return self.cp.size

    @property
    def dim(self) -> int:
        """Size of the bordered block: (v, S) for a fold, v for period doubling."""
        return self.K + 1 if self.kind is PointKind.CYCLE_FOLD else self.K

    def _signs(self) -> np.ndarray:
        """(N, m+1) signs of the interval node values of v: the antiperiodic wrap for period doubling."""
        N, m = self.cp.intervals, self.cp.degree
        sgn = np.ones((N, m + 1))
        if self.kind is PointKind.PERIOD_DOUBLING:
            sgn[-1, -1] = -1.0
        return sgn

    def _variational(self, CJ) -> scipy.sparse.spmatrix:
        """The collocated variational equation with the antiperiodic wrap, K x K."""
        cp, K = self.cp, self.K
        N, m, n = cp.intervals, cp.degree, cp.n
        rows, cols = col.block_pattern(N, m, n)
        data = (CJ.B * self._signs()[:, None, None, :, None]).ravel()
        return scipy.sparse.csc_matrix((data, (rows, cols)), shape=(K, K))

    def pack(self, orbit: col.Orbit, p: float, q: float) -> np.ndarray:
        return np.concatenate([orbit.nodes.ravel(), [orbit.period, p, q]])

    def weights(self) -> np.ndarray:
        return np.concatenate([self.cp.weights(), [1.0 / self.q_scale]])

    def _pieces(self, U: np.ndarray):
        """Collocation residual, its Jacobian A = [F_x F_T; P_x 0] (sparse), the columns in p and q."""
        G, A, CJ, e = self._collocation(U)
        n, q = self.cp.n, float(U[self.K + 2])
        col_p = np.append(CJ.col_p.ravel(), 0.0)
        col_q = np.append(-e["T"] * self._df_dq(e["Xc"].reshape(-1, n), e["p"], q).ravel(), 0.0)
        return G, A, col_p, col_q, e

    def _collocation(self, U: np.ndarray):
        """Collocation residual, its Jacobian A = [F_x F_T; P_x 0] (sparse), the collocation Jacobian's blocks and
        the evaluation at the collocation points."""
        K, cp = self.K, self.cp
        q = float(U[K + 2])
        cp.set_fixed(q=q)
        G, CJ = cp(U[:K + 2])
        self._last_jacobian = CJ
        if not np.all(np.isfinite(G)):
            raise ProblemError("collocation residual not finite")
        e = cp.evaluate(U[:K + 2])
        N, m, n = cp.intervals, cp.degree, cp.n
        rows, cols = col.block_pattern(N, m, n)
        data = CJ.B.ravel()
        rows = np.concatenate([rows, np.arange(K), np.full(K, K)])
        cols = np.concatenate([cols, np.full(K, K), np.arange(K)])
        data = np.concatenate([data, CJ.col_T.ravel(), CJ.phase.ravel()])
        A = scipy.sparse.csc_matrix((data, (rows, cols)), shape=(K + 1, K + 1))
        return G, A, CJ, e

    def _df_dq(self, P: np.ndarray, p: float, q: float) -> np.ndarray:
        (f_plus, _), (f_minus, _) = self._q_sides(P, p, q)
        return (f_plus - f_minus) / (2 * FD_RELATIVE * self.q_scale)

    def _q_sides(self, P: np.ndarray, p: float, q: float) -> tuple[tuple, tuple]:
        """(f, f_x) at the states P (one side's f_x at a kink) at q + h and q - h, h = FD_RELATIVE q_scale: the
        q column of the collocation Jacobian and the q derivative of the gradient read the same evaluations."""
        cached = self._sides
        if cached is not None and cached[0] == (p, q) and np.array_equal(cached[1], P):
            return cached[2]
        h = FD_RELATIVE * self.q_scale
        sides = tuple(self.family.rhs_and_jacobians(P, p, q + s, kink_rows=False) for s in (h, -h))
        self._sides = ((p, q), P.copy(), sides)
        return sides

    def _bordered(self, A, CJ):
        """The LU factors of the bordered matrix M of the module docstring (A and the collocation Jacobian CJ of
        one evaluation)."""
        core = A if self.kind is PointKind.CYCLE_FOLD else self._variational(CJ)
        M = scipy.sparse.bmat([[core, scipy.sparse.csc_matrix(self.b[:, None])],
                               [scipy.sparse.csc_matrix(self.c[None, :]), None]], format="csc")
        return factorize(M)

    def value(self, U: np.ndarray) -> np.ndarray:
        """H(U) alone, for the chord iterations of :func:`bifurcation.continuation.correct`: the collocation
        residual and g, without the parameter columns and g's gradient (a third of an evaluation of H with its
        Jacobian; Newton on this system converges only linearly where f has a kink on the orbit, so chord
        iterations lose little there)."""
        if self._cache is not None and np.array_equal(self._cache[0], U):
            return np.append(self._cache[1][0], self._cache[1][5][-1])
        try:
            G, A, CJ, _ = self._collocation(U)
            rhs = np.zeros(self.dim + 1)
            rhs[-1] = 1.0
            g = self._bordered(A, CJ).solve(rhs)[-1]
        except (ProblemError, RuntimeError):
            return np.full(self.K + 2, np.nan)
        return np.append(G, g)

    def evaluate(self, U: np.ndarray):
        if self._cache is not None and np.array_equal(self._cache[0], U):
            return self._cache[1]
        G, A, col_p, col_q, e = self._pieces(U)
        lu = self._bordered(A, self._last_jacobian)
        rhs = np.zeros(self.dim + 1)
        rhs[-1] = 1.0
        z = lu.solve(rhs)
        w = lu.solve(rhs, trans="T")
        out = (G, A, col_p, col_q, e, z, w)
        self._cache = (U.copy(), out)
        return out

    def _g_gradient(self, U: np.ndarray, e: dict, z: np.ndarray, w: np.ndarray) -> np.ndarray:
        """g_U = -w^T M_U z over U = (nodes, T, p, q); only the collocation rows of M depend on U.

        Collocation row k of M z is R_k = (D v)_k / h - T f_x(x_k) v_k - S f(x_k), v_k = (L v)_k."""
        cp, K = self.cp, self.K
        N, m, n = cp.intervals, cp.degree, cp.n
        v_nodes = z[:K].reshape(-1, n)
        S = z[K] if self.kind is PointKind.CYCLE_FOLD else 0.0
        sgn = self._signs()
        Yv = v_nodes[col.node_index(N, m)] * sgn[:, :, None]
        vk = col.collocation_states(Yv, cp.sch).reshape(-1, n)                                # (Nm, n)
        xk = e["Xc"].reshape(-1, n)
        wk = w[:K].reshape(-1, n)
        T, p, q = e["T"], e["p"], e["q"]
        Jf = e["Jf"].reshape(-1, n, n)
        # f_xx[v_k, .] by a central difference of the exact Jacobians along v_k.
        size = np.max(np.abs(vk) / cp.scales)
        eps = FD_RELATIVE / max(size, 1e-300)
        _, Jp = self.family.rhs_and_jacobians(xk + eps * vk, p, q)
        _, Jm = self.family.rhs_and_jacobians(xk - eps * vk, p, q)
        H = (Jp - Jm) / (2.0 * eps)                                     # (Nm, a, b) = d/dx_b (f_x v)_a
        gx = np.einsum("ka,kab->kb", wk, T * H + S * Jf)               # -w^T dR/dx_k
        per_interval = np.einsum("ki,jkb->jib", cp.sch.L, gx.reshape(N, m, n)) * sgn[:, :, None]
        g_nodes = np.zeros((N * m, n))
        np.add.at(g_nodes, col.node_index(N, m), per_interval)
        g_T = float(np.einsum("ka,kab,kb->", wk, Jf, vk))
        # Parameters: psi(p) = T f_x(x_k; p) v_k + S f(x_k; p), g_p = w^T dpsi/dp (central differences).

        # Parameter derivatives steer Newton only (g itself comes from collocation's Jacobian): one side's Jacobian at
        # a kink is enough, and saves the differences near a lift-off (a fold curve of the full geometry: 175 s ->
        # 123 s, the same points).  The state derivative above keeps them: one-sided there, no step was taken.
        def psi(f, fx):
            return T * np.einsum("kab,kb->ka", fx, vk) + S * f

        hp = FD_RELATIVE * cp.p_scale
        hq = FD_RELATIVE * self.q_scale
        g_p = float(np.sum(wk * (psi(*self.family.rhs_and_jacobians(xk, p + hp, q, kink_rows=False))
                                 - psi(*self.family.rhs_and_jacobians(xk, p - hp, q, kink_rows=False)))) / (2 * hp))
        plus, minus = self._q_sides(xk, p, q)
        g_q = float(np.sum(wk * (psi(*plus) - psi(*minus))) / (2 * hq))
        return np.concatenate([g_nodes.ravel(), [g_T, g_p, g_q]])

    def __call__(self, U: np.ndarray):
        K = self.K
        try:
            G, A, col_p, col_q, e, z, w = self.evaluate(U)
        except (ProblemError, RuntimeError):
            return np.full(K + 2, np.nan), SparseBordered(scipy.sparse.csr_matrix((K + 2, K + 3)))
        g = z[-1]
        grad = self._g_gradient(U, e, z, w)
        top = scipy.sparse.hstack([A, scipy.sparse.csc_matrix(col_p[:, None]),
                                   scipy.sparse.csc_matrix(col_q[:, None])])
        J = scipy.sparse.vstack([top, scipy.sparse.csr_matrix(grad[None, :])], format="csr")
        return np.append(G, g), SparseBordered(J)

    def renormalize(self, U: np.ndarray) -> None:
        """At an accepted point: the orbit becomes the phase reference, the borders the current null vectors."""
        K, d = self.K, self.dim
        _, _, _, _, _, z, w = self.evaluate(U)
        self.c = z[:d] / np.linalg.norm(z[:d])
        self.b = w[:d] / np.linalg.norm(w[:d])
        self.cp.set_reference(self.cp.orbit_of(U[:K + 2]))
        self._cache = None
        return None

    def point(self, U: np.ndarray) -> CyclePoint:
        K = self.K
        self.cp.set_fixed(q=float(U[K + 2]))
        return self.cp.point(U[:K + 2])

    def start(self, cycle: CyclePoint) -> np.ndarray:
        """The unknowns at the located point of a one-parameter branch."""
        return self.pack(cycle.orbit, cycle.p, cycle.q)

    def events(self, branch, k: int, step: float) -> list:
        """Further codimension-two points in the last step: (kind, cycle, located).  Period doubling: generalized
        period-doubling points, where the normal-form coefficient
        (:func:`bifurcation.cycles.normal_forms.period_doubling_coefficient`) changes sign, located by Brent's
        method on it along the corrected curve (a sign change through a pole, at a fold of cycles, is none)."""
        if self.kind is not PointKind.PERIOD_DOUBLING:
            return []
        from bifurcation.cycles.normal_forms import locate_zero, period_doubling_coefficient

        def coefficient(u, t=None):
            return period_doubling_coefficient(self, u)
        ends = (coefficient(branch.points[k]), coefficient(branch.points[-1]))
        if not ends[0] * ends[1] < 0.0:
            return []
        zero = locate_zero(branch, k, step, coefficient, ends)
        return [] if zero is None else [(PointKind.GENERALIZED_PERIOD_DOUBLING, self.point(zero[0]), zero[1])]

    def kappa(self, U: np.ndarray) -> float:
        """kappa = cos theta of the critical pair (torus systems only; NaN here)."""
        return float("nan")

    def end_events(self, branch, k: int, s_end: float, end: SpecialPoint) -> list:
        """Codimension-two points between point k and the curve's end point ``end`` (reached at arclength
        s_end beyond point k): (kind, cycle, located, bracket); none on fold and period-doubling curves."""
        return []












def fold_curve(family, point: SpecialPoint, lo: float, hi: float, p_min: float, p_max: float,
               settings: CycleSettings = CycleSettings(), continuation: ContinuationSettings = FOLD_SETTINGS,
               accept_hook=None):
    """The curve of cycle folds through the located fold ``point`` of a branch in the primary parameter, both
    ways, within [p_min, p_max] x [lo, hi], by the minimally augmented system (module docstring).

    Along the curve, cusps of cycles (the (p, q) tangent through zero), fold-flip points (another multiplier
    through -1) and fold-Neimark-Sacker points (a complex pair through the unit circle) are detected by the change
    in the number of multipliers outside the unit circle, with the two multipliers at +1 left out, and located by
    Brent's method on the period-doubling or torus test function along the corrected curve (Kuznetsov 2004,
    section 10.3; Govaerts 2000, ch. 7).

    Returns a :class:`bifurcation.cycle_curves.result.CycleCurve`."""
    if point.kind is not PointKind.CYCLE_FOLD:
        raise ValueError("fold_curve follows cycle folds")

    def make_system(cycle):
        return FoldSystem(family, cycle, curve_q_scale(cycle), settings, kind=point.kind)
    return follow_bordered_curve(family, point, lo, hi, p_min, p_max, settings, continuation, make_system,
                                 accept_hook)


def period_doubling_curve(family, point: SpecialPoint, lo: float, hi: float, p_min: float, p_max: float,
                          settings: CycleSettings = CycleSettings(),
                          continuation: ContinuationSettings = FOLD_SETTINGS, accept_hook=None):
    """The curve of period-doubling points through the located ``point`` of a branch in the primary parameter,
    both ways, within [p_min, p_max] x [lo, hi], by the minimally augmented PD system (antiperiodic variational
    equation, see :class:`FoldSystem`).  Along the curve, fold-flip points (a further multiplier through +1, the curve touching
    a cycle-fold curve; Kuznetsov 2004, section 10.3) are detected by the change in the number of real multipliers
    above 1, with the trivial one and the one at -1 left out, and located by Brent's method on the sum of the two
    multipliers nearest +1; generalized period-doubling points (the normal-form coefficient through zero) by
    :meth:`FoldSystem.events`.  Returns a :class:`bifurcation.cycle_curves.result.CycleCurve`."""
    if point.kind is not PointKind.PERIOD_DOUBLING:
        raise ValueError("period_doubling_curve follows period-doubling points")

    def make_system(cycle):
        return FoldSystem(family, cycle, curve_q_scale(cycle), settings, kind=point.kind)
    return follow_bordered_curve(family, point, lo, hi, p_min, p_max, settings, continuation, make_system,
                                 accept_hook)


def on_tolerance(family, point: SpecialPoint, settings: CycleSettings = CycleSettings()) -> SpecialPoint:
    """A cycle fold or period-doubling point of a branch in the primary parameter whose orbit misses the
    tolerance, moved to the same kind of point at the same q on a mesh its error estimate asks for (the defining
    system of :class:`FoldSystem`, corrected by Newton with q fixed: :func:`~bifurcation.cycle_curves.bordered.start_point`).

    A branch adapts its mesh only at accepted points; a long step across a fold leaves the point located on it on
    the older mesh.  On a multibody model whose right-hand side has a kink on the orbit (docs/results.md) a fold so
    located lay on 20 intervals with an error of 3.0e-5 against a tolerance of 1e-5, and 9e-4 (relative, in p)
    from the fold on an adequate mesh.  The point comes back unchanged where it meets the tolerance, or where Newton
    does not reach a point that does (its error estimate then says so)."""
    cycle = point.data["cycle"]
    if cycle.meets_tolerance or point.kind not in (PointKind.CYCLE_FOLD, PointKind.PERIOD_DOUBLING):
        return point

    def make_system(c):
        return FoldSystem(family, c, curve_q_scale(c), settings, kind=point.kind)
    try:
        system, U = start_point(make_system, cycle, FOLD_SETTINGS)
        G = system(U)[0]
    except (ProblemError, RuntimeError, np.linalg.LinAlgError):
        return point
    better = system.point(U)
    solved = np.all(np.isfinite(G)) and np.max(np.abs(G)) <= START_RESIDUAL * (1.0 + np.max(np.abs(U)))
    if not (solved and better.meets_tolerance and better.q == cycle.q):
        return point
    return dataclasses.replace(point, p=better.p, data={**point.data, "cycle": better, "period": better.period,
                                                        "amplitude": better.amplitude,
                                                        "multipliers": better.multipliers})
