"""Curves of torus (Neimark-Sacker) points of cycles by a bordered system on the collocation discretisation.

Doedel, Govaerts & Kuznetsov, SIAM J. Numer. Anal. 41 (2003) 401-435, the NS system; Kuznetsov 2004, section
10.3.2.  A cycle has multipliers exp(+-i theta) exactly when M^2 - 2 kappa M + I is singular with kappa = cos theta
(M the monodromy matrix).  On the discretisation this is the collocated variational equation v' = T f_x v over two
periods, v(2) - 2 kappa v(1) + v(0) = 0: a 2K x 2K sparse matrix A(U) (K collocation unknowns per period) whose
kernel is two-dimensional at a torus point.  Bordered by two columns and two rows, the 2 x 2 block G of the
solution of [A B; C^T 0] [Z; G] = [0; I] vanishes there; two of its entries, chosen at the start where their
gradients are the most independent, join the collocation and phase equations in the unknowns
U = (x nodes, T, p, q, kappa).  Gradients are -W_i^T A_U Z_j with W from the transposed system (same LU), second
derivatives of f from central differences of the exact Jacobians along the columns of Z, as for the cycle folds
(:mod:`bifurcation.cycle_curves.fold`, whose curve follower is reused).  Borders are reset to the current null
vectors at every accepted point.  Along the curve kappa itself locates the strong resonances 1:1 (kappa = 1),
1:2 (kappa = -1), 1:3 (kappa = -1/2) and 1:4 (kappa = 0); past 1:1 and 1:2 (|kappa| > 1) the points are neutral
saddle cycles, not torus points, and are marked so.  Chenciner points, where the real part of the
Neimark-Sacker normal-form coefficient (:func:`bifurcation.cycles.normal_forms.neimark_sacker_coefficient`)
changes sign, are located by Brent's method on it.
"""

from __future__ import annotations

import itertools

import numpy as np
import scipy.optimize
import scipy.sparse

from bifurcation.continuation import ContinuationSettings, locate_on_step
from bifurcation.cycle_curves.bordered import (
    FD_RELATIVE,
    FOLD_SETTINGS,
    SparseBordered,
    curve_q_scale,
    follow_bordered_curve,
)
from bifurcation.cycle_curves.fold import FoldSystem
from bifurcation.cycles import collocation as col
from bifurcation.cycles.multipliers import classify_multipliers
from bifurcation.cycles.problem import CyclePoint, CycleSettings
from bifurcation.problem import ProblemError
from bifurcation.special_points import PointKind, SpecialPoint
from bifurcation.factorization import factorize

RESONANCE_KAPPA = ((PointKind.RESONANCE_1_1, 1.0), (PointKind.RESONANCE_1_2, -1.0),
                   (PointKind.RESONANCE_1_3, -0.5), (PointKind.RESONANCE_1_4, 0.0))


class TorusSystem(FoldSystem):
    """H(U) = (collocation, phase condition, two entries of G) for U = (x nodes, T, p, q, kappa)."""

    def __init__(self, family, cycle: CyclePoint, q_scale: float, settings: CycleSettings = CycleSettings()):
        super().__init__(family, cycle, q_scale, settings, kind=PointKind.TORUS)
        rng = np.random.default_rng(2)
        self.b = rng.standard_normal((2 * self.K, 2))
        self.c = rng.standard_normal((2 * self.K, 2))
        self.entries: tuple[tuple[int, int], tuple[int, int]] = ((0, 0), (1, 0))
        self._lyapunov: tuple = (None, float("nan"))     # (accepted point, Re d there)

    @property
    def dim(self) -> int:
        return 2 * self.K

    def start(self, cycle: CyclePoint) -> np.ndarray:
        rest, _ = classify_multipliers(cycle.multipliers)
        pair = rest[np.abs(rest.imag) > 1e-7]
        mu = pair[np.argmin(np.abs(np.abs(pair) - 1.0))]
        U0 = np.append(self.pack(cycle.orbit, cycle.p, cycle.q), np.cos(np.angle(mu)))
        self.renormalize(U0), self.renormalize(U0)
        self._choose_entries(U0)
        return U0

    def weights(self) -> np.ndarray:
        return np.append(super().weights(), 1.0)

    # --- the chained variational equation -------------------------------------------------------------
    def _interval_values(self, z: np.ndarray, kappa: float) -> tuple[np.ndarray, np.ndarray]:
        """(N, m+1, n) interval node values of v over the first and the second period; the last node of the
        second period is 2 kappa v(1) - v(0)."""
        N, m, n = self.cp.intervals, self.cp.degree, self.cp.n
        nodes = z[:self.dim].reshape(2 * N * m, n)
        idx = np.arange(N)[:, None] * m + np.arange(m + 1)[None, :]
        first = nodes[idx]
        second = nodes[np.minimum(idx + N * m, 2 * N * m - 1)]
        second[-1, -1] = 2.0 * kappa * nodes[N * m] - nodes[0]
        return first, second

    def _chain(self, CJ, kappa: float) -> scipy.sparse.spmatrix:
        cp, K = self.cp, self.K
        N, m, n = cp.intervals, cp.degree, cp.n
        rows, _ = col.block_pattern(N, m, n)
        shape = (N, m, n, m + 1, n)
        local = np.broadcast_to(np.arange(N)[:, None, None, None, None] * m
                                + np.arange(m + 1)[None, None, None, :, None], shape).ravel()
        comp = np.broadcast_to(np.arange(n)[None, None, None, None, :], shape).ravel()
        data = CJ.B.ravel()
        wrap = local == N * m                       # the right node of the last interval
        r = [rows, rows + K]
        c = [local * n + comp, np.where(wrap, N * m, local + N * m) * n + comp]
        d = [data, np.where(wrap, 2.0 * kappa * data, data)]
        r.append(rows[wrap] + K)
        c.append(comp[wrap])                        # the -v(0) part of the wrap
        d.append(-data[wrap])
        return scipy.sparse.csc_matrix((np.concatenate(d), (np.concatenate(r), np.concatenate(c))),
                                       shape=(2 * K, 2 * K))

    # no chord iterations on the torus system: its value would need the same chained bordered solve as the rest
    value = None

    def evaluate(self, U: np.ndarray):
        if self._cache is not None and np.array_equal(self._cache[0], U):
            return self._cache[1]
        K = self.K
        G, A, col_p, col_q, e = self._pieces(U)
        core = self._chain(self._last_jacobian, float(U[K + 3]))
        M = scipy.sparse.bmat([[core, scipy.sparse.csc_matrix(self.b)],
                               [scipy.sparse.csc_matrix(self.c.T), None]], format="csc")
        lu = factorize(M)
        rhs = np.zeros((2 * K + 2, 2))
        rhs[-2:, :] = np.eye(2)
        Z = lu.solve(rhs)
        W = lu.solve(rhs, trans="T")
        out = (G, A, col_p, col_q, e, Z, W)
        self._cache = (U.copy(), out)
        return out

    def _parameter_jacobians(self, e: dict) -> tuple[np.ndarray, np.ndarray]:
        """d f_x / dp and d f_x / dq at the collocation points (central differences), shared by all entries."""
        cp, n = self.cp, self.cp.n
        xk = e["Xc"].reshape(-1, n)
        p, q = e["p"], e["q"]
        hp, hq = FD_RELATIVE * cp.p_scale, FD_RELATIVE * self.q_scale

        # Parameter derivatives of f_x, for gradients that only steer Newton: one side's Jacobian at a kink is enough
        # (the state derivative f_xx keeps the smoothed Jacobians: one-sided there, a fold curve of the full geometry
        # did not take a step, measured)
        def jac(p_, q_):
            return self.family.rhs_and_jacobians(xk, p_, q_, kink_rows=False)[1]
        return (jac(p + hp, q) - jac(p - hp, q)) / (2 * hp), (jac(p, q + hq) - jac(p, q - hq)) / (2 * hq)

    def _entry_gradient(self, U: np.ndarray, e: dict, Z: np.ndarray, W: np.ndarray, i: int, j: int,
                        dJ: tuple[np.ndarray, np.ndarray] | None = None) -> np.ndarray:
        """d G_ij / dU = -W_i^T A_U Z_j over U = (nodes, T, p, q, kappa)."""
        cp, K = self.cp, self.K
        N, m, n = cp.intervals, cp.degree, cp.n
        kappa = float(U[K + 3])
        T, p, q = e["T"], e["p"], e["q"]
        xk = e["Xc"].reshape(-1, n)
        Jf = e["Jf"].reshape(-1, n, n)
        dJ_p, dJ_q = self._parameter_jacobians(e) if dJ is None else dJ
        v_copies = self._interval_values(Z[:, j], kappa)
        w_rows = W[:2 * K, i].reshape(2, N * m, n)                      # collocation rows of both periods
        g_nodes = np.zeros((N * m, n))
        g_T = g_p = g_q = 0.0
        for Yv, wk in zip(v_copies, w_rows):
            vk = col.collocation_states(Yv, cp.sch).reshape(-1, n)
            eps = FD_RELATIVE / max(np.max(np.abs(vk) / cp.scales), 1e-300)
            H = (self.family.rhs_and_jacobians(xk + eps * vk, p, q)[1]
                 - self.family.rhs_and_jacobians(xk - eps * vk, p, q)[1]) / (2.0 * eps)
            gx = np.einsum("ka,kab->kb", wk, T * H)
            np.add.at(g_nodes, col.node_index(N, m), np.einsum("ki,jkb->jib", cp.sch.L, gx.reshape(N, m, n)))
            g_T += float(np.einsum("ka,kab,kb->", wk, Jf, vk))
            g_p += T * float(np.einsum("ka,kab,kb->", wk, dJ_p, vk))
            g_q += T * float(np.einsum("ka,kab,kb->", wk, dJ_q, vk))
        # kappa enters the last interval of the second period only, through its right node 2 kappa v(1).
        B_last = self._last_jacobian.B[-1]                                # (m, n, m+1, n)
        v1 = Z[:2 * K, j].reshape(2 * N * m, n)[N * m]
        g_kappa = -float(np.sum(w_rows[1].reshape(N, m, n)[-1] * (2.0 * np.einsum("kab,b->ka", B_last[:, :, -1, :],
                                                                                   v1))))
        return np.concatenate([g_nodes.ravel(), [g_T, g_p, g_q, g_kappa]])

    def _choose_entries(self, U: np.ndarray) -> None:
        """The two entries of G whose gradients are the most independent (smallest singular value largest)."""
        _, _, _, _, e, Z, W = self.evaluate(U)
        w = self.weights()
        dJ = self._parameter_jacobians(e)
        grads = {(i, j): self._entry_gradient(U, e, Z, W, i, j, dJ) / w for i in range(2) for j in range(2)}
        best = max(itertools.combinations(grads, 2),
                   key=lambda pair: np.linalg.svd(np.vstack([grads[pair[0]], grads[pair[1]]]), compute_uv=False)[-1])
        self.entries = best

    def __call__(self, U: np.ndarray):
        K = self.K
        try:
            G, A, col_p, col_q, e, Z, W = self.evaluate(U)
        except (ProblemError, RuntimeError):
            return np.full(K + 3, np.nan), SparseBordered(scipy.sparse.csr_matrix((K + 3, K + 4)))
        Gblk = Z[2 * K:, :]
        g = [Gblk[i, j] for i, j in self.entries]
        dJ = self._parameter_jacobians(e)
        grads = [self._entry_gradient(U, e, Z, W, i, j, dJ) for i, j in self.entries]
        top = scipy.sparse.hstack([A, scipy.sparse.csc_matrix(col_p[:, None]), scipy.sparse.csc_matrix(col_q[:, None]),
                                   scipy.sparse.csc_matrix((K + 1, 1))])
        J = scipy.sparse.vstack([top, scipy.sparse.csr_matrix(np.vstack(grads))], format="csr")
        return np.concatenate([G, g]), SparseBordered(J)

    def renormalize(self, U: np.ndarray) -> None:
        """At an accepted point: the orbit becomes the phase reference, the borders the current null vectors."""
        K = self.K
        _, _, _, _, _, Z, W = self.evaluate(U)
        self.c = np.linalg.qr(Z[:2 * K])[0]
        self.b = np.linalg.qr(W[:2 * K])[0]
        self.cp.set_reference(self.cp.orbit_of(U[:K + 2]))
        self._cache = None
        return None

    def kappa(self, U: np.ndarray) -> float:
        return float(U[self.K + 3])

    def events(self, branch, k: int, step: float) -> list:
        """The strong resonances 1:1, 1:2, 1:3 and 1:4: kappa through 1, -1, -1/2 and 0.  Past 1:1 or 1:2 the
        curve goes on as a curve of neutral saddle cycles (real multipliers mu, 1/mu; Kuznetsov 2004, sections
        9.5 and 10.3), marked per point by :attr:`bifurcation.cycle_curves.result.CycleCurve.neutral_saddle`."""
        K = self.K
        found = []
        before, after = branch.points[k][K + 3], branch.points[-1][K + 3]
        for kind, kappa in RESONANCE_KAPPA:
            if (before - kappa) * (after - kappa) < 0.0:
                u, _, ok = locate_on_step(branch, k, step, lambda u, t, kappa=kappa: u[K + 3] - kappa)
                found.append((kind, self.point(u), ok))
        from bifurcation.cycles.normal_forms import locate_zero, neimark_sacker_coefficient

        def lyapunov(u, t=None):
            return neimark_sacker_coefficient(self, u).real if abs(u[K + 3]) < 1.0 else float("nan")
        # The value at the step's start was computed as the previous step's end.
        previous = self._lyapunov if self._lyapunov[0] is branch.points[k] else (None, lyapunov(branch.points[k]))
        self._lyapunov = (branch.points[-1], lyapunov(branch.points[-1]))
        if previous[1] * self._lyapunov[1] < 0.0:
            zero = locate_zero(branch, k, step, lyapunov, (previous[1], self._lyapunov[1]))
            if zero is not None:
                found.append((PointKind.CHENCINER, self.point(zero[0]), zero[1]))
        return found


    def end_events(self, branch, k: int, s_end: float, end: SpecialPoint) -> list:
        """The strong resonances between point k and the Hopf-Hopf point ``end`` where the curve's amplitude
        vanishes.  There the cycle of frequency omega_1 has shrunk onto the equilibrium, whose other pair
        +-i omega_2 gives the multipliers exp(+-i omega_2 T), T = 2 pi / omega_1 (Kuznetsov 2004, section 8.6):
        kappa ends at cos(2 pi omega_2 / omega_1).  A resonance value between kappa at point k and that end is
        located by Brent's method in the arclength on the corrected curve, short of the end itself (where the orbit
        is the equilibrium); NOT_CONVERGED with its bracket when the corrector fails there."""
        K = self.K
        U = branch.points[k]
        own = 2.0 * np.pi / float(U[K])
        omegas = sorted((end.data.get("omega", np.nan), end.data.get("omega2", np.nan)), key=lambda w: abs(w - own))
        if not np.all(np.isfinite(omegas)):
            return []
        kappa_end = float(np.cos(2.0 * np.pi * omegas[1] / omegas[0]))
        before = float(U[K + 3])
        found = []
        for kind, kappa in RESONANCE_KAPPA:
            if not (before - kappa) * (kappa_end - kappa) < 0.0:
                continue

            def offset(s, kappa=kappa):
                if s >= s_end:
                    return kappa_end - kappa
                return float(branch.point_at(k, s)[0][K + 3]) - kappa
            try:
                s = scipy.optimize.brentq(offset, 0.0, s_end, xtol=1e-12, rtol=1e-10)
                if s >= s_end:
                    raise ValueError("the resonance is the end point itself")
                found.append((kind, self.point(branch.point_at(k, s)[0]), True, (s, s_end)))
            except (RuntimeError, ValueError):
                found.append((kind, self.point(branch.points[-1]), False, (0.0, s_end)))
        return found


def torus_curve(family, point: SpecialPoint, lo: float, hi: float, p_min: float, p_max: float,
                settings: CycleSettings = CycleSettings(), continuation: ContinuationSettings = FOLD_SETTINGS,
                accept_hook=None):
    """The curve of torus points through the located torus ``point`` of a branch in the primary parameter, both
    ways, within [p_min, p_max] x [lo, hi], by the bordered NS system (module docstring).  Returns a
    :class:`bifurcation.cycle_curves.result.CycleCurve`."""
    if point.kind is not PointKind.TORUS:
        raise ValueError("torus_curve follows torus points")

    def make_system(cycle: CyclePoint):
        return TorusSystem(family, cycle, curve_q_scale(cycle), settings)
    return follow_bordered_curve(family, point, lo, hi, p_min, p_max, settings, continuation, make_system,
                                 accept_hook)
