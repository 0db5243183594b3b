"""Time simulations through the API (:func:`simulate`, one signature for both models), with their inputs: the
initial state in degrees, the speed schedule in km/h, the guard against runs of many minutes.

Under braking the run starts from, and is measured about, straight running under that braking: a steady state off
x = 0 (:meth:`~reduced_model.family.ShimmyFamily.steady`; the MBS's own), which the trajectory carries as its
``origin`` (:meth:`~reduced_model.trajectory.Trajectory.deviation`).  ``initial_deg`` is then the kick away from it.
Re-exported by :mod:`comparisons.api`, where the models live; this module reaches them only through their methods.
"""

from __future__ import annotations

import dataclasses
from typing import Callable, Mapping

import numpy as np

from axles.braking import FREE_ROLLING, Braking
from axles.input_file import check_range
from axles.limits import (
    ANGLE_RANGE_DEG,
    DURATION_RANGE_S,
    MAX_CYCLES,
    MBS_MAX_DURATION,
    RAMP_TIME_RANGE_S,
    RATE_RANGE_DEG_S,
    SPEED_RANGE_KMH,
)
from axles.parameters import ParameterError
from axles.pressures import TyrePressures
from axles.units import to_si
from comparisons.results import Simulation
from reduced_model.model import N_STATES, STATE_NAMES, STATE_UNITS
from reduced_model.simulation import initial_state
from reduced_model.trajectory import SpeedSchedule


def initial_from_degrees(initial_deg: Mapping[str, float] | None) -> np.ndarray:
    """The SI initial state of ``{state: degrees}`` (deg/s for the rates); None: theta1 = 0.573 deg (0.01 rad)."""
    if initial_deg is None:
        return initial_state()
    values = {}
    for name, value in initial_deg.items():
        if name not in STATE_NAMES:
            raise ParameterError(f"unknown state '{name}' in initial_deg (names: {' '.join(STATE_NAMES)})")
        unit = STATE_UNITS[STATE_NAMES.index(name)]
        rate = unit == "rad/s"
        value = check_range(f"initial {name}", value, *(RATE_RANGE_DEG_S if rate else ANGLE_RANGE_DEG),
                            "deg/s" if rate else "deg")
        values[name] = to_si(value, unit)
    return initial_state(values)


def schedule_of(speed_kmh: float | None, ramp_kmh: tuple[float, float, float] | None) -> SpeedSchedule:
    """The speed schedule of a constant speed (km/h) or a ramp (from km/h, to km/h, seconds)."""
    if (speed_kmh is None) == (ramp_kmh is None):
        raise ParameterError("give either speed_kmh or ramp_kmh=(FROM, TO, SECONDS)")
    if speed_kmh is not None:
        return SpeedSchedule.constant(to_si(check_range("speed_kmh", speed_kmh, *SPEED_RANGE_KMH, "km/h"), "m/s"))
    if len(ramp_kmh) != 3:
        raise ParameterError(f"ramp_kmh must be (FROM, TO, SECONDS), got {ramp_kmh!r}")
    start, end = (to_si(check_range(f"ramp_kmh {what}", v, *SPEED_RANGE_KMH, "km/h"), "m/s")
                  for what, v in zip(("FROM", "TO"), ramp_kmh[:2]))
    return SpeedSchedule.ramp(start, end, check_range("ramp_kmh SECONDS", ramp_kmh[2], *RAMP_TIME_RANGE_S, "s"))


def check_simulation_work(model, pressures: TyrePressures, schedule: SpeedSchedule, duration: float,
                          what: str = "duration_s", braking: Braking = FREE_ROLLING) -> None:
    """Refuse (:class:`ParameterError`, naming ``what``) a simulation that would run on for many minutes: an MBS
    run longer than :data:`~axles.limits.MBS_MAX_DURATION`, or one whose fastest oscillation needs more than
    :data:`~axles.limits.MAX_CYCLES` periods resolved.

    Within the physical ranges an axle can still combine a stiff tie rod with a light wheel (k1 = 1e8 N m/rad,
    I1 = 0.1 kg m^2 oscillate at 7 kHz): both integrators must follow every period of such a mode, and 20 s take
    hours.  The fastest frequency is read from the linearisation of the model that runs (``model`` a
    :class:`~comparisons.api.ReducedModel` or :class:`~comparisons.api.MultibodyModel`), at straight running
    under ``braking``, at both ends of the speed range: the MBS's own, whose full geometry adds modes (steering
    gear, lateral travel) the reduced model does not have.
    """
    mbs = hasattr(model, "fidelity")
    if mbs and duration > MBS_MAX_DURATION:
        option = f"{what} with --model mbs" if what.startswith("--") else f"{what} of the multibody model"
        raise ParameterError(f"{option} must be at most {MBS_MAX_DURATION:g} s (about 2 s of computing per "
                             f"simulated second), got {duration:g}")
    speeds = {schedule.start} | ({schedule.end} if schedule.end is not None else set())
    family = model.problem(pressures, "pressure", braking)
    fastest = max(float(np.max(np.abs(np.linalg.eigvals(family.linear_matrix(v, family.nominal)).imag)))
                  for v in speeds) / (2 * np.pi)
    cycles = fastest * duration
    if cycles > MAX_CYCLES:
        which = "the MBS's" if mbs else "the axle's"
        raise ParameterError(f"{which} fastest oscillation, {fastest:.4g} Hz, would need {cycles:.3g} periods "
                             f"resolved in {duration:g} s (limit {MAX_CYCLES:g}): shorten {what} or check the "
                             f"stiffnesses and inertias (k1, k2, I1, ...)")


def steady_start(model, pressures: TyrePressures, braking: Braking, speed: float) -> np.ndarray | None:
    """Straight running under ``braking`` at ``speed`` (m/s) in the model's own state order (the MBS's extended
    one), or None free rolling (x = 0)."""
    if not braking.active:
        return None
    family = model.problem(pressures, "pressure", braking)
    return family.equilibrium(speed, family.nominal)


def simulate(model, pressures: TyrePressures, *, speed_kmh: float | None = None,
             ramp_kmh: tuple[float, float, float] | None = None, duration_s: float,
             initial_deg: Mapping[str, float] | None = None, progress: Callable[[float], None] | None = None,
             poses: bool = False, allow_long: bool = False, braking: Braking = FREE_ROLLING) -> Simulation:
    """A time simulation of either model (a :class:`~comparisons.api.ReducedModel` or
    :class:`~comparisons.api.MultibodyModel`), the same call for both: at a constant ``speed_kmh`` or along
    ``ramp_kmh=(FROM, TO, SECONDS)`` (then held), for ``duration_s`` s from ``initial_deg`` (degrees, deg/s for
    the rates; default theta1 = 0.573 deg).  Under ``braking`` (:class:`~axles.braking.Braking`) the start is
    straight running under it plus ``initial_deg``, and the trajectory's amplitudes are measured about that steady
    state (its ``origin``).  The reduced model runs on scipy, the MBS on Exudyn (about 2 s of computing per
    simulated second).  ``progress(t)`` is called with the simulated time every 1 % of the duration;
    ``poses`` keeps the MBS bodies' poses in the trajectory, for a 3D recording
    (:func:`comparisons.recordings.writer.write_recording`).  As the command, a run that would take many minutes
    is refused (:func:`check_simulation_work`: the MBS beyond 100 s, or more than 50000 periods of the fastest
    oscillation); ``allow_long=True`` runs it anyway.

    >>> from comparisons.api import Axle
    >>> run = simulate(Axle.paper().reduced(), TyrePressures.both(2.5), speed_kmh=60, duration_s=2)
    >>> run.status.value
    'complete'
    """
    if not isinstance(braking, Braking):
        raise TypeError(f"braking must be Braking, got {type(braking).__name__}")
    schedule = schedule_of(speed_kmh, ramp_kmh)
    duration = check_range("duration_s", duration_s, *DURATION_RANGE_S, "s")
    x0 = initial_from_degrees(initial_deg)
    if not allow_long:
        check_simulation_work(model, pressures, schedule, duration, braking=braking)
    steady = steady_start(model, pressures, braking, schedule.start)
    if steady is not None:
        x0 = steady + np.concatenate([x0, np.zeros(len(steady) - N_STATES)])
    trajectory = model.run(pressures, schedule, x0, duration, progress=progress, poses=poses, braking=braking)
    if steady is not None:
        trajectory = dataclasses.replace(trajectory, origin=np.array(steady[:N_STATES], dtype=float))
    braked = f", {braking}" if braking.active else ""
    return Simulation(f"{model.label()}, {pressures}{braked}, axle {model.axle.data.shown_name}", trajectory)
