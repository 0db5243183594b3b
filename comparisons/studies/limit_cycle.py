"""Steady limit-cycle amplitudes by brute-force simulation, for the reduced model and the MBS.

The continued cycle branches (:mod:`comparisons.studies.cycle_peak`) give the amplitudes; these runs are their independent
check (an attractor reached by time integration) and serve the kick searches. Method: simulate from a state near the
cycle for ``settle`` seconds, then take the largest |theta1| (and |psi|, and the frequency of theta1 from its upward
zero crossings) over the last ``window`` seconds; the run has settled when that maximum changed by less than
:data:`SETTLED_TOL` (relative) against the window before, or fell below :data:`DECAYED` (straight running attracts:
no cycle there, amplitude 0 to that accuracy). Otherwise the run is continued, ``settle`` seconds at a time, up to
:data:`MAX_TIME`. The reduced model is integrated by scipy's DOP853 (rtol 1e-9, atol 1e-12) on
:meth:`reduced_model.model.ShimmyModel.rhs`; the MBS by :func:`mbs_shimmy.simulation.simulate` with the fixed-step
setting (RK67 at 1/240 s, within 1e-4 of every state's amplitude), sampled at every step; the maxima are refined by
a parabola through the largest sample and its neighbours (:func:`peak`).  Under braking the runs carry the
braking and the amplitudes are taken about the braked steady state ``origin`` (reduced-model order), not from 0.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import scipy.integrate

from axles.axle import interface_text
from axles.braking import FREE_ROLLING, Braking
from axles.dimensions import DEFAULT_DIMENSIONS, AxleDimensions
from mbs_shimmy.fidelity import Fidelity
from mbs_shimmy.simulation import FAST_METHOD, FAST_STEP, extended_states, integrate
from reduced_model.model import N_STATES, STATE_NAMES, Effects, ShimmyModel
from reduced_model.modes import crossing_frequency
from axles.parameters import ShimmyParameters
from reduced_model.trajectory import SpeedSchedule
from axles.pressures import TyrePressures

SETTLE = 12.0            # s
VMAX = 111.11111111111111   # m/s (400 km/h): the paper's speed window
WINDOW = 2.0             # s: several periods of either mode (5-14 Hz)
SETTLED_TOL = 1e-3
DECAYED = 1e-5           # rad
MAX_TIME = 72.0          # s
RTOL, ATOL = 1e-9, 1e-12
TH1, PSI = STATE_NAMES.index("theta1"), STATE_NAMES.index("psi")


@dataclass(frozen=True)
class SteadyAmplitude:
    """Amplitudes (rad) of the steady oscillation reached at one speed, and the state it ended in."""

    speed: float                 # m/s
    theta1: float                # max |theta1| over the last window (about the steady state under braking), rad
    psi: float                   # max |psi| over the last window (likewise), rad
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


def _amplitudes(t: np.ndarray, x: np.ndarray, end: float, window: float,
                origin: np.ndarray | None = None) -> tuple[float, float, bool, float]:
    """(max |theta1|, max |psi|, settled, frequency of theta1 in Hz) over the last window, about ``origin`` (the
    steady state, reduced-model order; None: x = 0)."""
    if origin is not None:
        x = x[:, :N_STATES] - np.asarray(origin)[None, :N_STATES]
    last = t >= end - window - 1e-9
    before = (t >= end - 2 * window - 1e-9) & ~last
    a1 = peak(x[last, TH1])
    a0 = peak(x[before, TH1]) if np.any(before) else math.inf
    settled = abs(a1 - a0) < SETTLED_TOL * max(a1, 1e-300) or a1 < DECAYED
    return a1, peak(x[last, PSI]), settled, crossing_frequency(t[last], x[last, TH1])


def reduced_steady_amplitude(model: ShimmyModel, pressures: TyrePressures, speed: float,
                             x0: np.ndarray | None = None, settle: float = SETTLE,
                             window: float = WINDOW, braking: Braking = FREE_ROLLING,
                             origin: np.ndarray | None = None) -> SteadyAmplitude:
    """Steady amplitude of the reduced model at constant ``speed`` (m/s), from ``x0`` (default theta1 = 0.01),
    under ``braking``, about ``origin`` (module docstring)."""
    x = _default_start() if x0 is None else np.asarray(x0, dtype=float)
    total = 0.0
    while True:
        sol = scipy.integrate.solve_ivp(lambda t, y: model.rhs(y, speed, pressures, braking), (0.0, settle), x,
                                        method="DOP853", rtol=RTOL, atol=ATOL, dense_output=True)
        t = np.linspace(max(0.0, settle - 2 * window), settle, int(4000 * window) + 1)
        xs = sol.sol(t).T
        total += settle
        a1, ap, settled, hz = _amplitudes(t, xs, settle, window, origin)
        x = xs[-1].copy()
        if settled or total >= MAX_TIME:
            return SteadyAmplitude(speed, a1, ap, settled, x, f"scipy DOP853 rtol {RTOL:g}, {total:g} s", hz)


def mbs_steady_amplitude(params: ShimmyParameters, effects: Effects, fidelity: Fidelity,
                         pressures: TyrePressures, speed: float, x0: np.ndarray | None = None,
                         settle: float = SETTLE, window: float = WINDOW,
                         dims: AxleDimensions = DEFAULT_DIMENSIONS, step: float = FAST_STEP,
                         method: str = FAST_METHOD, braking: Braking = FREE_ROLLING,
                         origin: np.ndarray | None = None) -> SteadyAmplitude:
    """Steady amplitude of the MBS at constant ``speed`` (m/s) from ``x0`` (reduced-model state order, the new
    coordinates of the full axle at rest at zero, or all states in the extended order); ``final_state`` is in the
    extended order, so that a continued run keeps the new coordinates.  Under ``braking``, about ``origin``."""
    x = _default_start() if x0 is None else np.asarray(x0, dtype=float)
    total = 0.0
    while True:
        traj = integrate(params, effects, fidelity, pressures, SpeedSchedule.constant(speed), x, settle, dims=dims,
                        step=step, method=method, poses=False, braking=braking)
        if not traj.complete:
            return SteadyAmplitude(speed, math.nan, math.nan, False,
                                   extended_states(traj)[-1].copy() if len(traj.t) else x,
                                   f"MBS run stopped: {interface_text(traj.message)}")
        total += settle
        a1, ap, settled, hz = _amplitudes(traj.t, traj.x, settle, window, origin)
        x = extended_states(traj)[-1].copy()
        if settled or total >= MAX_TIME:
            return SteadyAmplitude(speed, a1, ap, settled, x, f"{traj.integrator}, {total:g} s", hz)

