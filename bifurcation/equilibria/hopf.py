"""Hopf points of the equilibrium in a window of the primary parameter p.

Seeding is exact rather than by sampling: the Jacobian at the equilibrium is often affine in p, A(p) = A0 + p A1,
so the bialternate product 2A(p) (.) I (whose eigenvalues are the sums lambda_i + lambda_j, i < j) is an affine
matrix pencil, and *every* p with an eigenvalue pair summing to zero (a Hopf point or a neutral saddle) is a
finite real generalized eigenvalue of that pencil (Govaerts, Numerical Methods for Bifurcations of Dynamical
Equilibria, SIAM 2000, ch. 4; Guckenheimer, Myers & Sturmfels, SIAM J. Numer. Anal. 34, 1997).  Close pairs of Hopf
points cannot slip between grid nodes.  When A is not affine in p the seeding falls back to an eigenvalue scan.
Each seed is then polished by Newton's method on the standard defining system
(A(p) - i w I) v = 0, c^H v = 1 in the unknowns (Re v, Im v, w, p) (Kuznetsov 2004, section 10.2.2), and its
first Lyapunov coefficient is computed (:mod:`bifurcation.equilibria.normal_form`), and where f has a kink at the
equilibrium (once but not twice differentiable) the quadratic coefficient that takes l1's place there.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass, field

import numpy as np
import scipy.linalg

from bifurcation.messages import Message
from bifurcation.equilibria import normal_form
from bifurcation.equilibria.normal_form import first_lyapunov_coefficient
from bifurcation.problem import Family, clip_window, describe
from bifurcation.special_points import ConvergenceError, Criticality

NEWTON_MAX_ITER = 30
PRIMARY_STEPS_PER_SCALE = 1000.0   # the step of dA/dp is primary_scale / this: relative, whatever the unit of p


@dataclass(frozen=True)
class HopfPoint:
    """A Hopf point of the equilibrium at the primary parameter ``p`` and fixed second parameter ``q`` (SI units)."""

    p: float               # the primary parameter
    q: float               # the family's second parameter
    omega: float               # rad/s
    first_lyapunov: float
    eigenvector: np.ndarray = field(compare=False, repr=False)
    newton_iterations: int = 0
    # where f is once but not twice differentiable at the equilibrium (the family's ``twice_differentiable`` says
    # so), the quadratic coefficient a of the amplitude equation (:func:`kink_coefficient`), which decides the
    # criticality at vanishing amplitude that l1 cannot; NaN where f is smooth there or l1 was not asked for
    kink: float = float("nan")

    @property
    def frequency_hz(self) -> float:
        return self.omega / (2.0 * np.pi)

    @property
    def criticality(self) -> Criticality | None:
        """By l1's sign; None when l1 was not computed (a vector field that cannot be evaluated at complex states).
        Where f has a kink at the equilibrium l1's sign is no criticality: :attr:`kink_criticality` is."""
        if np.isnan(self.first_lyapunov):
            return None
        return Criticality.SUPERCRITICAL if self.first_lyapunov < 0.0 else Criticality.SUBCRITICAL


    @property
    def kink_criticality(self) -> Criticality | None:
        """At vanishing amplitude, where f has a kink at the equilibrium: a > 0 subcritical, a < 0 supercritical;
        None where f is smooth there (or a is 0)."""
        if not np.isfinite(self.kink) or self.kink == 0.0:
            return None
        return Criticality.SUPERCRITICAL if self.kink < 0.0 else Criticality.SUBCRITICAL


def eigenvalues(family: Family, p: float, q: float) -> np.ndarray:
    """Eigenvalues at the equilibrium, sorted by decreasing real part."""
    lam = np.linalg.eigvals(family.linear_matrix(p, q))
    return lam[np.argsort(-lam.real)]


def primary_derivative(family: Family, p: float, q: float, A: np.ndarray | None = None) -> np.ndarray:
    """dA/dp by a forward difference of a thousandth of the family's ``primary_scale`` (so the same relative step
    whatever p's unit).  One-sided: where A is affine in p (module docstring) the difference quotient is exact."""
    h = family.primary_scale / PRIMARY_STEPS_PER_SCALE
    if A is None:
        A = family.linear_matrix(p, q)
    return (family.linear_matrix(p + h, q) - A) / h


def parameter_derivative(family: Family, p: float, q: float, scale: float,
                         A: np.ndarray | None = None) -> np.ndarray:
    """dA/dq by a forward difference (relative error ~1e-7).  Only Newton's convergence rate depends on it: the
    solutions of the defining systems do not, and neither does a fold, where the (v, omega, p) block of the
    Jacobian is singular whatever this column holds."""
    h = 1e-7 * scale
    if A is None:
        A = family.linear_matrix(p, q)
    return (family.linear_matrix(p, q + h) - A) / h


def hopf_residual(A: np.ndarray, vr, vi, omega, cr, ci) -> np.ndarray:
    return np.concatenate([A @ vr + omega * vi, A @ vi - omega * vr, [cr @ vr + ci @ vi - 1.0, cr @ vi - ci @ vr]])


def hopf_jacobian(A, A_p, vr, vi, omega, cr, ci, A_q=None) -> np.ndarray:
    """Jacobian of :func:`hopf_residual` in (vr, vi, omega, p[, q])."""
    n = A.shape[0]
    I = np.eye(n)
    cols = 2 * n + 2 + (A_q is not None)
    J = np.zeros((2 * n + 2, cols))
    J[:n, :n], J[:n, n:2 * n], J[:n, 2 * n], J[:n, 2 * n + 1] = A, omega * I, vi, A_p @ vr
    J[n:2 * n, :n], J[n:2 * n, n:2 * n], J[n:2 * n, 2 * n], J[n:2 * n, 2 * n + 1] = -omega * I, A, -vr, A_p @ vi
    J[2 * n, :n], J[2 * n, n:2 * n] = cr, ci
    J[2 * n + 1, :n], J[2 * n + 1, n:2 * n] = -ci, cr
    if A_q is not None:
        J[:n, -1], J[n:2 * n, -1] = A_q @ vr, A_q @ vi
    return J


def locate_hopf(family: Family, q: float, p: float, omega: float, v: np.ndarray,
                tol: float = 1e-11, lyapunov: bool = True) -> HopfPoint:
    """Newton on the Hopf defining system at fixed q, from a guess (p, omega, eigenvector v).

    With ``lyapunov`` the first Lyapunov coefficient comes from the family's multilinear forms.
    """
    n = family.n
    v = np.asarray(v, dtype=complex) / np.linalg.norm(v)
    cr, ci = v.real.copy(), v.imag.copy()
    y = np.concatenate([v.real, v.imag, [omega, p]])
    for it in range(1, NEWTON_MAX_ITER + 1):
        vr, vi, w, p_k = y[:n], y[n:2 * n], y[2 * n], y[2 * n + 1]
        A = family.linear_matrix(p_k, q)
        r = hopf_residual(A, vr, vi, w, cr, ci)
        J = hopf_jacobian(A, primary_derivative(family, p_k, q, A), vr, vi, w, cr, ci)
        dy = np.linalg.solve(J, -r)
        y = y + dy
        if np.max(np.abs(dy[2 * n:])) < tol * (1.0 + abs(y[2 * n + 1])) and np.max(np.abs(r)) < 1e-8:
            break
    else:
        raise ConvergenceError(Message.of("Hopf Newton did not converge near ", describe(family, p, q),
                                          f" (last step {np.max(np.abs(dy)):.2e})"))
    vr, vi, w, p_hopf = y[:n], y[n:2 * n], abs(y[2 * n]), y[2 * n + 1]
    vec = vr + 1j * vi if y[2 * n] > 0 else vr - 1j * vi
    l1 = kink = float("nan")
    if lyapunov:
        A = family.linear_matrix(p_hopf, q)
        x0 = family.equilibrium(p_hopf, q)
        l1 = first_lyapunov_coefficient(family.multilinear_forms(x0, p_hopf, q), A, w, vec)
        smooth = getattr(family, "twice_differentiable", None)
        if smooth is not None and smooth(x0, p_hopf, q) is False:
            kink = kink_coefficient(family, x0, float(p_hopf), q, A, w, vec)[0]
    return HopfPoint(p=float(p_hopf), q=float(q), omega=float(w), first_lyapunov=l1, eigenvector=vec,
                     newton_iterations=it, kink=kink)


def kink_coefficient(family: Family, x0: np.ndarray, p: float, q: float, A: np.ndarray, omega: float,
                     v: np.ndarray) -> tuple[float, float]:
    """(a, its quadrature error) at a Hopf point of ``family`` (A v = i omega v at the equilibrium x0) whose f has
    a kink there, from the family's one-sided exact Jacobians
    (:func:`bifurcation.equilibria.normal_form.kink_coefficient`)."""
    def jacobians(X: np.ndarray) -> np.ndarray:
        return family.rhs_and_jacobians(X, p, q, kink_rows=False)[1]
    return normal_form.kink_coefficient(jacobians, x0, A, omega, v)


@functools.lru_cache(maxsize=8)
def _antisymmetric_basis(n: int) -> np.ndarray:
    """Orthonormal basis of vec(X) (column-major) for antisymmetric n x n X, shape (n*n, n(n-1)/2)."""
    cols = []
    for i in range(n):
        for j in range(i + 1, n):
            E = np.zeros((n, n))
            E[i, j], E[j, i] = 1.0, -1.0
            cols.append(E.reshape(-1, order="F") / np.sqrt(2.0))
    return np.array(cols).T


def bialternate(A: np.ndarray) -> np.ndarray:
    """2A (.) I restricted to antisymmetric matrices: X -> A X + X A^T; eigenvalues lambda_i + lambda_j, i < j."""
    n = A.shape[0]
    P = _antisymmetric_basis(n)
    I = np.eye(n)
    return P.T @ (np.kron(A, I) + np.kron(I, A)) @ P


def _hopf_pair(A: np.ndarray) -> tuple[float, np.ndarray] | None:
    """The (omega, eigenvector) of the eigenvalue pair summing to ~0 if it is imaginary, None for a saddle."""
    lam, vecs = np.linalg.eig(A)
    s = np.abs(lam[:, None] + lam[None, :]) + np.diag(np.full(len(lam), np.inf))
    i, j = np.unravel_index(np.argmin(s), s.shape)
    prod = lam[i] * lam[j]
    if prod.real <= 0.0 or abs(lam[i].imag) < 1e-9:
        return None  # neutral saddle (+-mu real) or a double zero
    k = i if lam[i].imag > 0 else j
    return float(lam[k].imag), vecs[:, k]


def hopf_seeds(family: Family, q: float, p_min: float, p_max: float) -> list[float]:
    """The p in [p_min, p_max] where two eigenvalues sum to zero (Hopf points and neutral saddles)."""
    A0 = family.linear_matrix(0.0, q)
    A1 = family.linear_matrix(1.0, q) - A0
    Avmax = family.linear_matrix(p_max, q)
    if np.max(np.abs(A0 + p_max * A1 - Avmax)) <= 1e-9 * np.max(np.abs(Avmax)):
        B0, B1 = bialternate(A0), bialternate(A1)
        roots = scipy.linalg.eigvals(B0, -B1)
        finite = roots[np.isfinite(roots)]
        real = finite[np.abs(finite.imag) <= 1e-7 * (1.0 + np.abs(finite.real))].real
        return sorted(float(p) for p in real if p_min - 1e-9 <= p <= p_max + 1e-9)
    return _scan_hopf_seeds(family, q, p_min, p_max)


def _scan_hopf_seeds(family: Family, q: float, p_min: float, p_max: float, n: int = 801) -> list[float]:
    grid = np.linspace(p_min, p_max, n)
    unstable = np.array([np.sum(np.linalg.eigvals(family.linear_matrix(p, q)).real > 0) for p in grid])
    idx = np.nonzero(np.diff(unstable))[0]
    return [0.5 * (grid[i] + grid[i + 1]) for i in idx]


def find_hopf_points(family: Family, q: float, p_min: float, p_max: float,
                lyapunov: bool = True) -> tuple[HopfPoint, ...]:
    """Every Hopf point of the equilibrium with p_min <= p <= p_max at the second parameter q, by p.

    The window never reaches below the family's ``primary_min``.

    ``family`` needs ``n``, ``validate(q)`` and ``linear_matrix(p, q)`` (and what :func:`locate_hopf` needs for l1).
    """
    family.validate(q)
    p_min, p_max = clip_window(family, p_min, p_max)
    found: list[HopfPoint] = []
    for p in hopf_seeds(family, q, p_min, p_max):
        pair = _hopf_pair(family.linear_matrix(p, q))
        if pair is None:
            continue
        point = locate_hopf(family, q, p, *pair, lyapunov=lyapunov)
        if p_min <= point.p <= p_max and not any(abs(point.p - h.p) < 1e-7 and
                                             abs(point.omega - h.omega) < 1e-6 for h in found):
            found.append(point)
    return tuple(sorted(found, key=lambda h: h.p))
