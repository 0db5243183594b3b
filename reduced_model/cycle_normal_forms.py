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

c = 0 on a period-doubling curve is a generalized period-doubling point.  psi comes from the transposed
bordered variational system (the left null vector of the collocation rows, which already carries the Gauss
quadrature weights, so that sums over collocation points are the integrals); B and C from central differences of
the exact (complex-step) Jacobians along the directions.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse.linalg

from . import collocation as col

C_STEP = 1e-3       # second differences of Jacobians for C: step relative to the direction's scaled size
B_STEP = 1e-5       # first (central) differences for B


def _directional(jac, xk: np.ndarray, d: np.ndarray, scales: np.ndarray, step: float):
    """(B(d, .), C(d, d, .), J) at every point: central first and second differences of the Jacobians along d
    scaled to unit size (step ``step``), multiplied back by the size (the forms are linear and quadratic in d)."""
    size = float(np.max(np.abs(d) / scales))
    J0 = jac(xk)
    if not size > 0.0:          # a zero direction (e.g. h2 = 0 when B(v1, v1) = 0)
        return np.zeros_like(J0), np.zeros_like(J0), J0
    unit = d / size
    Jp, Jm = jac(xk + step * unit), jac(xk - step * unit)
    return size * (Jp - Jm) / (2.0 * step), size ** 2 * (Jp - 2.0 * J0 + Jm) / step ** 2, J0


def period_doubling_coefficient(system, U: np.ndarray) -> float:
    """The period-doubling normal-form coefficient c (module docstring) of the cycle of a period-doubling
    :class:`reduced_model.cycle_fold_system.FoldSystem` at its unknowns ``U`` (a point of its curve)."""
    cp, K = system.cp, system.K
    N, m, n = cp.intervals, cp.degree, cp.n
    _, A, _, _, e, z, w = system.evaluate(U)
    T, V, q = e["T"], e["V"], e["q"]
    xk = e["Xc"].reshape(-1, n)
    quad = (cp.widths[:, None] * cp.sch.weights[None, :]).reshape(-1)          # Gauss weights on [0, 1]

    def jac(X):
        return col.values_and_jacobians(lambda Z: system.family.rhs(Z, V, q), X)[1]

    def at_points(nodes: np.ndarray, signs: np.ndarray) -> np.ndarray:
        Y = nodes.reshape(-1, n)[col.node_index(N, m)] * signs[:, :, None]
        return col.collocation_states(Y, cp.sch).reshape(-1, n)

    v = at_points(z[:K], system._signs())
    v = v / np.sqrt(np.einsum("k,ka,ka->", quad, v, v))
    psi = w[:K].reshape(-1, n)
    dB, dC, J0 = _directional(jac, xk, v, cp.scales, C_STEP)
    Bvv = np.einsum("kab,kb->ka", _directional(jac, xk, v, cp.scales, B_STEP)[0], v)
    Cvvv = np.einsum("kab,kb->ka", dC, v)
    sol = scipy.sparse.linalg.splu(A.tocsc()).solve(np.append(T * Bvv.ravel(), 0.0))
    alpha = -sol[K] / (2.0 * T)
    h = at_points(sol[:K], np.ones((N, m + 1)))
    Bvh = np.einsum("kab,kb->ka", _directional(jac, xk, h, cp.scales, B_STEP)[0], v)
    dv = T * np.einsum("kab,kb->ka", J0, v)
    num = np.sum(psi * (T * (Cvvv + 3.0 * Bvh) - 6.0 * alpha * dv))
    return float(num / (6.0 * T * np.sum(psi * v)))
