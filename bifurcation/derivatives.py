"""How a family's derivatives are formed: the two ways a problem can offer them to the toolkit.

Every algorithm of the toolkit asks the family for f and df/dx at many states (collocation), for df/dp (the free
parameter's column of a Newton matrix), and for the multilinear forms B and C of f at an equilibrium (normal-form
coefficients).  A family inherits one of the two implementations here, according to what its right-hand side can
do:

* :class:`ComplexStepDerivatives`, for a vector field analytic in the state and the first parameter and vectorised
  over columns, complex values allowed (the paper's model): complex-step Jacobians (Squire & Trapp, SIAM Rev. 40,
  1998), exact to rounding, and the multilinear forms from Cauchy's integral formula on a complex circle
  (:mod:`bifurcation.equilibria.normal_form`).
* :class:`DifferenceDerivatives`, for a vector field evaluated at one real state at a time (the Exudyn model):
  the family's own Jacobian at each state, central differences in the parameters, and the multilinear forms by
  finite differences of f along real directions, extended to complex arguments by multilinearity, as MatCont
  computes them numerically (Dhooge, Govaerts, Kuznetsov, Meijer & Sautois, Math. Comput. Model. Dyn. Syst. 14,
  2008, section 3; Kuznetsov, Elements of Applied Bifurcation Theory, 3rd ed., 2004, section 10.2).
"""

from __future__ import annotations

import numpy as np

from bifurcation.equilibria.normal_form import CauchyForms, DifferenceForms, MultilinearForms

COMPLEX_STEP = 1e-30
PARAMETER_STEP = 1e-6     # central differences in a parameter: step relative to max(|value|, its scale)


def values_and_jacobians(rhs, P: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """f and df/dx at the M points P (M, n) from one complex-step call of the vectorised ``rhs(X (n, k))``.

    Re f(x + i h e_b) = f(x) + O(h^2), so with h = 1e-30 the real parts are f itself (Squire & Trapp 1998).
    Returns f (M, n) and J (M, n, n) with J[k, a, b] = df_a/dx_b at point k.
    """
    M, n = P.shape
    C = P[:, None, :] + (1j * COMPLEX_STEP) * np.eye(n)[None, :, :]       # (M, dir, n)
    F = rhs(C.reshape(M * n, n).T)                                        # (n, M*dir)
    F = np.asarray(F).reshape(n, M, n)
    f = F[:, :, 0].real.T
    J = np.transpose(F.imag, (1, 0, 2)) / COMPLEX_STEP                    # (M, a, dir)
    return f, J


def _central_difference(rhs, P: np.ndarray, value: float, scale: float) -> np.ndarray:
    h = PARAMETER_STEP * max(abs(value), scale)
    return (rhs(P.T, value + h) - rhs(P.T, value - h)).T / (2.0 * h)


class ComplexStepDerivatives:
    """Derivatives of an analytic, column-vectorised ``rhs(X, p, q)`` that accepts complex X and p."""

    costly_jacobian = False     # one vectorised call gives f and df/dx together

    def rhs_and_jacobians(self, P: np.ndarray, p: float, q: float,
                          kink_rows: bool = True) -> tuple[np.ndarray, np.ndarray]:
        """f (M, n) and df/dx (M, n, n) at the states P (M, n) (smooth: ``kink_rows`` changes nothing)."""
        return values_and_jacobians(lambda Z: self.rhs(Z, p, q), P)

    def parameter_derivative(self, P: np.ndarray, p: float, q: float, free: str, scale: float) -> np.ndarray:
        """df/d(free) (M, n) at the states P (M, n), ``scale`` the free parameter's size: complex step in the first parameter, central differences in
        the second (which may enter through a rebuilt model that complex values cannot pass)."""
        if free == self.primary:
            return (self.rhs(P.T.astype(complex), p + 1j * COMPLEX_STEP, q).imag / COMPLEX_STEP).T
        return _central_difference(lambda X, v: self.rhs(X, p, v), P, q, scale)

    def multilinear_forms(self, x0: np.ndarray, p: float, q: float) -> MultilinearForms:
        return CauchyForms(lambda X: self.rhs(X, p, q), x0)


class DifferenceDerivatives:
    """Derivatives of a ``rhs(x, p, q)`` known at real states only, from the family's ``jacobian`` and differences."""

    costly_jacobian = True      # df/dx costs about 2 n evaluations of f: continuation runs chord iterations

    def rhs_and_jacobians(self, P: np.ndarray, p: float, q: float,
                          kink_rows: bool = True) -> tuple[np.ndarray, np.ndarray]:
        P = np.asarray(P, dtype=float)
        f = np.array([self.rhs(x, p, q) for x in P])
        J = np.array([self.jacobian(x, p, q) for x in P])
        return f, J

    def parameter_derivative(self, P: np.ndarray, p: float, q: float, free: str, scale: float) -> np.ndarray:
        if free == self.primary:
            return _central_difference(lambda X, v: self.rhs(X, v, q), P, p, scale)
        return _central_difference(lambda X, v: self.rhs(X, p, v), P, q, scale)

    def multilinear_forms(self, x0: np.ndarray, p: float, q: float) -> MultilinearForms:
        return DifferenceForms(lambda x: self.rhs(x, p, q), x0, self.state_scales(1.0))
