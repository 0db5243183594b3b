"""Multilinear derivatives of a vector field and the first Lyapunov coefficient of a Hopf point.

Directional derivatives D^k f(x0)[d, ..., d] come from Cauchy's integral formula evaluated by the FFT on a circle
in the complex plane (Lyness & Moler, SIAM J. Numer. Anal. 4, 1967; Fornberg, ACM TOMS 7, 1981): for an analytic
vector field this is accurate to a few ulps of the Taylor coefficients, unlike nested finite differences.  Mixed
terms follow by polarisation.  The first Lyapunov coefficient is Kuznetsov's formula (Elements of Applied
Bifurcation Theory, 3rd ed., 2004, eq. 3.20), with <q, q> = 1 and <p, q> = 1; l1 < 0 means supercritical.
"""

from __future__ import annotations

import itertools
from typing import Callable, Protocol

import numpy as np

VectorField = Callable[[np.ndarray], np.ndarray]  # x of shape (n, m), complex allowed -> (n, m)


def taylor_coefficients(f: VectorField, x0: np.ndarray, directions: np.ndarray, order: int = 3,
                        radius: float = 1e-2, n_points: int = 32) -> np.ndarray:
    """Coefficients a_k (k = 0..order) of f(x0 + z d) = sum a_k z^k for each row d of ``directions``.

    Returns a complex array of shape (len(directions), order + 1, n), from one call of f on all sample points.
    ``radius`` is the largest state excursion on the sampling circle; it must lie well inside the domain where f
    is analytic (for the tyre: |alpha| << 1/B_y, about 0.1 rad).
    """
    D = np.atleast_2d(np.asarray(directions, dtype=complex))
    size = np.max(np.abs(D), axis=1)
    r = radius / np.where(size > 0.0, size, 1.0)  # a zero direction has zero derivatives whatever r is
    z = r[:, None] * np.exp(2j * np.pi * np.arange(n_points) / n_points)[None, :]          # (k, N)
    X = np.asarray(x0, dtype=complex)[:, None, None] + D.T[:, :, None] * z[None, :, :]      # (n, k, N)
    n, k = X.shape[0], X.shape[1]
    samples = f(X.reshape(n, k * n_points)).reshape(n, k, n_points)
    coeffs = np.fft.fft(samples, axis=2)[:, :, : order + 1] / n_points                      # (n, k, order+1)
    coeffs = coeffs / (r[None, :, None] ** np.arange(order + 1)[None, None, :])
    return coeffs.transpose(1, 2, 0)


def bilinear(f: VectorField, x0: np.ndarray, pairs: list[tuple[np.ndarray, np.ndarray]], **kw) -> list:
    """B(u, v) = D^2 f(x0)[u, v] for each (u, v) pair, by polarisation, in one call of f."""
    dirs = [w for u, v in pairs for w in (u + v, u - v)]
    a2 = 2.0 * taylor_coefficients(f, x0, np.array(dirs), order=2, **kw)[:, 2]
    return [0.25 * (a2[2 * i] - a2[2 * i + 1]) for i in range(len(pairs))]


class MultilinearForms(Protocol):
    """The multilinear forms of f at an equilibrium x0 that normal-form coefficients need (complex arguments)."""

    def bilinear(self, pairs: list[tuple[np.ndarray, np.ndarray]]) -> list[np.ndarray]:
        """B(u, v) = D^2 f(x0)[u, v] for each pair."""

    def hopf_terms(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(B(q, conj q), B(q, q), C(q, q, conj q))."""


class CauchyForms:
    """The forms of an analytic vector field ``f(X (n, m))`` (complex states allowed) from Taylor coefficients on
    complex circles (module docstring): one call of f per request."""

    def __init__(self, f: VectorField, x0: np.ndarray, **kw):
        self.f, self.x0, self.kw = f, x0, kw

    def bilinear(self, pairs):
        return bilinear(self.f, self.x0, pairs, **self.kw)

    def hopf_terms(self, q):
        qb = q.conj()
        # B(q, qb), B(q, q) and C(q, q, qb) = [T(q + qb) - T(q - qb) - 2 T(qb)] / 6 with T(w) = D^3 f[w, w, w].
        c = taylor_coefficients(self.f, self.x0, np.array([q + qb, q - qb, 2.0 * q, 0.0 * q, qb]), order=3, **self.kw)
        B_qqb = 0.25 * (2.0 * c[0, 2] - 2.0 * c[1, 2])
        B_qq = 0.25 * (2.0 * c[2, 2] - 2.0 * c[3, 2])
        C_qqqb = (6.0 * c[0, 3] - 6.0 * c[1, 3] - 12.0 * c[4, 3]) / 6.0
        return B_qqb, B_qq, C_qqqb


# Stencil weights (offsets -k..k) of fourth-order central differences for the second and third derivative along
# a direction (Fornberg, Math. Comp. 51, 1988): truncation O(h^4).
SECOND = {-2: -1 / 12, -1: 16 / 12, 0: -30 / 12, 1: 16 / 12, 2: -1 / 12}
THIRD = {-3: 1 / 8, -2: -1.0, -1: 13 / 8, 1: -13 / 8, 2: 1.0, 3: -1 / 8}


class RealForms:
    """Multilinear forms of complex arguments from real ones, by multilinearity: B(u, v) is the sum over the real
    and imaginary parts of u and v, C(u, v, w) likewise (MatCont's numerical multilinear forms: Dhooge, Govaerts,
    Kuznetsov, Meijer & Sautois, Math. Comput. Model. Dyn. Syst. 14, 2008).  A subclass gives the real forms
    :meth:`real_bilinear` and :meth:`real_trilinear` at its equilibrium ``x0``."""

    x0: np.ndarray

    def real_bilinear(self, a: np.ndarray, b: np.ndarray) -> np.ndarray:
        raise NotImplementedError

    def real_trilinear(self, a: np.ndarray, b: np.ndarray, c: np.ndarray) -> np.ndarray:
        raise NotImplementedError

    def _complex(self, real_form, *args: np.ndarray) -> np.ndarray:
        """A multilinear form of complex arguments as the sum over their real and imaginary parts."""
        parts = [(np.asarray(a).real, np.asarray(a).imag) for a in args]
        total = np.zeros(len(self.x0), dtype=complex)
        for choice in itertools.product((0, 1), repeat=len(args)):
            vectors = [parts[k][c] for k, c in enumerate(choice)]
            if any(not np.any(v) for v in vectors):
                continue
            total = total + (1j ** sum(choice)) * real_form(*vectors)
        return total

    def bilinear(self, pairs):
        return [self._complex(self.real_bilinear, u, v) for u, v in pairs]

    def hopf_terms(self, q):
        qb = q.conj()
        return (self._complex(self.real_bilinear, q, qb), self._complex(self.real_bilinear, q, q),
                self._complex(self.real_trilinear, q, q, qb))


class DifferenceForms(RealForms):
    """The forms of a vector field known at real states only, ``f(x (n,)) -> (n,)``, by finite differences along
    real directions, extended to complex arguments by multilinearity (:class:`RealForms`).

    A direction w is stepped so that its largest component, measured in ``scales`` (the problem's typical state
    sizes), moves ``relative_step`` of its scale: small enough that the truncation error (h / radius of
    analyticity)^4 stays small, large enough that rounding in f, divided by h^2 or h^3, does not take over."""

    def __init__(self, f, x0: np.ndarray, scales: np.ndarray, relative_step: float = 0.05):
        self.f, self.x0 = f, np.asarray(x0, dtype=float)
        self.scales, self.relative_step = np.asarray(scales, dtype=float), relative_step

    def _along(self, w: np.ndarray, stencil: dict, order: int) -> np.ndarray:
        size = np.max(np.abs(w) / self.scales)
        if size == 0.0:
            return np.zeros_like(self.x0)
        h = self.relative_step / size
        total = sum(c * np.asarray(self.f(self.x0 + k * h * w), dtype=float) for k, c in stencil.items())
        return total / h ** order

    def real_bilinear(self, a: np.ndarray, b: np.ndarray) -> np.ndarray:
        return 0.25 * (self._along(a + b, SECOND, 2) - self._along(a - b, SECOND, 2))

    def real_trilinear(self, a: np.ndarray, b: np.ndarray, c: np.ndarray) -> np.ndarray:
        T = lambda w: self._along(w, THIRD, 3)      # noqa: E731
        return (T(a + b + c) - T(a + b - c) - T(a - b + c) + T(a - b - c)) / 24.0


def first_lyapunov_coefficient(forms: MultilinearForms, A: np.ndarray, omega: float, q: np.ndarray) -> float:
    """l1 at a Hopf point with A q = i omega q (Kuznetsov 2004, eq. 3.20), for <q, q> = 1.

    With this normalisation the planar normal form x' = -w y + a x r^2, y' = w x + a y r^2 has l1 = 2a/w.
    """
    n = A.shape[0]
    q = np.asarray(q, dtype=complex)
    q = q / np.linalg.norm(q)
    p = left_eigenvector(A, omega, q)
    qb = q.conj()
    B_qqb, B_qq, C_qqqb = forms.hopf_terms(q)
    term2, term3 = forms.bilinear([(q, np.linalg.solve(A, B_qqb)),
                                   (qb, np.linalg.solve(2j * omega * np.eye(n) - A, B_qq))])
    value = np.vdot(p, C_qqqb) - 2.0 * np.vdot(p, term2) + np.vdot(p, term3)
    return float(value.real / (2.0 * omega))


def left_eigenvector(A: np.ndarray, omega: float, q: np.ndarray) -> np.ndarray:
    """p with A^T p = -i omega p and <p, q> = p^H q = 1 (A q = i omega q), from the smallest singular vector."""
    n = A.shape[0]
    _, _, vh = np.linalg.svd(A.T + 1j * omega * np.eye(n))
    p = vh[-1].conj()
    return p / np.conj(np.vdot(p, q))


def kink_coefficient(jacobians: Callable[[np.ndarray], np.ndarray], x0: np.ndarray, A: np.ndarray, omega: float,
                     q: np.ndarray, step: float = 1e-5, points: int = 1024) -> tuple[float, float]:
    """(a, its quadrature error estimate): the quadratic coefficient of the amplitude equation rho' = sigma rho +
    a rho^2 + O(rho^3) at a Hopf point (A q = i omega q, |q| = 1, x = 2 Re(z q), rho = |z|) of a vector field that
    is once but not twice differentiable at the equilibrium x0, its second derivative jumping across a surface
    through x0 (a kink such as |x_1| x_2).

    Then f(x0 + x) = f(x0) + A x + Q(x) + O(|x|^3) with Q positively homogeneous of degree 2 (Q(t x) = t^2 Q(x),
    t > 0) but Q(-x) != Q(x), and first-order averaging over the linear oscillation x = rho u(phi),
    u(phi) = 2 Re(q e^{i phi}), gives a = (1/2 pi) int Re(e^{-i phi} p^H Q(u(phi))) dphi (Sanders, Verhulst &
    Murdock, Averaging Methods in Nonlinear Dynamical Systems, 2nd ed., 2007, ch. 2; for planar continuous
    piecewise-smooth systems Kuepper & Moritz, Phil. Trans. R. Soc. A 359, 2001).  A smooth Q, a quadratic form,
    averages to exactly zero (its harmonics are 0 and 2), so a != 0 only through the kink, and then it decides the
    criticality that l1 (a cubic term) cannot: a > 0 subcritical, a < 0 supercritical, the amplitude of the
    cycles linear in the parameter's distance instead of its square root.

    Q(u) is read off exact one-sided Jacobians (``jacobians``: states (M, n) -> df/dx (M, n, n)), each on the side
    of the kink the ray x0 + t u lies on: J(x0 + t u) u = J0 u + 2 t Q(u) + 3 t^2 C(u) + O(t^3) with J0 = J(x0)
    (f is once differentiable there), so Q(u) = (4 J(x0 + s u) u - J(x0 + 2 s u) u - 3 J0 u) / (4 s) + O(s^2); the
    mean over ``points`` equally spaced phases (the trapezoidal rule; its integrand is periodic with kinks where the
    oscillation crosses the kink's surface, so the error falls as points^-2) and over every other one (whose
    difference from it is then three times its error) give a and the error estimate."""
    q = np.asarray(q, dtype=complex) / np.linalg.norm(q)
    p = left_eigenvector(A, omega, q)
    phi = 2.0 * np.pi * np.arange(points) / points
    U = 2.0 * np.real(q[None, :] * np.exp(1j * phi)[:, None])                  # (points, n)
    J = jacobians(np.concatenate([x0[None, :], x0 + step * U, x0 + 2.0 * step * U]))
    JU = np.einsum("mij,mj->mi", J[1:], np.concatenate([U, U]))
    Q = (4.0 * JU[:points] - JU[points:] - 3.0 * U @ J[0].T) / (4.0 * step)
    g = np.real(np.exp(-1j * phi) * (Q @ p.conj()))
    a, half = float(np.mean(g)), float(np.mean(g[::2]))
    return a, abs(a - half)
