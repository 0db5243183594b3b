"""Normal-form coefficients of cycle bifurcations on the collocation discretisation (periodic normalization).

Kuznetsov, Govaerts, Doedel & Dhooge, "Numerical periodic normalization for codim 1 bifurcations of limit
cycles", SIAM J. Numer. Anal. 43 (2005) 1407-1435, section 4 (period doubling), as in MatCont's ``nf_PD``.  On the
centre manifold of a period-doubling cycle x0 (period T, time tau in [0, 1]),

    x = x0(tau) + xi v1(tau) + xi^2 / 2 h2(tau) + xi^3 / 6 h3(tau),  dtau/dt = (1 + alpha xi^2) / T,  dxi/dt = c xi^3,

with v1 the antiperiodic eigenfunction (v1' = T f_x v1, v1(1) = -v1(0)), normalised to int_0^1 <v1, v1> = 1.  The
xi^2 terms give h2' - T f_x h2 = T B(v1, v1) - 2 alpha T f(x0) (periodic), solved with the periodic problem's
bordered Jacobian, whose period column -f yields alpha; the xi^3 terms' solvability against the antiperiodic
adjoint eigenfunction psi gives

    c = int <psi, T (C(v1, v1, v1) + 3 B(v1, h2)) - 6 alpha v1'> / (6 T int <psi, v1>).

c = 0 on a period-doubling curve is a generalized period-doubling point.

Neimark-Sacker (section 5 of the same paper; MatCont's ``nf_NS``): with multipliers exp(+-i theta),
x = x0 + xi v + conj + xi^2 / 2 h20 + |xi|^2 h11 + ..., dtau/dt = (1 + alpha |xi|^2) / T,
dxi/dt = i theta / T xi + d xi |xi|^2, v periodic with v' = T f_x v - i theta v, int <v, conj(v)> = 1:

    h11' - T f_x h11 = T B(v, conj v) - alpha T f(x0)         (periodic, bordered as h2 above)
    h20' + 2 i theta h20 - T f_x h20 = T B(v, v)               (periodic, regular away from 1:1, 1:2, 1:3)
    d = int <psi, T (C(v, v, conj v) + 2 B(v, h11) + B(conj v, h20)) - 2 alpha v'> / (2 T int <psi, v>),

psi the left null vector of the collocated operator d/dtau + i theta - T f_x (transposed, not conjugated, so
that the sums are the bilinear integrals).  Re d is the first Lyapunov coefficient of the torus bifurcation (up to
a positive factor); its zero on a torus curve is a Chenciner (degenerate Neimark-Sacker) point.  psi comes from the transposed
bordered variational system (the left null vector of the collocation rows, which already carries the Gauss
quadrature weights, so that sums over collocation points are the integrals); B and C from central differences of
the exact (complex-step) Jacobians along the directions.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse

from bifurcation.continuation import locate_on_step
from bifurcation.cycles import collocation as col
from bifurcation.factorization import factorize

POLE_RATIO = 1e-6   # |coefficient| at a located sign change above this fraction of its size at the step ends: a pole
C_STEP = 1e-3       # second differences of Jacobians for C: step relative to the direction's scaled size
B_STEP = 1e-5       # first (central) differences for B


def _directional(jac, xk: np.ndarray, d: np.ndarray, scales: np.ndarray, step: float, J0: np.ndarray):
    """(B(d, .), C(d, d, .)) at every point: central first and second differences of the Jacobians along d
    scaled to unit size (step ``step``), multiplied back by the size (the forms are linear and quadratic in d);
    J0 the Jacobians at xk."""
    size = float(np.max(np.abs(d) / scales))
    if not size > 0.0:          # a zero direction (e.g. h2 = 0 when B(v1, v1) = 0)
        return np.zeros_like(J0), np.zeros_like(J0)
    unit = d / size
    Jp, Jm = jac(xk + step * unit), jac(xk - step * unit)
    return size * (Jp - Jm) / (2.0 * step), size ** 2 * (Jp - 2.0 * J0 + Jm) / step ** 2


def locate_zero(branch, k: int, step: float, fun, ends: tuple[float, float]):
    """(u, located) of the zero of ``fun`` in the last step, whose values at its ends are ``ends``, or None when
    the sign change is a pole: the coefficients blow up where the bordered periodic problem is singular (a fold of
    cycles: fold-flip, fold-Neimark-Sacker), and Brent's method converges onto the pole."""
    u, _, ok = locate_on_step(branch, k, step, fun)
    if ok and not abs(fun(u)) <= POLE_RATIO * max(abs(e) for e in ends):
        return None
    return u, ok


class _Forms:
    """The cycle's collocation data at U and the multilinear forms at its collocation points."""

    def __init__(self, system, U: np.ndarray, bordered: bool = True):
        cp = system.cp
        self.cp, self.K, self.system = cp, system.K, system
        self.N, self.m, self.n = cp.intervals, cp.degree, cp.n
        # The bordered solution (z, w) only when needed: it costs a factorisation of the system's own matrix.
        if bordered:
            self.pieces = system.evaluate(U)
        else:
            kept = getattr(system, "_last_jacobian", None)     # the system's gradients read it after a cache hit
            self.pieces = system._pieces(U)
            system._last_jacobian = kept
        e = self.pieces[4]
        self.T, p, q = e["T"], e["p"], e["q"]
        self.Jf = e["Jf"]
        self.J0 = self.Jf.reshape(-1, self.n, self.n)
        self.xk = e["Xc"].reshape(-1, self.n)
        self.quad = (cp.widths[:, None] * cp.sch.weights[None, :]).reshape(-1)    # Gauss weights on [0, 1]
        self.jac = lambda X: system.family.rhs_and_jacobians(X, p, q)[1]   # noqa: E731

    def at_points(self, nodes: np.ndarray, signs: np.ndarray | None = None) -> np.ndarray:
        N, m, n = self.N, self.m, self.n
        Y = nodes.reshape(-1, n)[col.node_index(N, m)]
        if signs is not None:
            Y = Y * signs[:, :, None]
        return col.collocation_states(Y, self.cp.sch).reshape(-1, n)

    def normalized(self, v: np.ndarray) -> np.ndarray:
        return v / np.sqrt(np.einsum("k,ka,ka->", self.quad, v, np.conj(v)).real)

    def dB(self, d: np.ndarray) -> np.ndarray:
        """B(d, .) as a matrix field, d real or complex."""
        out = _directional(self.jac, self.xk, d.real, self.cp.scales, B_STEP, self.J0)[0]
        if np.iscomplexobj(d):
            out = out + 1j * _directional(self.jac, self.xk, d.imag, self.cp.scales, B_STEP, self.J0)[0]
        return out

    def B(self, d: np.ndarray, other: np.ndarray) -> np.ndarray:
        """B(d, other) at every point, d real or complex."""
        return np.einsum("kab,kb->ka", self.dB(d), other)

    def C(self, d: np.ndarray) -> np.ndarray:
        """C(d, d, .) as a matrix field, d real."""
        return _directional(self.jac, self.xk, d, self.cp.scales, C_STEP, self.J0)[1]

    def periodic_solve(self, rhs: np.ndarray) -> tuple[np.ndarray, float]:
        """h with h' - T f_x h = rhs + s f (periodic, phase-fixed) from the bordered periodic Jacobian: (h, s)."""
        A = self.pieces[1]
        sol = factorize(A).solve(np.append(rhs.ravel(), 0.0))
        return self.at_points(sol[:self.K]), float(sol[self.K])

    def shifted(self, omega: float) -> scipy.sparse.spmatrix:
        """The collocated periodic operator d/dtau + i omega - T f_x (K x K, complex)."""
        N, m, n = self.N, self.m, self.n
        rows, cols = col.block_pattern(N, m, n)
        data = col.block_jacobians(self.Jf - (1j * omega / self.T) * np.eye(n), self.cp.widths, self.T, self.cp.sch)
        return scipy.sparse.csc_matrix((data.ravel(), (rows, cols)), shape=(self.K, self.K))


def period_doubling_coefficient(system, U: np.ndarray) -> float:
    """The period-doubling normal-form coefficient c (module docstring) of the cycle of a period-doubling
    :class:`bifurcation.cycle_curves.fold.FoldSystem` at its unknowns ``U`` (a point of its curve)."""
    f = _Forms(system, U)
    z, w = f.pieces[5], f.pieces[6]
    T = f.T
    v = f.normalized(f.at_points(z[:f.K], system._signs()))
    psi = w[:f.K].reshape(-1, f.n)
    Cvvv = np.einsum("kab,kb->ka", f.C(v), v)
    h, s = f.periodic_solve(T * f.B(v, v))
    alpha = -s / (2.0 * T)
    dv = T * np.einsum("kab,kb->ka", f.Jf.reshape(-1, f.n, f.n), v)
    num = np.sum(psi * (T * (Cvvv + 3.0 * f.B(h, v)) - 6.0 * alpha * dv))
    return float(num / (6.0 * T * np.sum(psi * v)))


def neimark_sacker_coefficient(system, U: np.ndarray) -> complex:
    """The Neimark-Sacker normal-form coefficient d (module docstring) of the cycle of a
    :class:`bifurcation.cycle_curves.torus.TorusSystem` at its unknowns ``U``; Re d < 0: supercritical (a stable
    torus is born)."""
    f = _Forms(system, U, bordered=False)
    T, n, K = f.T, f.n, f.K
    theta = float(np.arccos(np.clip(U[K + 3], -1.0, 1.0)))
    lu = factorize(f.shifted(theta))
    rng = np.random.default_rng(3)
    v_nodes, psi = (rng.standard_normal(K) + 1j * rng.standard_normal(K) for _ in range(2))
    for _ in range(2):          # inverse iteration on the (nearly) singular operator: its null vectors
        v_nodes = lu.solve(v_nodes / np.linalg.norm(v_nodes))
        psi = lu.solve(psi / np.linalg.norm(psi), trans="T")
    v = f.normalized(f.at_points(v_nodes))
    psi = psi.reshape(-1, n)
    a, b = v.real, v.imag
    Ca, Cb = f.C(a), f.C(b)
    Cvvv = (np.einsum("kab,kb->ka", Ca + Cb, a) + 1j * np.einsum("kab,kb->ka", Ca + Cb, b))
    Ba, Bb = f.dB(a), f.dB(b)
    h11, s = f.periodic_solve(T * (np.einsum("kab,kb->ka", Ba, a) + np.einsum("kab,kb->ka", Bb, b)))
    alpha = -s / T
    Bvv = np.einsum("kab,kb->ka", Ba + 1j * Bb, v)
    h20 = f.at_points(factorize(f.shifted(2.0 * theta)).solve((T * Bvv).ravel()))
    dv = T * np.einsum("kab,kb->ka", f.Jf.reshape(-1, n, n), v) - 1j * theta * v
    num = np.sum(psi * (T * (Cvvv + 2.0 * f.B(h11, v) + f.B(h20, np.conj(v))) - 2.0 * alpha * dv))
    return complex(num / (2.0 * T * np.sum(psi * v)))
