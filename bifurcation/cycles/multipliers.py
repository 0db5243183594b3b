"""Floquet multipliers of a cycle and the test functions read from them (Kuznetsov 2004, ch. 10; Govaerts 2000,
ch. 7): the trivial multiplier (the one nearest +1) is set apart, torus and period-doubling tests on the rest, and
on fold and period-doubling curves the tests with the critical multipliers taken out.
"""

from __future__ import annotations

import numpy as np

COMPLEX_TOL = 1e-7          # |Im mu| below this: a real multiplier


def classify_multipliers(mu: np.ndarray) -> tuple[np.ndarray, complex]:
    """(non-trivial multipliers, trivial multiplier): the trivial one is the multiplier nearest +1.

    The trivial multiplier is exactly 1, so real.  Where a second multiplier is near +1 too (beside a Hopf point,
    at a fold) the discretisation can split the two into a conjugate pair 1 +- i eps; the partner of a complex
    trivial multiplier is then real as well and is returned without its imaginary part (otherwise it would be a
    lone complex multiplier crossing the unit circle: a spurious torus point)."""
    k = int(np.argmin(np.abs(mu - 1.0)))
    trivial = complex(mu[k])
    rest = np.delete(mu, k)
    if abs(trivial.imag) > COMPLEX_TOL and len(rest):
        j = int(np.argmin(np.abs(rest - trivial.conjugate())))
        rest = rest.astype(complex)
        rest[j] = rest[j].real
    return rest, trivial


def complex_outside(mu: np.ndarray) -> int:
    return int(np.sum((np.abs(mu.imag) > COMPLEX_TOL) & (np.abs(mu) > 1.0)))


def negative_outside(mu: np.ndarray) -> int:
    return int(np.sum((np.abs(mu.imag) <= COMPLEX_TOL) & (mu.real < -1.0)))


def torus_test(mu: np.ndarray) -> float:
    """|mu| - 1 of the complex non-trivial multiplier nearest the unit circle (NaN if none)."""
    c = mu[np.abs(mu.imag) > COMPLEX_TOL]
    if len(c) == 0:
        return float("nan")
    k = int(np.argmin(np.abs(np.abs(c) - 1.0)))
    return float(np.abs(c[k]) - 1.0)


def period_doubling_test(mu: np.ndarray) -> float:
    """mu + 1 of the real negative non-trivial multiplier nearest -1 (NaN if none)."""
    r = mu[(np.abs(mu.imag) <= COMPLEX_TOL) & (mu.real < 0.0)].real
    if len(r) == 0:
        return float("nan")
    return float(r[np.argmin(np.abs(r + 1.0))] + 1.0)


def critical_multipliers(mu: np.ndarray) -> np.ndarray:
    """The multipliers of a fold cycle other than the two nearest +1 (the trivial one and the fold's)."""
    order = np.argsort(np.abs(mu - 1.0))
    return np.delete(mu, order[:2])


def flip_critical_multipliers(mu: np.ndarray) -> np.ndarray:
    """The multipliers of a period-doubling cycle other than the one nearest +1 (trivial) and the one nearest -1."""
    rest = np.delete(mu, int(np.argmin(np.abs(mu - 1.0))))
    return np.delete(rest, int(np.argmin(np.abs(rest + 1.0))))


def positive_outside(mu: np.ndarray) -> int:
    return int(np.sum((np.abs(mu.imag) <= COMPLEX_TOL) & (mu.real > 1.0)))


def fold_test(mu: np.ndarray) -> float:
    """Re(mu_1 + mu_2) - 2 of the two multipliers nearest +1 (all multipliers, the trivial one included): the
    non-trivial one's mu - 1 up to the discretisation error of the trivial one, whichever of them is nearer +1."""
    pair = mu[np.argsort(np.abs(mu - 1.0))[:2]]
    return float(np.sum(pair.real) - 2.0)
