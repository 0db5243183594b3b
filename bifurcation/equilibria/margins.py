"""Stability margins of the equilibrium: the least damping ratio over a grid of the two parameters (p, q).

For the Jacobian A(p, q) at the equilibrium, each oscillatory eigenvalue lambda (Im lambda != 0) has the damping
ratio zeta = -Re(lambda) / |lambda|: the lines of constant zeta are the rays from the origin of the complex plane,
and a linear oscillator x'' + 2 zeta w x' + w^2 x = 0 has the eigenvalues -zeta w +- i w sqrt(1 - zeta^2) (Ogata,
Modern Control Engineering, 5th ed. 2010, ch. 5, second-order systems; the damping of the least damped mode against
the parameter is the flutter engineer's margin: Hodges & Pierce, Introduction to Structural Dynamics and
Aeroelasticity, 2nd ed. 2011, ch. 5).  The margin at (p, q) is the least zeta over the oscillatory
eigenvalues; zeta < 0 means a growing oscillation, zeta = 0 is a Hopf point of the equilibrium when that pair is
the only one crossing.

Real eigenvalues do not oscillate and are left out of zeta (by the formula each would have zeta = +-1); the largest
of them is kept as ``real_growth``, so that a real eigenvalue in the right half-plane (a
divergence, not an oscillation) is seen: :attr:`Margin.divergent`.  An eigenvalue counts as oscillatory when
|Im lambda| exceeds :data:`IMAG_RTOL` times the spectral radius of A (a double real eigenvalue splits into a
spurious pair of about sqrt(machine epsilon) relative).

The toolkit evaluates only ``family.linear_matrix(p, q)``; a family that caches its Jacobian per q (affine in p)
makes the p direction of a map cheap.
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass, field
from typing import Callable, Sequence

import numpy as np
import scipy.optimize

from bifurcation.messages import Message, Quantity
from bifurcation.problem import Family, clip_window

IMAG_RTOL = 1e-6
ROOT_XTOL = 1e-12      # relative, of the zero level's location in p


class MarginStatus(enum.Enum):
    OSCILLATORY = "oscillatory"             # zeta is the least damping ratio of the oscillatory eigenvalues
    NO_OSCILLATION = "no oscillation"       # every eigenvalue is real: zeta is undefined (NaN)


@dataclass(frozen=True)
class Margin:
    """The least damped oscillatory eigenvalue of the equilibrium at (p, q)."""

    p: float
    q: float
    damping_ratio: float            # -Re / |lambda|; negative: the oscillation grows; NaN without oscillation
    eigenvalue: complex             # the least damped one, Im > 0 (NaN without oscillation)
    real_growth: float              # the largest real eigenvalue's value (NaN: none is real)
    status: MarginStatus
    eigenvector: np.ndarray | None = field(default=None, compare=False, repr=False)   # of ``eigenvalue``

    @property
    def omega(self) -> float:
        """Damped angular frequency |Im lambda| (0 without oscillation)."""
        return abs(self.eigenvalue.imag) if self.status is MarginStatus.OSCILLATORY else 0.0

    @property
    def frequency_hz(self) -> float:
        return self.omega / (2.0 * math.pi)

    @property
    def divergent(self) -> bool:
        """A real eigenvalue in the right half-plane."""
        return self.real_growth > 0.0

    @property
    def stable(self) -> bool:
        """Every eigenvalue in the open left half-plane."""
        damped = self.status is MarginStatus.NO_OSCILLATION or self.damping_ratio > 0.0
        return damped and not self.real_growth >= 0.0


def least_damped(family: Family, p: float, q: float, A: np.ndarray | None = None, vector: bool = True) -> Margin:
    """The margin at (p, q) (module docstring), from ``family.linear_matrix(p, q)`` unless ``A`` is given; without
    ``vector`` the eigenvector is not computed (``eigenvector`` None; about half the cost)."""
    if A is None:
        A = family.linear_matrix(p, q)
    A = np.asarray(A, dtype=float)
    values, vectors = np.linalg.eig(A) if vector else (np.linalg.eigvals(A), None)
    radius = float(np.max(np.abs(values))) if values.size else 0.0
    oscillatory = np.abs(values.imag) > IMAG_RTOL * radius
    real = values[~oscillatory].real
    growth = float(np.max(real)) if real.size else math.nan
    upper = np.nonzero(oscillatory & (values.imag > 0.0))[0]
    if upper.size == 0:
        return Margin(float(p), float(q), math.nan, complex(math.nan, math.nan), growth, MarginStatus.NO_OSCILLATION)
    zeta = -values[upper].real / np.abs(values[upper])
    k = upper[int(np.argmin(zeta))]
    return Margin(float(p), float(q), float(-values[k].real / abs(values[k])), complex(values[k]), growth,
                  MarginStatus.OSCILLATORY, None if vectors is None else vectors[:, k])


@dataclass(frozen=True)
class MarginMap:
    """Margins on the grid ``p`` x ``q``: ``margins[j][i]`` at (p[i], q[j])."""

    p: np.ndarray = field(compare=False)
    q: np.ndarray = field(compare=False)
    margins: tuple[tuple[Margin, ...], ...]

    @property
    def damping_ratio(self) -> np.ndarray:
        """zeta, shape (len(q), len(p)); NaN where nothing oscillates."""
        return np.array([[m.damping_ratio for m in row] for row in self.margins])

    @property
    def undefined(self) -> int:
        """Grid points with no oscillatory eigenvalue."""
        return sum(m.status is MarginStatus.NO_OSCILLATION for row in self.margins for m in row)

    def minimum(self, p_min: float = -math.inf, p_max: float = math.inf, q_min: float = -math.inf,
                q_max: float = math.inf) -> Margin | None:
        """The least margin on the grid nodes inside the window (its location to the grid's spacing); None when no
        node of the window oscillates."""
        found = [m for row in self.margins for m in row
                 if m.status is MarginStatus.OSCILLATORY and p_min <= m.p <= p_max and q_min <= m.q <= q_max]
        return min(found, key=lambda m: m.damping_ratio) if found else None


def margin_map(family: Family, p_values: Sequence[float], q_values: Sequence[float],
               progress: Callable[[], None] | None = None) -> MarginMap:
    """The margin at every (p, q) of the grid; p below the family's lowest meaningful p is dropped.  ``progress()``
    is called once per q."""
    p_all = np.asarray(sorted(float(v) for v in p_values))
    p = p_all[p_all >= family.primary_min]
    if p.size == 0:
        raise ValueError(Message.of(f"no {family.primary} of the grid is at or above its lowest meaningful value, ",
                                    Quantity(family.primary, family.primary_min)))
    q = np.asarray(sorted(float(v) for v in q_values))
    rows = []
    for qj in q:
        family.validate(qj)
        rows.append(tuple(least_damped(family, pi, qj) for pi in p))
        if progress is not None:
            progress()
    return MarginMap(p, q, tuple(rows))


def zero_level(family: Family, q: float, p_values: Sequence[float]) -> tuple[float, ...]:
    """Where the least damping ratio changes sign along p at fixed q: Brent's method (scipy ``brentq``) on
    zeta(p) = :func:`least_damped` between consecutive nodes of ``p_values`` whose margins differ in sign.

    Each is a Hopf point of the equilibrium at which the last growing oscillation (or the first) appears: where
    another pair is already unstable, the least zeta stays negative through a Hopf point and it is not found here.
    Nodes without an oscillatory eigenvalue bracket nothing.
    """
    lo, hi = clip_window(family, min(p_values), max(p_values))
    nodes = [lo] + [float(v) for v in sorted(p_values) if lo < v < hi] + [hi]

    def zeta(p: float) -> float:
        return least_damped(family, p, q).damping_ratio

    values = [zeta(v) for v in nodes]
    roots = []
    for a, b, za, zb in zip(nodes[:-1], nodes[1:], values[:-1], values[1:]):
        if not (np.isfinite(za) and np.isfinite(zb)):
            continue
        if za == 0.0:
            roots.append(a)
        elif za * zb < 0.0:
            roots.append(float(scipy.optimize.brentq(zeta, a, b, xtol=ROOT_XTOL * max(1.0, abs(a)),
                                                     rtol=4 * np.finfo(float).eps)))
    if values[-1] == 0.0:
        roots.append(nodes[-1])
    return tuple(roots)
