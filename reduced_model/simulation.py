"""Time simulation of the reduced model at constant speed or along a speed schedule.

Integrator: scipy's LSODA (``scipy.integrate.ode``; Petzold, SIAM J. Sci. Stat. Comput. 4, 1983; Hindmarsh,
ODEPACK, 1983) with the exact complex-step Jacobian.  LSODA switches between Adams (non-stiff) and BDF (stiff)
by itself, so the same call serves the whole speed range.  At the default tolerances (rtol = 1e-9, atol = 1e-11
in SI: rad, rad/s) a 20 s run at 180 km/h costs about 1.6 s (this model is only mildly stiff: its fastest rate is
the slip relaxation V / sigma, about 150 1/s at 350 km/h).  The solver interpolates each sample of a uniform grid
from its own history (:func:`integrate`).

Along a speed ramp the speed is an explicit function of time in the right-hand side; the speed schedule and the
trajectory type are shared with the multibody model (:mod:`reduced_model.trajectory`).
"""

from __future__ import annotations

from typing import Callable

import warnings

import numpy as np
import scipy.integrate

from bifurcation.messages import NO_MESSAGE, Message, Quantity
from reduced_model.model import N_STATES, STATE_NAMES, ShimmyModel
from axles.parameters import ParameterError
from axles.braking import FREE_ROLLING, Braking
from axles.pressures import TyrePressures
from reduced_model.trajectory import SimulationStatus, SpeedSchedule, Trajectory

RTOL = 1e-9
ATOL = 1e-11
SAMPLE_INTERVAL = 1e-3        # s between stored samples
MAX_STEPS = 100_000           # LSODA steps within one sample interval before it gives up (excess work)
DIVERGENCE_ANGLE = 3.0        # rad: any angle beyond this is outside the model's meaning (small-angle model)
ANGLE_INDEX = [STATE_NAMES.index(s) for s in ("theta1", "theta2", "psi", "alpha1", "alpha2")]
DEFAULT_INITIAL = {"theta1": 0.01}


def initial_state(values: dict[str, float] | None = None) -> np.ndarray:
    """State vector from ``{name: value}`` (SI); missing states are zero.  Default: theta1 = 0.01 rad."""
    values = DEFAULT_INITIAL if values is None else values
    x0 = np.zeros(N_STATES)
    for name, value in values.items():
        if name not in STATE_NAMES:
            raise ParameterError(f"unknown state '{name}' (known: {', '.join(STATE_NAMES)})")
        if not np.isfinite(value):
            raise ParameterError(f"initial {name} must be a finite number, got {value}")
        x0[STATE_NAMES.index(name)] = float(value)
    return x0


def scalar_speed(schedule: SpeedSchedule):
    """V(t) of ``schedule`` with plain float arithmetic.

    :meth:`SpeedSchedule.speed` works on arrays; called once per right-hand side evaluation its numpy overhead
    cost more than the vector field itself (18 s instead of 7 s for a 90 s ramp).  Same formula, checked against
    it in the tests.
    """
    start, end, ramp, t0 = float(schedule.start), schedule.end, float(schedule.ramp_time), float(schedule.t_start)
    if end is None:
        return lambda t: start
    end = float(end)

    def speed(t: float) -> float:
        s = (t - t0) / ramp
        s = 0.0 if s < 0.0 else 1.0 if s > 1.0 else s
        return start + s * (end - start)
    return speed


def integrate(model: ShimmyModel, pressures: TyrePressures, schedule: SpeedSchedule, duration: float,
             x0: np.ndarray | None = None, rtol: float = RTOL, atol: float = ATOL,
             sample_interval: float = SAMPLE_INTERVAL, progress: Callable[[float], None] | None = None,
             braking: Braking = FREE_ROLLING) -> Trajectory:
    """Integrate the reduced model over [0, duration] s from ``x0`` (default theta1 = 0.01 rad), under a steady
    ``braking`` (default free rolling; the caller starts it from the braked steady state, as
    :func:`comparisons.simulations.simulate` does).

    LSODA runs in ``scipy.integrate.ode``, asked for one sample at a time: it steps in compiled code and
    interpolates each sample from its own Nordsieck history, so Python runs only the right-hand side and one call
    per sample.  ``solve_ivp``'s LSODA (the same solver) returns to Python after every step and builds a dense
    output object there; at rtol 1e-9 that took twice as long (3.3 s against 1.6 s for 20 s at 180 km/h, 1.5 bar,
    t0 = 0.25 m), the samples differing by 1.5e-8 of the amplitude.

    The trajectory is complete, or stops early with status ``solver_failed`` (the integrator gave up) or
    ``diverged`` (an angle passed DIVERGENCE_ANGLE, checked on the samples); ``message`` says when.
    ``progress(t)`` is called every 1 % of the duration.  A non-finite right-hand side raises FloatingPointError.
    """
    if not duration > 0.0:
        raise ParameterError(f"duration must be positive, got {duration:g} s")
    if not sample_interval > 0.0:
        raise ParameterError(f"sample interval must be positive, got {sample_interval:g} s")
    x0 = initial_state() if x0 is None else np.asarray(x0, dtype=float)
    model.tyres(pressures, braking)  # raises ParameterError where the model is meaningless
    speed = scalar_speed(schedule)
    calls = [0]

    def rhs(t, x):
        calls[0] += 1
        dx = model.rhs(x, speed(t), pressures, braking)
        if not np.isfinite(dx.sum()):   # LSODA carries NaN on as if it were a number: stop and say where
            raise FloatingPointError(f"non-finite right-hand side of the reduced model at t = {t:.6g} s")
        return dx

    def jac(t, x):
        return model.jacobian(x, speed(t), pressures, braking)

    n = int(np.floor(duration / sample_interval + 1e-9)) + 1
    t = np.arange(n) * sample_interval
    if t[-1] < duration - 1e-12:
        t = np.append(t, duration)
    x = np.empty((len(t), N_STATES))
    x[0] = x0
    solver = scipy.integrate.ode(rhs, jac).set_integrator("lsoda", rtol=rtol, atol=atol, nsteps=MAX_STEPS)
    solver.set_initial_value(x0, 0.0)
    status, message, last = SimulationStatus.COMPLETE, NO_MESSAGE, len(t) - 1
    report_every, next_report = max(1, len(t) // 100), 0
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        for k in range(len(t)):
            if k > 0:
                if progress is not None and k >= next_report:
                    next_report = k + report_every
                    progress(float(t[k - 1]))
                x[k] = solver.integrate(t[k])
                if not solver.successful():
                    why = "; ".join(str(w.message) for w in caught) or f"return code {solver.get_return_code()}"
                    last, status = k - 1, SimulationStatus.SOLVER_FAILED
                    message = Message.of(f"LSODA stopped at t = {float(solver.t):.4f} s: {why}")
                    break
            if np.max(np.abs(x[k, ANGLE_INDEX])) > DIVERGENCE_ANGLE:
                last, status = k, SimulationStatus.DIVERGED
                message = Message.of(f"an angle passed {DIVERGENCE_ANGLE:g} rad at t = {t[k]:.3f} s (",
                                     Quantity("speed", float(speed(t[k])), 10), ")")
                break
    if progress is not None:
        progress(float(t[last]))
    t, x = t[:last + 1], x[:last + 1]
    integrator = (f"scipy.integrate.ode LSODA (exact Jacobian), rtol={rtol:g}, atol={atol:g}, "
                  f"sampled every {sample_interval:g} s")
    return Trajectory(t=t, x=x, speed=np.asarray(schedule.speed(t), dtype=float), model="reduced",
                      integrator=integrator, status=status, message=message,
                      extra={"rhs_evaluations": calls[0], "pressures": pressures, "effects": model.effects.names})
