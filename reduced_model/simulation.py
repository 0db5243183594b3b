"""Time simulation of the reduced model at constant speed or along a speed schedule.

Integrator: scipy's LSODA (``scipy.integrate.solve_ivp``; Petzold, SIAM J. Sci. Stat. Comput. 4, 1983; Hindmarsh,
ODEPACK, 1983) with the exact complex-step Jacobian.  LSODA switches between Adams (non-stiff) and BDF (stiff)
by itself, so the same call serves the whole speed range, and it keeps a dense output.  At the default
tolerances (rtol = 1e-9, atol = 1e-11 in SI: rad, rad/s) a 10 s run at 180 km/h costs about one second, like
DOP853 and far less than Radau or BDF (this model is only mildly stiff: its fastest rate is the slip relaxation
V / sigma, about 150 1/s at 350 km/h).  The dense output is sampled on a uniform grid for the trajectory.

Along a speed ramp the speed is an explicit function of time in the right-hand side; the speed schedule and the
trajectory type are shared with the multibody model (:mod:`reduced_model.trajectory`).
"""

from __future__ import annotations

from typing import Callable

import numpy as np
import scipy.integrate

from bifurcation.messages import NO_MESSAGE, Message, Quantity
from reduced_model.model import N_STATES, STATE_NAMES, ShimmyModel
from axles.parameters import ParameterError
from axles.braking import FREE_ROLLING, Braking
from axles.pressures import TyrePressures
from reduced_model.trajectory import SimulationStatus, SpeedSchedule, Trajectory

METHOD = "LSODA"
RTOL = 1e-9
ATOL = 1e-11
SAMPLE_INTERVAL = 1e-3        # s between stored samples of the dense output
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
             x0: np.ndarray | None = None, method: str = METHOD, rtol: float = RTOL, atol: float = ATOL,
             sample_interval: float = SAMPLE_INTERVAL, progress: Callable[[float], None] | None = None,
             braking: Braking = FREE_ROLLING) -> Trajectory:
    """Integrate the reduced model over [0, duration] s from ``x0`` (default theta1 = 0.01 rad), under a steady
    ``braking`` (default free rolling; the caller starts it from the braked steady state, as
    :func:`comparisons.simulations.simulate` does).

    The trajectory is complete, or stops early with status ``solver_failed`` (the integrator gave up) or
    ``diverged`` (an angle passed DIVERGENCE_ANGLE); ``message`` says when.  ``progress(t)`` is called every
    1 % of the duration.
    """
    if not duration > 0.0:
        raise ParameterError(f"duration must be positive, got {duration:g} s")
    x0 = initial_state() if x0 is None else np.asarray(x0, dtype=float)
    model.tyres(pressures, braking)  # raises ParameterError where the model is meaningless

    speed = scalar_speed(schedule)

    next_report = [0.0]

    def rhs(t, x):
        if progress is not None and t >= next_report[0]:
            next_report[0] = t + 0.01 * duration
            progress(min(t, duration))
        dx = model.rhs(x, speed(t), pressures, braking)
        if not np.isfinite(dx.sum()):   # LSODA retries a non-finite step forever: stop and say where
            raise FloatingPointError(f"non-finite right-hand side of the reduced model at t = {t:.6g} s")
        return dx

    def jac(t, x):
        return model.jacobian(x, speed(t), pressures, braking)

    kwargs = {"jac": jac} if method in ("LSODA", "Radau", "BDF") else {}
    sol = scipy.integrate.solve_ivp(rhs, (0.0, duration), x0, method=method, rtol=rtol, atol=atol,
                                    dense_output=True, **kwargs)
    # Divergence is checked on the solver's steps afterwards: a terminal event costs a third of the run time.
    beyond = np.nonzero(np.max(np.abs(sol.y[ANGLE_INDEX]), axis=0) > DIVERGENCE_ANGLE)[0]
    t_end = float(sol.t[beyond[0]]) if len(beyond) else float(sol.t[-1])
    if sol.sol is not None:
        n = int(np.floor(t_end / sample_interval + 1e-9)) + 1
        t = np.arange(n) * sample_interval
        if t[-1] < t_end - 1e-12:
            t = np.append(t, t_end)
        x = sol.sol(t).T
    else:  # the solver failed on its first step: only what it has
        keep = sol.t <= t_end
        t, x = sol.t[keep], sol.y[:, keep].T
    status, message = SimulationStatus.COMPLETE, NO_MESSAGE
    if len(beyond):
        status = SimulationStatus.DIVERGED
        message = Message.of(f"an angle passed {DIVERGENCE_ANGLE:g} rad at t = {t_end:.3f} s (",
                             Quantity("speed", float(schedule.speed(t_end)), 10), ")")
    elif sol.status != 0:
        status = SimulationStatus.SOLVER_FAILED
        message = Message.of(f"{method} stopped at t = {t_end:.4f} s: {sol.message}")
    jacobian = " (exact Jacobian)" if "jac" in kwargs else ""
    integrator = (f"scipy.integrate.solve_ivp {method}{jacobian}, rtol={rtol:g}, atol={atol:g}, "
                  f"dense output sampled every {sample_interval:g} s")
    return Trajectory(t=t, x=x, speed=np.asarray(schedule.speed(t), dtype=float), model="reduced",
                      integrator=integrator, status=status, message=message,
                      extra={"solver_steps": int(len(sol.t)), "rhs_evaluations": int(sol.nfev),
                             "pressures": pressures, "effects": model.effects.names})
