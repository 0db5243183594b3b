"""What a problem gives the toolkit: the :class:`Family` protocol.

A family is a vector field f(x; p, q) with two named parameters: the first, p, is the one every one-parameter
computation continues in (Hopf points, cycle branches); the second, q, is fixed there and freed on two-parameter
curves.  This is BifurcationKit's separation of the problem from the algorithms (Veltz, BifurcationKit.jl,
https://hal.archives-ouvertes.fr/hal-02902346): the toolkit evaluates a family only through these members, so any
model that provides them (the paper's 3-DOF model, the Exudyn multibody model, a test oscillator) runs through the
same code.  Messages of the toolkit keep the parameter values they name as values (:mod:`bifurcation.messages`); the
interface shows them in its own units.
"""

from __future__ import annotations

from typing import Protocol, runtime_checkable

import numpy as np

from bifurcation.messages import Message, Quantity


class ProblemError(ValueError):
    """A request the problem cannot serve (a parameter it does not have, a window outside its validity)."""


@runtime_checkable
class Family(Protocol):
    """f(x; p, q) with its Jacobian, the Jacobian at the equilibrium, and what "small" and "valid" mean for it."""

    param: str            # the name of q

    @property
    def primary(self) -> str:
        """The name of p."""

    @property
    def primary_scale(self) -> float:
        """How much p changes per unit of arclength in continuation norms."""

    @property
    def primary_min(self) -> float:
        """The lowest meaningful p: every window of the toolkit starts at or above it."""

    @property
    def n(self) -> int:
        """Number of states."""

    @property
    def state_names(self) -> tuple[str, ...]:
        ...

    @property
    def nominal(self) -> float:
        """q at the operating point (its scale in continuation norms)."""

    def state_scales(self, omega: float) -> np.ndarray:
        """Typical size of each state in an oscillation at omega rad/s (for norms and mesh monitors)."""

    def rhs(self, x: np.ndarray, p: float, q: float) -> np.ndarray:
        """f at one state (n,) or at the columns of X (n, k)."""

    def jacobian(self, x: np.ndarray, p: float, q: float) -> np.ndarray:
        ...

    def linear_matrix(self, p: float, q: float) -> np.ndarray:
        """The Jacobian at the equilibrium."""

    def equilibrium(self, p: float, q: float) -> np.ndarray:
        ...

    def validate(self, q: float) -> None:
        """Raise where the family is meaningless at q."""

    # Optional: ``origin_equilibrium = False`` says the equilibrium may lie off x = 0, so that the size of a cycle is
    # measured about its mean (:meth:`~bifurcation.cycles.problem.CycleProblem.scaled_rms`) and its max |x_i| about the
    # equilibrium at (p, q) (:attr:`~bifurcation.cycles.problem.CyclePoint.amplitude`); default True.

    # How the derivatives are formed: inherit one of :mod:`bifurcation.derivatives`.
    costly_jacobian: bool   # df/dx costs many evaluations of f (continuation then reuses Jacobians)
    # Optional, False where absent: f has kinks (two-parameter cycle curves then step over the gaps a collocation
    # node's crossing makes and run chord iterations, :mod:`bifurcation.cycle_curves.bordered`)
    piecewise_smooth: bool
    # Optional: ``twice_differentiable(x0, p, q) -> bool | None`` says whether f is twice differentiable at the
    # equilibrium x0 (None: cannot tell); where False, a Hopf point's criticality is its kink coefficient's
    # (:func:`bifurcation.equilibria.hopf.kink_coefficient`), not l1's

    def rhs_and_jacobians(self, P: np.ndarray, p: float, q: float,
                          kink_rows: bool = True) -> tuple[np.ndarray, np.ndarray]:
        """f (M, n) and df/dx (M, n, n) at the states P (M, n).  Where f has a kink near a state, df/dx is smoothed
        across it (differences straddling it) so that a fold's test function does not jump as a collocation state
        crosses the kink; with ``kink_rows`` False one side's exact df/dx, enough for a caller that only forms a
        Newton direction from it (the gradients of bordered test functions).  Smooth families ignore it."""

    def parameter_derivative(self, P: np.ndarray, p: float, q: float, free: str, scale: float) -> np.ndarray:
        """df/d(free) (M, n) at the states P (M, n); ``scale`` is the free parameter's size."""

    def multilinear_forms(self, x0: np.ndarray, p: float, q: float):
        """The forms B and C of f at the equilibrium x0 (:class:`~bifurcation.equilibria.normal_form.MultilinearForms`)."""


def clip_window(family: Family, lo: float, hi: float) -> tuple[float, float]:
    """The window [lo, hi] of p with its lower end raised to the family's lowest meaningful p."""
    return max(float(lo), family.primary_min), float(hi)


def describe(family: Family, p: float, q: float | None = None) -> Message:
    """A location in a message, its parameters named as the family names them: ``str()`` gives
    ``"<primary> = 12.5, <param> = 150000"`` (SI), the interface its own units."""
    return Message.of(Quantity(family.primary, float(p)),
                      None if q is None else Message.of(", ", Quantity(family.param, float(q))))
