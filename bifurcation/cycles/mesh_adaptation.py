"""Error estimates of collocated orbits and mesh adaptation (for :mod:`bifurcation.cycles.collocation`).

Mesh adaptation equidistributes the local error estimate h_j^(m+1) |x^(m+1)|, with x^(m+1) approximated from
the jumps of the (piecewise constant) m-th derivative across mesh points (de Boor, "Good approximation by splines
with variable knots", 1973; Russell & Christiansen, SIAM J. Numer. Anal. 15, 1978, 59; AUTO's mesh adaption).

Error estimate (:func:`error_estimate`).  Inside interval j the collocation error has the principal part
e(tau_j + s h_j) = h_j^(m+1) x^(m+1) (1/m!) int_0^s prod_k (r - rho_k) dr (Ascher, Mattheij & Russell 1995,
theorem 5.140 and section 9.3.1; the same principal error function drives AUTO's and COCO's mesh adaption), with
rho_k the Gauss points; its maximum over s gives a per-interval, per-state bound of the error of the stored
polynomial at interior points, where maxima of |x_i| are read.  :func:`refined_intervals` turns it into the
number of intervals that meets a tolerance.
"""

from __future__ import annotations

import functools
import math

import numpy as np

from bifurcation.cycles.collocation import Orbit, scheme


@functools.lru_cache(maxsize=8)
def error_constant(degree: int) -> float:
    """max over s in [0, 1] of |int_0^s prod_k (r - rho_k) dr| / m! (rho_k the Gauss points): the principal
    error constant of Gauss collocation of degree m at interior points (module docstring)."""
    sch = scheme(degree)
    psi = np.polynomial.polynomial.polyfromroots(sch.points)
    s = np.linspace(0.0, 1.0, 2001)
    return float(np.max(np.abs(np.polynomial.polynomial.polyval(s, np.polynomial.polynomial.polyint(psi))))
                 / math.factorial(degree))


def _next_derivative(orbit: Orbit) -> np.ndarray:
    """x^(m+1) (d/dtau) at the mesh points tau_j, from the jumps of the piecewise constant m-th derivative:
    (N, n), units of the states per unit of scaled time^(m+1)."""
    sch = scheme(orbit.degree)
    m = orbit.degree
    h = orbit.widths
    dm = np.einsum("i,jin->jn", sch.top, orbit.interval_values()) / h[:, None] ** m    # m-th derivative
    jump = dm - np.roll(dm, 1, axis=0)                                                   # at mesh point j
    hbar = 0.5 * (h + np.roll(h, 1))
    return jump / hbar[:, None]


def error_estimate(orbit: Orbit) -> np.ndarray:
    """Estimated largest error of every state on every interval, (N, n) in the states' units (module
    docstring: principal error function of Gauss collocation, x^(m+1) from the m-th derivative jumps)."""
    h = orbit.widths
    d = np.abs(_next_derivative(orbit))
    per_interval = np.maximum(d, np.roll(d, -1, axis=0))      # both ends of interval j
    return error_constant(orbit.degree) * h[:, None] ** (orbit.degree + 1) * per_interval


def relative_error(orbit: Orbit, scales: np.ndarray, amplitudes: np.ndarray | None = None) -> float:
    """Largest estimated error of any state relative to that state's amplitude max |x_i| (floored at 1e-6 of
    the largest amplitude, measured in ``scales``, so that a state that hardly moves does not decide alone)."""
    amp = orbit.maxima() if amplitudes is None else np.asarray(amplitudes)
    size = np.max(amp / scales)
    if not np.isfinite(size) or size <= 0.0:
        return 0.0
    floor = np.maximum(amp, 1e-6 * size * scales)
    return float(np.max(error_estimate(orbit) / floor[None, :]))


def refined_intervals(intervals: int, error: float, tolerance: float, degree: int, safety: float = 0.5,
                      max_growth: float = 4.0) -> int:
    """Intervals that bring an error estimate ``error`` (which scales as N^-(m+1)) to ``safety * tolerance``."""
    if not np.isfinite(error):
        return int(np.ceil(intervals * max_growth))
    factor = (error / (safety * tolerance)) ** (1.0 / (degree + 1))
    return int(np.ceil(intervals * min(max(factor, 1.0), max_growth)))


def adapted_mesh(orbit: Orbit, scales: np.ndarray, floor: float = 0.05, intervals: int | None = None) -> np.ndarray:
    """A mesh of ``intervals`` intervals (default: as many as now) equidistributing h_j^(m+1) |x^(m+1)|
    (module docstring).

    ``scales`` weigh the states (SI units differ by orders of magnitude).  ``floor`` (relative to the mean
    density) keeps intervals from growing without bound where the orbit is nearly straight.
    """
    m = orbit.degree
    N = orbit.intervals if intervals is None else int(intervals)
    h = orbit.widths
    scaled = Orbit(mesh=orbit.mesh, nodes=orbit.nodes / scales[None, :], period=orbit.period, degree=m)
    d_next = np.linalg.norm(_next_derivative(scaled), axis=1)              # (m+1)-th derivative at tau_j
    w = 0.5 * (d_next + np.roll(d_next, -1))                                # per interval
    rho = w ** (1.0 / (m + 1))
    mean = np.sum(rho * h)
    if not np.isfinite(mean) or mean <= 0.0:
        return orbit.mesh.copy()
    rho = rho + floor * mean
    cumulative = np.concatenate([[0.0], np.cumsum(rho * h)])
    targets = np.linspace(0.0, cumulative[-1], N + 1)
    new = np.interp(targets, cumulative, orbit.mesh)
    new[0], new[-1] = 0.0, 1.0
    return new


def remesh(orbit: Orbit, mesh: np.ndarray) -> Orbit:
    """The same piecewise polynomial sampled at the nodes of another mesh (interpolation, no re-solve)."""
    sch = scheme(orbit.degree)
    widths = np.diff(mesh)
    tau = (mesh[:-1, None] + widths[:, None] * sch.nodes[None, :-1]).ravel()
    return Orbit(mesh=np.asarray(mesh, float), nodes=orbit.at(tau), period=orbit.period, degree=orbit.degree)


def mesh_quality(mesh: np.ndarray, target: np.ndarray) -> float:
    """Largest relative difference of interval widths between two meshes (0: identical)."""
    a, b = np.diff(mesh), np.diff(target)
    return float(np.max(np.abs(a - b) / b))
