"""Steady limit-cycle amplitudes by brute-force simulation, for the reduced model and the MBS.

This is the one place where limit-cycle amplitudes are measured; when the reduced model's periodic-orbit
continuation is available, :func:`reduced_peak` and :func:`reduced_steady_amplitude` can be replaced by it without
touching the callers.  Method: simulate from a state near the cycle for ``settle`` seconds, then take the largest
|theta1| (and |psi|, and the frequency of theta1 from its upward zero crossings) over the last ``window`` seconds; the run has settled when that maximum changed by less than
:data:`SETTLED_TOL` (relative) against the window before, or fell below :data:`DECAYED` (straight running
attracts: no cycle there, amplitude 0 to that accuracy).  Otherwise the run is continued, ``settle`` seconds at a
time, up to :data:`MAX_TIME`.  The reduced model is integrated by scipy's DOP853 (rtol 1e-9, atol 1e-12) on
:meth:`reduced_model.model.ShimmyModel.rhs`; the MBS by :func:`mbs_shimmy.simulation.simulate` with the fixed-step
setting (RK67 at 1/240 s, within 1e-4 of every state's amplitude), sampled at every step; the maxima are refined by a
parabola through the largest sample and its neighbours (:func:`peak`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Sequence

import numpy as np
import scipy.integrate

from mbs_shimmy.dimensions import DEFAULT_DIMENSIONS, AxleDimensions
from mbs_shimmy.fidelity import Fidelity
from mbs_shimmy.simulation import FAST_METHOD, FAST_STEP, extended_states, simulate
from reduced_model.bifurcation.equilibria.hopf import hopf_points
from reduced_model.family import SpeedFamily
from reduced_model.model import N_STATES, STATE_NAMES, Effects, ShimmyModel
from reduced_model.modes import crossing_frequency
from reduced_model.parameters import ShimmyParameters
from reduced_model.trajectory import SpeedSchedule

SETTLE = 12.0            # s
VMAX = 111.11111111111111   # m/s (400 km/h): the paper's speed window
WINDOW = 2.0             # s: several periods of either mode (5-14 Hz)
SETTLED_TOL = 1e-3
DECAYED = 1e-5           # rad
MAX_TIME = 72.0          # s
RTOL, ATOL = 1e-9, 1e-12
TH1, PSI = STATE_NAMES.index("theta1"), STATE_NAMES.index("psi")
GOLDEN = (math.sqrt(5.0) - 1.0) / 2.0


@dataclass(frozen=True)
class SteadyAmplitude:
    """Amplitudes (rad) of the steady oscillation reached at one speed, and the state it ended in."""

    speed: float                 # m/s
    theta1: float                # max |theta1| over the last window, rad
    psi: float                   # max |psi| over the last window, rad
    settled: bool                # changed by less than SETTLED_TOL against the window before
    final_state: np.ndarray = field(compare=False, repr=False)
    method: str = ""
    frequency_hz: float = math.nan   # of theta1 over the last window (upward zero crossings; NaN if fewer than two)


def _default_start() -> np.ndarray:
    x0 = np.zeros(N_STATES)
    x0[TH1] = 0.01
    return x0


def peak(y: np.ndarray) -> float:
    """max |y| of samples of a smooth signal, refined by the parabola through the largest sample and its two
    neighbours (for a 6 Hz oscillation sampled every 1/240 s the plain maximum is up to 0.3 % low, the refined one
    about 1e-5)."""
    a = np.abs(np.asarray(y, dtype=float))
    k = int(np.argmax(a))
    top = float(a[k])
    if 0 < k < len(a) - 1:
        left, right = float(a[k - 1]), float(a[k + 1])
        curvature = left - 2.0 * top + right
        if curvature < 0.0:
            top -= (right - left) ** 2 / (8.0 * curvature)
    return top


def _amplitudes(t: np.ndarray, x: np.ndarray, end: float, window: float) -> tuple[float, float, bool, float]:
    """(max |theta1|, max |psi|, settled, frequency of theta1 in Hz) over the last window."""
    last = t >= end - window - 1e-9
    before = (t >= end - 2 * window - 1e-9) & ~last
    a1 = peak(x[last, TH1])
    a0 = peak(x[before, TH1]) if np.any(before) else math.inf
    settled = abs(a1 - a0) < SETTLED_TOL * max(a1, 1e-300) or a1 < DECAYED
    return a1, peak(x[last, PSI]), settled, crossing_frequency(t[last], x[last, TH1])


def reduced_steady_amplitude(model: ShimmyModel, pressure: float | Sequence[float], speed: float,
                             x0: np.ndarray | None = None, settle: float = SETTLE,
                             window: float = WINDOW) -> SteadyAmplitude:
    """Steady amplitude of the reduced model at constant ``speed`` (m/s), from ``x0`` (default theta1 = 0.01)."""
    x = _default_start() if x0 is None else np.asarray(x0, dtype=float)
    total = 0.0
    while True:
        sol = scipy.integrate.solve_ivp(lambda t, y: model.rhs(y, speed, pressure), (0.0, settle), x,
                                        method="DOP853", rtol=RTOL, atol=ATOL, dense_output=True)
        t = np.linspace(max(0.0, settle - 2 * window), settle, int(4000 * window) + 1)
        xs = sol.sol(t).T
        total += settle
        a1, ap, settled, hz = _amplitudes(t, xs, settle, window)
        x = xs[-1].copy()
        if settled or total >= MAX_TIME:
            return SteadyAmplitude(speed, a1, ap, settled, x, f"scipy DOP853 rtol {RTOL:g}, {total:g} s", hz)


def mbs_steady_amplitude(params: ShimmyParameters, effects: Effects, fidelity: Fidelity,
                         pressure: float | Sequence[float], speed: float, x0: np.ndarray | None = None,
                         settle: float = SETTLE, window: float = WINDOW,
                         dims: AxleDimensions = DEFAULT_DIMENSIONS, step: float = FAST_STEP,
                         method: str = FAST_METHOD) -> SteadyAmplitude:
    """Steady amplitude of the MBS at constant ``speed`` (m/s) from ``x0`` (reduced-model state order, the new
    coordinates of the full axle at rest at zero, or all states in the extended order); ``final_state`` is in the
    extended order, so that a continued run keeps the new coordinates."""
    x = _default_start() if x0 is None else np.asarray(x0, dtype=float)
    total = 0.0
    while True:
        traj = simulate(params, effects, fidelity, pressure, SpeedSchedule.constant(speed), x, settle, dims=dims,
                        step=step, method=method, poses=False)
        if not traj.complete:
            return SteadyAmplitude(speed, math.nan, math.nan, False,
                                   extended_states(traj)[-1].copy() if len(traj.t) else x,
                                   f"MBS run stopped: {traj.message}")
        total += settle
        a1, ap, settled, hz = _amplitudes(traj.t, traj.x, settle, window)
        x = extended_states(traj)[-1].copy()
        if settled or total >= MAX_TIME:
            return SteadyAmplitude(speed, a1, ap, settled, x, f"{traj.integrator}, {total:g} s", hz)


def unstable_windows(model: ShimmyModel, pressure: float, vmax: float) -> list[tuple[float, float]]:
    """Speed intervals (m/s) between consecutive Hopf points where straight running is unstable."""
    family = SpeedFamily(model, pressure=pressure)
    points = hopf_points(family, family.nominal, 0.0, vmax, lyapunov=False)
    edges = [0.0] + [h.p for h in points] + [vmax]
    windows = []
    for a, b in zip(edges[:-1], edges[1:]):
        mid = 0.5 * (a + b)
        if b - a > 1e-6 and np.max(np.linalg.eigvals(family.linear_matrix(mid, family.nominal)).real) > 0.0:
            windows.append((a, b))
    return windows


def reduced_peak(model: ShimmyModel, pressure: float, vmax: float = VMAX, settle: float = SETTLE,
                 iterations: int = 8) -> SteadyAmplitude | None:
    """The largest steady theta1 amplitude of the reduced model over its unstable speed windows.

    Golden-section search for the maximum in each window (the amplitude rises from zero at each end), starting
    every run from the state the previous one ended in.  None if straight running is stable everywhere.
    """
    best: SteadyAmplitude | None = None
    for a, b in unstable_windows(model, pressure, vmax):
        lo, hi = a + 0.05 * (b - a), b - 0.05 * (b - a)
        state = None
        cache: dict[float, SteadyAmplitude] = {}

        def amp(v: float) -> SteadyAmplitude:
            nonlocal state
            if v not in cache:
                r = reduced_steady_amplitude(model, pressure, v, state, settle)
                state = r.final_state
                cache[v] = r
            return cache[v]

        x1, x2 = hi - GOLDEN * (hi - lo), lo + GOLDEN * (hi - lo)
        for _ in range(iterations):
            if amp(x1).theta1 >= amp(x2).theta1:
                hi, x2 = x2, x1
                x1 = hi - GOLDEN * (hi - lo)
            else:
                lo, x1 = x1, x2
                x2 = lo + GOLDEN * (hi - lo)
        top = max(cache.values(), key=lambda r: r.theta1)
        if best is None or top.theta1 > best.theta1:
            best = top
    return best
