"""Orthogonal collocation of periodic orbits on an adaptive mesh: the discretisation used by AUTO-07p and COCO.

A periodic orbit x(t) of period T is written in scaled time tau = t / T in [0, 1] as a continuous, periodic,
piecewise polynomial of degree m on a mesh 0 = tau_0 < ... < tau_N = 1.  On each interval the polynomial is held
by its values at m + 1 equally spaced nodes (the last node of an interval is the first of the next, and the last
of interval N - 1 is node 0: periodicity is built into the unknowns), and x' = T f(x) is imposed at the m
Gauss-Legendre points of each interval.  Doedel, Keller & Kernevez, Int. J. Bifurcation and Chaos 1 (1991) 493
and 745; Doedel, "Lecture notes on numerical analysis of nonlinear equations" (the AUTO notes), sections on
periodic solutions; Ascher, Mattheij & Russell, Numerical Solution of Boundary Value Problems for ODEs (SIAM 1995),
ch. 5 (collocation) and 9 (mesh selection).

Why collocation and not multiple shooting, for this model:

* At large amplitude the tyre force saturates (arctan in the Magic Formula) and the orbits stop being harmonic.
  Collocation with an equidistributed mesh puts intervals where the orbit bends; its error is controlled by the
  mesh alone, while shooting would carry an adaptive integrator (and its tolerance) inside every Newton step.
* The Newton matrix is exact and sparse: f and its Jacobian at all N m collocation points come from one
  vectorised complex-step evaluation of the vector field, the matrix is assembled in scipy.sparse and factorised
  with SuperLU.  Exact shooting derivatives would need the n x n variational equations integrated alongside.
* Gauss points are superconvergent at the mesh points, O(h^(2m)) (de Boor & Swartz, SIAM J. Numer. Anal. 10,
  1973), so 20-60 intervals of degree 4 give amplitudes to 1e-8.
* The Floquet multipliers come from the same Jacobian blocks by condensation of parameters: eliminating the
  interior nodes of each interval gives a transfer matrix per interval, and their product is the monodromy
  matrix of the discretised variational equation (Lust, Int. J. Bifurcation and Chaos 11, 2001, 2389; AUTO's
  Floquet multipliers come from the same block structure).  The product loses relative accuracy only for
  multipliers far inside the unit circle (|mu| << 1e-12), which never decide stability.

Error estimates and mesh adaptation: :mod:`bifurcation.cycles.mesh_adaptation`.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse

from bifurcation.factorization import factorize

DEFAULT_DEGREE = 4
RECURSION_LIMIT = 1e6   # growth of the partial transfer products beyond which the cyclic system is factorised


@dataclass(frozen=True)
class Scheme:
    """Degree-m collocation: equally spaced representation nodes, Gauss-Legendre collocation points on [0, 1]."""

    degree: int
    nodes: np.ndarray = field(repr=False)     # (m+1,) in [0, 1]
    points: np.ndarray = field(repr=False)    # (m,) Gauss-Legendre points in (0, 1)
    weights: np.ndarray = field(repr=False)   # (m,) Gauss weights on [0, 1], summing to 1
    L: np.ndarray = field(repr=False)         # (m, m+1) basis values at the collocation points
    D: np.ndarray = field(repr=False)         # (m, m+1) basis derivatives at the collocation points
    top: np.ndarray = field(repr=False)       # (m+1,) m-th derivatives of the basis (constants)

    def basis(self, s: np.ndarray) -> np.ndarray:
        """Lagrange basis at local coordinates s in [0, 1]: shape (len(s), m+1)."""
        s = np.asarray(s, dtype=float)[:, None]
        z = self.nodes
        out = np.ones((s.shape[0], len(z)))
        for i in range(len(z)):
            for k in range(len(z)):
                if k != i:
                    out[:, i] *= (s[:, 0] - z[k]) / (z[i] - z[k])
        return out

    def basis_derivative(self, s: np.ndarray) -> np.ndarray:
        s = np.asarray(s, dtype=float)
        z = self.nodes
        out = np.zeros((len(s), len(z)))
        for i in range(len(z)):
            for k in range(len(z)):
                if k == i:
                    continue
                term = np.full(len(s), 1.0 / (z[i] - z[k]))
                for l in range(len(z)):
                    if l != i and l != k:
                        term *= (s - z[l]) / (z[i] - z[l])
                out[:, i] += term
        return out


@functools.lru_cache(maxsize=8)
def scheme(degree: int = DEFAULT_DEGREE) -> Scheme:
    m = int(degree)
    if m < 2:
        raise ValueError("collocation degree must be at least 2")
    nodes = np.linspace(0.0, 1.0, m + 1)
    g, w = np.polynomial.legendre.leggauss(m)
    points, weights = 0.5 * (g + 1.0), 0.5 * w
    proto = Scheme(m, nodes, points, weights, np.zeros(0), np.zeros(0), np.zeros(0))
    L = proto.basis(points)
    D = proto.basis_derivative(points)
    top = np.array([math.factorial(m) / np.prod([nodes[i] - nodes[k] for k in range(m + 1) if k != i])
                    for i in range(m + 1)])
    return Scheme(m, nodes, points, weights, L, D, top)


@functools.lru_cache(maxsize=16)
def node_index(n_intervals: int, degree: int) -> np.ndarray:
    """(N, m+1) indices of the nodes of each interval into the N m stored nodes (periodic wrap)."""
    j = np.arange(n_intervals)[:, None] * degree + np.arange(degree + 1)[None, :]
    return j % (n_intervals * degree)


@dataclass(frozen=True)
class Orbit:
    """A periodic orbit as a continuous periodic piecewise polynomial in scaled time tau in [0, 1]."""

    mesh: np.ndarray      # (N+1,), mesh[0] = 0, mesh[-1] = 1
    nodes: np.ndarray     # (N m, n) values at the representation nodes; node N m would be node 0 again
    period: float         # s
    degree: int = DEFAULT_DEGREE

    @property
    def intervals(self) -> int:
        return len(self.mesh) - 1

    @property
    def n(self) -> int:
        return self.nodes.shape[1]

    @property
    def widths(self) -> np.ndarray:
        return np.diff(self.mesh)

    def interval_values(self) -> np.ndarray:
        """(N, m+1, n) node values per interval."""
        return self.nodes[node_index(self.intervals, self.degree)]

    def node_times(self) -> np.ndarray:
        """Scaled times of the N m stored nodes."""
        sch = scheme(self.degree)
        return (self.mesh[:-1, None] + self.widths[:, None] * sch.nodes[None, :-1]).ravel()

    def at(self, tau: np.ndarray) -> np.ndarray:
        """States at scaled times tau (wrapped into [0, 1)): shape (len(tau), n)."""
        tau = np.mod(np.asarray(tau, dtype=float), 1.0)
        j = np.clip(np.searchsorted(self.mesh, tau, side="right") - 1, 0, self.intervals - 1)
        s = (tau - self.mesh[j]) / self.widths[j]
        B = scheme(self.degree).basis(s)                        # (len, m+1)
        return np.einsum("ti,tin->tn", B, self.interval_values()[j])

    def sample(self, per_interval: int = 16) -> tuple[np.ndarray, np.ndarray]:
        """(tau, x) on ``per_interval`` equally spaced points in every mesh interval: one period, tau = 1
        (the same state as tau = 0) left out."""
        s = np.arange(per_interval) / per_interval
        B = scheme(self.degree).basis(s)
        x = np.einsum("ti,jin->jtn", B, self.interval_values()).reshape(-1, self.n)
        tau = (self.mesh[:-1, None] + self.widths[:, None] * s[None, :]).ravel()
        return tau, x

    def maxima(self, per_interval: int = 16, about: np.ndarray | None = None) -> np.ndarray:
        """max over the orbit of |x_i| (or of |x_i - about_i|: about an equilibrium off x = 0) for every state,
        refined by a parabola through the largest sample and its neighbours (error O(h^4) of the sample spacing,
        below 1e-9 relative here)."""
        tau, x = self.sample(per_interval)
        a = np.abs(x if about is None else x - np.asarray(about)[None, :])
        k = np.argmax(a, axis=0)
        cols = np.arange(self.n)
        km, kp = (k - 1) % len(tau), (k + 1) % len(tau)
        y0, ym, yp = a[k, cols], a[km, cols], a[kp, cols]
        # Uneven spacing only across mesh points; use the local spacings.
        hm = np.mod(tau[k] - tau[km], 1.0)
        hp = np.mod(tau[kp] - tau[k], 1.0)
        # Parabola through (-hm, ym), (0, y0), (hp, yp): vertex value.
        d1 = (yp - y0) / hp
        d0 = (y0 - ym) / hm
        c2 = (d1 - d0) / (hm + hp)
        c1 = d0 + c2 * hm
        with np.errstate(divide="ignore", invalid="ignore"):
            peak = np.where(c2 < 0.0, y0 - c1 * c1 / (4.0 * c2), y0)
        return np.maximum(peak, y0)

    def mean_square(self) -> np.ndarray:
        """Time averages of x_i^2 by Gauss quadrature (exact for the polynomial)."""
        sch = scheme(self.degree)
        Xc = np.einsum("ki,jin->jkn", sch.L, self.interval_values())
        return np.einsum("j,k,jkn->n", self.widths, sch.weights, Xc ** 2)

    def variance(self) -> np.ndarray:
        """Time averages of (x_i - mean x_i)^2 by Gauss quadrature: the size of an orbit about an equilibrium
        off x = 0."""
        sch = scheme(self.degree)
        Xc = np.einsum("ki,jin->jkn", sch.L, self.interval_values())
        mean = np.einsum("j,k,jkn->n", self.widths, sch.weights, Xc)
        return np.einsum("j,k,jkn->n", self.widths, sch.weights, (Xc - mean) ** 2)


def uniform_mesh(n_intervals: int) -> np.ndarray:
    return np.linspace(0.0, 1.0, n_intervals + 1)


def orbit_from_function(fun, period: float, mesh: np.ndarray, degree: int = DEFAULT_DEGREE) -> Orbit:
    """Orbit whose nodes sample ``fun(tau) -> (len, n)``."""
    sch = scheme(degree)
    widths = np.diff(mesh)
    tau = (mesh[:-1, None] + widths[:, None] * sch.nodes[None, :-1]).ravel()
    return Orbit(mesh=np.asarray(mesh, float), nodes=np.asarray(fun(tau), float), period=float(period),
                 degree=degree)


def collocation_states(Y: np.ndarray, sch: Scheme) -> np.ndarray:
    """(N, m, n) states at the collocation points from interval node values Y (N, m+1, n)."""
    return np.einsum("ki,jin->jkn", sch.L, Y)


def collocation_derivatives(Y: np.ndarray, widths: np.ndarray, sch: Scheme) -> np.ndarray:
    """(N, m, n) d/dtau at the collocation points."""
    return np.einsum("ki,jin->jkn", sch.D, Y) / widths[:, None, None]


def block_jacobians(Jf: np.ndarray, widths: np.ndarray, period: float, sch: Scheme) -> np.ndarray:
    """d(collocation residual)/d(node values), per interval: (N, m, n, m+1, n).

    Residual at point k of interval j: sum_i D[k, i] Y[j, i] / h_j - T f(sum_i L[k, i] Y[j, i]).
    """
    N, m, n, _ = Jf.shape
    eye = np.eye(n)
    B = (sch.D[None, :, None, :, None] / widths[:, None, None, None, None]) * eye[None, None, :, None, :]
    B = B - period * sch.L[None, :, None, :, None] * Jf[:, :, :, None, :]
    return B


@functools.lru_cache(maxsize=16)
def block_pattern(n_intervals: int, degree: int, n: int) -> tuple[np.ndarray, np.ndarray]:
    """Row and column indices of the entries of :func:`block_jacobians` (flattened in C order)."""
    N, m = n_intervals, degree
    rows = (np.arange(N)[:, None, None, None, None] * m * n + np.arange(m)[None, :, None, None, None] * n
            + np.arange(n)[None, None, :, None, None])
    cols = node_index(N, m)[:, None, None, :, None] * n + np.arange(n)[None, None, None, None, :]
    shape = (N, m, n, m + 1, n)
    return np.broadcast_to(rows, shape).ravel().copy(), np.broadcast_to(cols, shape).ravel().copy()


def _interval_solves(B: np.ndarray, columns: np.ndarray) -> np.ndarray:
    """Solve each interval's collocation equations for its interior and right nodes: [B_I B_R]^-1 columns.

    B (N, m, n, m+1, n); columns (N, m n, c).  Returns (N, m n, c): interior nodes first, right node last.
    """
    N, m, n = B.shape[0], B.shape[1], B.shape[2]
    Bf = B.reshape(N, m * n, (m + 1) * n)
    return np.linalg.solve(Bf[:, :, n:], columns)


def transfer_matrices(B: np.ndarray) -> np.ndarray:
    """Per-interval transfer matrices of the discretised variational equation, by condensation: (N, n, n).

    For v' = T A(tau) v collocated like the orbit, the m n equations of interval j fix its interior and right
    nodes from its left node: v_right = P_j v_left.
    """
    N, m, n = B.shape[0], B.shape[1], B.shape[2]
    left = B.reshape(N, m * n, (m + 1) * n)[:, :, :n]
    return _interval_solves(B, -left)[:, -n:, :]


def floquet_eigenfunction(B: np.ndarray, multiplier: complex) -> np.ndarray:
    """Node values (N m, n) of the solution of the discretised variational equation whose monodromy image is
    ``multiplier`` times itself (the Floquet eigenfunction, real part), from the eigenvector of the monodromy
    propagated through every interval's condensed solution; it does not close on itself: the next value after
    the last stored node would be ``multiplier`` times node 0."""
    N, m, n = B.shape[0], B.shape[1], B.shape[2]
    left = B.reshape(N, m * n, (m + 1) * n)[:, :, :n]
    W = _interval_solves(B, -left)                        # (N, m n, n): interior and right nodes from the left
    M = np.eye(n)
    for Pj in W[:, -n:, :]:
        M = Pj @ M
    lam, vecs = np.linalg.eig(M)
    v = vecs[:, int(np.argmin(np.abs(lam - multiplier)))]
    v = (v / v[np.argmax(np.abs(v))]).real                # real for a real multiplier
    nodes = np.empty((N, m, n))
    for j in range(N):
        nodes[j, 0] = v
        inner = W[j] @ v
        nodes[j, 1:] = inner[:-n].reshape(m - 1, n)
        v = inner[-n:]
    return nodes.reshape(N * m, n)


def monodromy(B: np.ndarray) -> np.ndarray:
    """Monodromy matrix (product of the transfer matrices over one period)."""
    P = transfer_matrices(B)
    M = np.eye(P.shape[1])
    for Pj in P:
        M = Pj @ M
    return M


@functools.lru_cache(maxsize=16)
def _reduced_pattern(N: int, n: int):
    """CSC structure of the condensed system in the unknowns (x_0, ..., x_{N-1}, T, p) and the permutation
    from the stacking order of :meth:`CondensedJacobian.solve_bordered` to CSC order."""
    size = N * n + 2
    blk = np.arange(N)[:, None, None] * n
    a = np.arange(n)
    rows_P = np.broadcast_to(blk + a[None, :, None], (N, n, n)).ravel()
    cols_P = np.broadcast_to(blk + a[None, None, :], (N, n, n)).ravel()
    rows_I = (np.arange(N)[:, None] * n + a[None, :]).ravel()
    cols_I = (((np.arange(N)[:, None] + 1) % N) * n + a[None, :]).ravel()
    rows_c = np.arange(N * n)
    border_rows = np.repeat([N * n, N * n + 1], size)
    border_cols = np.tile(np.arange(size), 2)
    rows = np.concatenate([rows_P, rows_I, rows_c, rows_c, border_rows])
    cols = np.concatenate([cols_P, cols_I, np.full(N * n, N * n), np.full(N * n, N * n + 1), border_cols])
    order = np.lexsort((rows, cols))
    indptr = np.searchsorted(cols[order], np.arange(size + 1))
    return order, rows[order].astype(np.int32), indptr.astype(np.int32), size


class CondensedJacobian:
    """The Newton matrix of the periodic collocation problem in block form, solved by condensation.

    Rows: collocation (N m n), phase condition; columns: node values (N m n), T, p.  Each interval's equations
    are solved for its interior and right nodes in terms of its left node, T and p (one batched dense solve of
    N (m n) x (m n) systems); what remains is a cyclic block-bidiagonal system in the N mesh-point values with
    two dense border rows (phase condition and the continuation's bordering row) and two dense columns (T, p),
    solved as described in :meth:`_solve_reduced`.  This is the condensation of parameters of AUTO (Doedel's
    notes; Ascher, Mattheij & Russell 1995, section 5.6.2); the per-interval solutions are the transfer
    matrices whose product is the monodromy matrix.  It is what
    :func:`bifurcation.continuation.correct` sees as the Jacobian: it only needs ``shape`` and
    :meth:`solve_bordered`.
    """

    def __init__(self, B: np.ndarray, col_T: np.ndarray, col_p: np.ndarray, phase: np.ndarray):
        self.B = B                    # (N, m, n, m+1, n)
        self.col_T = col_T            # (N, m, n)
        self.col_p = col_p            # (N, m, n)
        self.phase = phase            # (N m, n) gradient of the phase condition in the node values
        N, m, n = B.shape[0], B.shape[1], B.shape[2]
        self.dims = (N, m, n)
        self.shape = (N * m * n + 1, N * m * n + 2)
        self._solves = 0
        self._solved = None     # (inverses of the interval blocks, their solutions for the Jacobian's columns)

    # From this solve on with one matrix, its interval blocks are inverted: an inversion costs about 2.5 batched
    # solves (measured for 32 and 56 unknowns per interval) and then each further solve is a product.  Chord
    # iterations solve with one Jacobian 1-13 times (the full-geometry MBS branch: 41 of 85 once, 12 seven times or
    # more; the reduced model's 2.5 bar branch: 22 of 65 once, 22 twice).
    INVERT_AT = 3

    def solve_bordered(self, row: np.ndarray, rhs: np.ndarray) -> np.ndarray:
        """Solve [J; row] x = rhs."""
        N, m, n = self.dims
        K = N * m * n
        Bf = self.B.reshape(N, m * n, (m + 1) * n)
        self._solves += 1
        # the columns of the left node, T and p, then the right-hand side's
        fixed = [-Bf[:, :, :n], -self.col_T.reshape(N, m * n, 1), -self.col_p.reshape(N, m * n, 1)]
        column = rhs[:K].reshape(N, m * n, 1)
        try:
            if self._solves < self.INVERT_AT:
                W = _interval_solves(self.B, np.concatenate(fixed + [column], axis=2))   # (N, m n, n + 3)
            else:
                if self._solved is None:
                    inverse = np.linalg.inv(Bf[:, :, n:])
                    self._solved = (inverse, inverse @ np.concatenate(fixed, axis=2))
                inverse, solved = self._solved
                W = np.concatenate([solved, inverse @ column], axis=2)
        except np.linalg.LinAlgError:
            return np.full(K + 2, np.nan)
        top, bottom = W[:, :-n, :], W[:, -n:, :]            # interior nodes, right node
        reduced_rhs = np.empty(N * n + 2)
        reduced_rhs[:N * n] = bottom[:, :, n + 2].ravel()
        border = []
        for b_nodes, b_T, b_p, b_rhs in ((self.phase, 0.0, 0.0, rhs[K]),
                                         (row[:K].reshape(-1, n), row[K], row[K + 1], rhs[K + 1])):
            b = b_nodes.reshape(N, m, n)
            bz = b[:, 1:, :].reshape(N, (m - 1) * n)
            c = np.einsum("ji,jic->jc", bz, top)            # (N, n + 3)
            coef = np.concatenate([(b[:, 0, :] + c[:, :n]).ravel(), [b_T + c[:, n].sum(), b_p + c[:, n + 1].sum()]])
            border.append(coef)
            reduced_rhs[N * n + len(border) - 1] = b_rhs - c[:, n + 2].sum()
        y = self._solve_reduced(bottom, border, reduced_rhs)
        if y is None:
            return np.full(K + 2, np.nan)
        xs = y[:N * n].reshape(N, n)
        dT, dp = y[N * n], y[N * n + 1]
        z = (np.einsum("jic,jc->ji", top[:, :, :n], xs) + top[:, :, n] * dT + top[:, :, n + 1] * dp
             + top[:, :, n + 2])                            # (N, (m-1) n)
        nodes = np.concatenate([xs[:, None, :], z.reshape(N, m - 1, n)], axis=1).reshape(K)
        return np.concatenate([nodes, [dT, dp]])


    def _solve_reduced(self, bottom: np.ndarray, border: list[np.ndarray], reduced_rhs: np.ndarray):
        """Solve the condensed cyclic system x_(j+1) = P_j x_j + a_j T + b_j p + g_j, x_N = x_0, plus the two
        border rows, for (x_0, ..., x_(N-1), T, p).

        The recursion x_j = R_j (x_0, T, p, 1) reduces it to n + 2 equations in (x_0, T, p) (the closure and the
        border rows).  This is the shooting form of the condensed system, cheap and accurate while the partial
        products R_j stay moderate (they are bounded by the Floquet multipliers, at most about 2 for the shimmy
        cycles); when they grow beyond RECURSION_LIMIT the full cyclic system is factorised by SuperLU with
        partial pivoting instead, which is stable for any multipliers.
        """
        N, m, n = self.dims
        R = np.empty((N + 1, n, n + 3))
        R[0] = 0.0
        R[0, :, :n] = np.eye(n)
        for j in range(N):
            R[j + 1] = bottom[j, :, :n] @ R[j]
            R[j + 1, :, n:] += bottom[j, :, n:]
        if np.max(np.abs(R)) < RECURSION_LIMIT:
            A = np.empty((n + 2, n + 2))
            b = np.empty(n + 2)
            A[:n] = R[N, :, :n + 2]
            A[:n, :n] -= np.eye(n)
            b[:n] = -R[N, :, n + 2]
            for i, coef in enumerate(border):
                proj = np.einsum("ja,jac->c", coef[:N * n].reshape(N, n), R[:N])
                A[n + i, :n] = proj[:n]
                A[n + i, n] = proj[n] + coef[N * n]
                A[n + i, n + 1] = proj[n + 1] + coef[N * n + 1]
                b[n + i] = reduced_rhs[N * n + i] - proj[n + 2]
            try:
                y0 = np.linalg.solve(A, b)
            except np.linalg.LinAlgError:
                return None
            xs = np.einsum("jac,c->ja", R[:N], np.append(y0, 1.0))
            return np.concatenate([xs.ravel(), y0[n:]])
        data = np.concatenate([(-bottom[:, :, :n]).ravel(), np.ones(N * n), -bottom[:, :, n].ravel(),
                               -bottom[:, :, n + 1].ravel(), border[0], border[1]])
        order, indices, indptr, size = _reduced_pattern(N, n)
        A = scipy.sparse.csc_matrix((data[order], indices, indptr), shape=(size, size))
        try:
            return factorize(A).solve(reduced_rhs)
        except RuntimeError:  # exactly singular
            return None


def collocation_residual(orbit: Orbit, rhs) -> float:
    """max over the collocation points of |x'(tau) - T f(x(tau))|, relative to max |x'(tau)|: how well the orbit
    solves the collocation equations of the right-hand side ``rhs(X) -> f`` (states and values as columns, (n, k)),
    which may be another evaluator of the equations than the one the orbit was continued with."""
    sch = scheme(orbit.degree)
    Y = orbit.interval_values()
    Xc = collocation_states(Y, sch)
    dX = collocation_derivatives(Y, orbit.widths, sch)
    f = np.asarray(rhs(Xc.reshape(-1, orbit.n).T)).T.reshape(Xc.shape)
    return float(np.max(np.abs(dX - orbit.period * f)) / np.max(np.abs(dX)))
