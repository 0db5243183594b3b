"""Time simulation of the multibody axle in Exudyn, at constant speed or along a speed ramp.

Integrator: Exudyn's explicit Runge-Kutta solvers on the kinematic tree (no constraints), fixed step.  Explicit
solvers evaluate the tyre states consistently at every stage, so the implicit solvers' trap of a zero initial
ODE1 derivative at the start of a run does not arise.  The default is the classical RK44 with
h = :data:`DEFAULT_STEP` = 1 ms, sampled every millisecond like the reduced model's trajectories: at 1.5 bar and
100 km/h its error is about 3e-6 of each state's amplitude, and halving the step changes a run by less than 1e-4
(``tests/test_mbs_simulation.py``).  :data:`FAST_METHOD` / :data:`FAST_STEP` (RK67, 1/240 s) is the cheapest
fixed-step setting found that stays within 1e-4 (all states, 10 s at 100 km/h, full geometry).  DOPRI5 with
automatic step size at the tolerances of :data:`BENCH_SETTINGS` stays within 1e-4 of the same run with half the
force evaluations (the benchmark's setting).  ``step`` and ``method`` (and for DOPRI5 the tolerances) can be chosen,
and :func:`convergence` compares a run with the same run at a smaller step.

The wheel spin follows the speed schedule, Omega(t) = V(t)/R, through the rotor moments of
:mod:`mbs_shimmy.forces`.  A run stops early with status ``diverged`` when an angle leaves the range where the model
means anything (:data:`DIVERGENCE_ANGLE`) or a value is not finite, and with ``solver_failed`` when Exudyn's solver
gives up; either way the trajectory up to that time is kept and ``message`` gives the time and the state.
"""

from __future__ import annotations

import math
from typing import Callable
from dataclasses import dataclass, field


from mbs_shimmy import engine  # noqa: F401  (before exudyn: chooses Exudyn's compiled module)

# isort: split
import exudyn as exu
import numpy as np

from axles.braking import FREE_ROLLING, Braking
from bifurcation.messages import Message
from axles.dimensions import DEFAULT_DIMENSIONS, AxleDimensions
from mbs_shimmy.fidelity import Fidelity
from mbs_shimmy.geometry import SIDES, quaternions_xyzw
from mbs_shimmy.model import MbsModel
from reduced_model.model import N_STATES, STATE_NAMES, Effects
from axles.parameters import YANG2024, ParameterError, ShimmyParameters
from axles.pressures import TyrePressures
from reduced_model.trajectory import SimulationStatus, SpeedSchedule, Trajectory

DEFAULT_METHOD = "RK44"
DEFAULT_STEP = 1e-3          # s
DEFAULT_SPEED = 16.666666666666668   # m/s (60 km/h)
# The cheapest fixed-step setting found that keeps a 10 s run at 1.5 bar, 100 km/h (full geometry) within 1e-4 of
# every state's amplitude (measured against step/4: ``tests/test_mbs_simulation.py``); used by the benchmark.
FAST_METHOD = "RK67"
FAST_STEP = 1.0 / 240.0      # s
# The benchmark's settings (``shimmy bench mbs_simulation_full mbs_simulation_reduced``), the cheapest found within
# 1e-4 of every state's amplitude of RK67 at 1/960 s over its run (``tests/test_mbs_benchmark_accuracy.py``).  Full
# geometry: Exudyn's DOPRI5 with automatic step size, largest step 10 ms (also the sampling interval), relative
# tolerance 2e-5 and absolute 2e-7 (rad, m): 4.0e-5 with 8 400 force evaluations against RK67's 16 800 at 1/240 s
# (3.8e-5): the fixed step is set by the fastest mode (114 rad/s) all the time, the adaptive one only while that mode
# is large.  (rtol 1e-5: 3.1e-5, 9 400 evaluations; 5e-5: 9.0e-5, too close; 1e-4: 1.8e-4.)  Reduced fidelity: DOPRI5 would need rtol 3e-6 and 14 700 evaluations for 7.6e-5 (worst state alpha2),
# so it keeps RK67 at 1/240 s (3.8e-5).
BENCH_SETTINGS = {"full": {"method": "DOPRI5", "step": 0.01, "rtol": 2e-5, "atol": 2e-7},
                  "reduced": {"method": FAST_METHOD, "step": FAST_STEP}}
OUTPUT_INTERVAL = 1e-3       # s between stored samples
DIVERGENCE_ANGLE = 1.0       # rad: beyond this a steer, tramp or slip angle makes the geometry meaningless
METHODS = {"RK44": exu.DynamicSolverType.RK44, "RK67": exu.DynamicSolverType.RK67,
           "RK33": exu.DynamicSolverType.RK33, "DOPRI5": exu.DynamicSolverType.DOPRI5}
FIXED_STEP_METHODS = ("RK44", "RK67", "RK33")


class _Schedule:
    """Scalar V(t), dV/dt of a :class:`SpeedSchedule` without numpy overhead inside the user functions."""

    def __init__(self, schedule: SpeedSchedule):
        self.s = schedule
        self.constant = schedule.is_constant
        self.v0 = float(schedule.start)

    def speed(self, t: float) -> float:
        return self.v0 if self.constant else float(self.s.speed(t))

    def acceleration(self, t: float) -> float:
        return 0.0 if self.constant else float(self.s.acceleration(t))


@dataclass
class _Watch:
    """Divergence watch run before every step; it also reports the simulated time to ``progress`` every
    ``every`` seconds of it."""

    limit: float
    stopped_at: float | None = None
    state: np.ndarray | None = None
    reason: str = ""
    progress: Callable[[float], None] | None = None
    every: float = math.inf
    _next: float = 0.0

    def __call__(self, mbs, t) -> bool:
        if self.progress is not None and t >= self._next:
            self._next = t + self.every
            self.progress(t)
        sd = mbs.systemData
        q = sd.GetODE2Coordinates()
        v = sd.GetODE2Coordinates_t()      # its last two entries are the slip angles
        m = len(q) - 2
        big = max(float(np.max(np.abs(q[0:m]))), abs(v[m]), abs(v[m + 1]))
        if not big <= self.limit:        # also catches NaN
            self.stopped_at = t
            self.state = np.concatenate([q[0:m], v])
            self.reason = "not finite" if not math.isfinite(big) else f"an angle passed {self.limit:g} rad"
            return False
        return True


def integrate(params: ShimmyParameters = YANG2024, effects: Effects | None = None, fidelity: Fidelity | None = None,
             pressures: TyrePressures = TyrePressures.uniform(2.5e5), schedule: SpeedSchedule | None = None,
             x0: np.ndarray | None = None, duration: float = 2.0, *, dims: AxleDimensions = DEFAULT_DIMENSIONS,
             step: float = DEFAULT_STEP, method: str = DEFAULT_METHOD, output_interval: float | None = None,
             poses: bool = True, rtol: float | None = None, atol: float | None = None,
             progress: Callable[[float], None] | None = None, braking: Braking = FREE_ROLLING) -> Trajectory:
    """Simulate the MBS over [0, duration] s from ``x0`` (reduced-model state order and SI; default theta1 =
    0.01 rad) with the speed ``schedule`` (default 60 km/h) at the tyres' ``pressures``.  ``progress(t)`` is
    called with the simulated time (s) every 1 % of the duration.

    ``poses`` adds body poses and contact forces to ``extra`` (see :func:`pose_record`).  Samples every
    ``output_interval`` s (default the larger of 1 ms and the step).  With an adaptive method (``DOPRI5``)
    ``step`` is the largest step and ``rtol`` / ``atol`` the relative / absolute error tolerances of a step
    (default Exudyn's); the samples are then the first steps past each ``output_interval``.  ``braking``: a steady
    braking of the wheels (:class:`~axles.braking.Braking`; the speed is then held, as in the families).
    """
    effects = effects or Effects()
    fidelity = fidelity or Fidelity.reduced()
    schedule = schedule or SpeedSchedule.constant(DEFAULT_SPEED)
    if not (isinstance(duration, (int, float)) and math.isfinite(duration) and duration > 0.0):
        raise ParameterError(f"duration must be positive, got {duration!r} s")
    if method not in METHODS:
        raise ParameterError(f"unknown integrator '{method}' (known: {', '.join(METHODS)})")
    if not (math.isfinite(step) and 0.0 < step <= 0.05):
        raise ParameterError(f"step must be in (0, 0.05] s, got {step!r}")
    for name, tol in (("rtol", rtol), ("atol", atol)):
        if tol is not None and not (isinstance(tol, (int, float)) and math.isfinite(tol) and tol > 0.0):
            raise ParameterError(f"{name} must be a positive number, got {tol!r}")
    if output_interval is None:
        output_interval = max(OUTPUT_INTERVAL, step)
    if not (math.isfinite(output_interval) and output_interval >= step * (1 - 1e-9)):
        raise ParameterError(f"output interval must be at least the step ({step:g} s), got {output_interval!r}")
    model = MbsModel(params, effects, fidelity, dims)
    layout = model.layout
    if x0 is None:
        x0 = np.zeros(N_STATES)
        x0[STATE_NAMES.index("theta1")] = 0.01
    x0 = np.asarray(x0, dtype=float)
    if x0.shape == (N_STATES,):        # the new coordinates start at rest at zero
        x0 = np.concatenate([x0, np.zeros(layout.n - N_STATES)])
    if x0.shape != (layout.n,) or not np.all(np.isfinite(x0)):
        raise ParameterError(f"initial state must be {N_STATES} finite numbers ({', '.join(STATE_NAMES)})"
                             + (f" or {layout.n} ({', '.join(layout.state_names)})" if layout.n > N_STATES else ""))

    sched = _Schedule(schedule)
    system = model.system(pressures, sched.speed, None if sched.constant else sched.acceleration, y0=x0[layout.x_to_y],
                          output_interval=output_interval, braking=braking)
    mbs = system.mbs
    watch = _Watch(DIVERGENCE_ANGLE, progress=progress, every=0.01 * duration)
    mbs.SetPreStepUserFunction(watch)

    settings = exu.SimulationSettings()
    ti = settings.timeIntegration
    n_steps = max(1, int(round(duration / step)))
    ti.endTime = duration
    ti.numberOfSteps = n_steps
    ti.verboseMode = 0
    ti.automaticStepSize = method not in FIXED_STEP_METHODS
    if rtol is not None:
        ti.relativeTolerance = float(rtol)
    if atol is not None:
        ti.absoluteTolerance = float(atol)
    ti.explicit.computeEndOfStepAccelerations = False
    settings.solution.file.write = False
    settings.solution.sensors.writePeriod = output_interval
    h = duration / n_steps
    integrator = (f"Exudyn {method} (explicit Runge-Kutta on the kinematic tree), fixed step {h:.6g} s"
                  if method in FIXED_STEP_METHODS else
                  f"Exudyn {method}, adaptive step up to {h:.6g} s, tolerances {ti.absoluteTolerance:g} abs / "
                  f"{ti.relativeTolerance:g} rel")

    status, message = SimulationStatus.COMPLETE, ""
    # Exudyn warns about memory allocations in every step (expected: the forces are Python user functions) and
    # prints solver failures to the console; both would corrupt a JSON output, and failures are reported here.
    previous = (exu.config.suppressWarnings, exu.config.printToConsole)
    exu.config.suppressWarnings, exu.config.printToConsole = True, False
    try:
        ok = mbs.SolveDynamic(settings, solverType=METHODS[method])
    except Exception as exc:          # Exudyn raises its own error types; keep what was computed
        text = str(exc).strip().splitlines()
        ok, message = False, f"Exudyn solver error ({text[0] if text else type(exc).__name__})"
    finally:
        exu.config.suppressWarnings, exu.config.printToConsole = previous
    if system.error is not None:
        ok = False
        message = (f"solver failed at t = {system.error[0]:.6g} s: force evaluation raised "
                   f"{type(system.error[1]).__name__}: {system.error[1]}")
    t, y = _stored(system)
    if watch.stopped_at is not None:
        status = SimulationStatus.DIVERGED
        message = (f"diverged at t = {watch.stopped_at:.6g} s ({watch.reason}); "
                   f"state {_describe(watch.state[layout.y_to_x], layout)}")
    elif not ok:
        status = SimulationStatus.SOLVER_FAILED
        last = (f"last stored t = {t[-1]:.6g} s, state {_describe(y[-1][layout.y_to_x], layout)}" if len(t)
                else "no output")
        message = f"{message or 'Exudyn solver failed'}; {last}"
    message = Message.of(message)
    x_ext = y[:, layout.y_to_x] if len(t) else np.zeros((0, layout.n))
    x = x_ext[:, :N_STATES]
    speed = np.asarray(schedule.speed(t), dtype=float) if len(t) else np.zeros(0)
    extra = {"fidelity": fidelity.label, "effects": list(effects.names), "step": h, "method": method,
             "force_evaluations": system.calls,
             "extra_states": {name: x_ext[:, N_STATES + k] for k, name in enumerate(layout.state_names[N_STATES:])}}
    if poses and len(t):
        extra.update(pose_record(model, pressures, schedule, t, y))
    return Trajectory(t=t, x=x, speed=speed, model="mbs", integrator=integrator, status=status, message=message,
                      extra=extra)


def extended_states(trajectory: Trajectory) -> np.ndarray:
    """(N, n) states of an MBS trajectory in the extended order: the reduced model's eight, then the new
    coordinates and rates (:attr:`mbs_shimmy.system.Layout.state_names`)."""
    extra = trajectory.extra.get("extra_states", {})
    return np.column_stack([trajectory.x] + [np.asarray(v) for v in extra.values()])


def _stored(system) -> tuple[np.ndarray, np.ndarray]:
    data = {name: np.asarray(system.mbs.GetSensorStoredData(s)) for name, s in system.sensors.items()}
    q = data["q"]
    m = system.layout.n_mech
    if q.ndim != 2 or len(q) == 0:
        return np.zeros(0), np.zeros((0, system.layout.n))
    n = min(len(q), len(data["q_t"]))
    t = q[:n, 0]
    y = np.column_stack([q[:n, 1:1 + m], data["q_t"][:n, 1:m + 3]])
    # Exudyn may store the final time twice (last step and end of simulation)
    keep = np.concatenate([[True], np.diff(t) > 1e-12])
    return t[keep], y[keep]


def _describe(x: np.ndarray, layout) -> str:
    return ", ".join(f"{n} = {v:.4g}" for n, v in zip(layout.state_names, x))


def pose_record(model: MbsModel, pressures: TyrePressures, schedule: SpeedSchedule, t: np.ndarray, y: np.ndarray) -> dict:
    """Body poses and tyre forces at each sample, vehicle frame (moving with the speed along x), SI.

    Returns ``{"bodies": {name: {"position": (N,3), "quaternion_xyzw": (N,4)}}, "links": {"tie_rod": (N,2,3),
    "drag_link": (N,2,3)}, "contact": {"right"|"left": {"point": (N,3), "force": (N,3)}}, "travel": (N,)}``.
    Bodies: ``axle`` (at O on the roll axis), ``knuckle_right``/``knuckle_left`` (at the kingpin point, frame of
    the axle at zero steer), ``wheel_right``/``wheel_left`` (at the wheel centre, including the spin angle
    integral of V/R about the wheel axis).  The contact force is the tyre's total force on the wheel at the contact
    point (vertical, rolling resistance, k4 spring, Magic Formula).  Poses are Exudyn's (the markers of the
    geometry tree, caster-tilted whatever the fidelity), read at each stored state ``y`` (MBS order).
    """
    speed = np.asarray(schedule.speed(t), dtype=float)
    travel = np.concatenate([[0.0], np.cumsum(0.5 * (speed[1:] + speed[:-1]) * np.diff(t))])
    spin_angle = travel / model.params.R
    sched = _Schedule(schedule)
    system = model.system(pressures, sched.speed, None if sched.constant else sched.acceleration, drawing=True)
    forces, mk, get = system.forces, system.markers, system.mbs.GetMarkerOutput
    OV = exu.OutputVariableType
    layout = system.layout
    m = layout.n_mech
    n = len(t)
    names = ("axle", "knuckle_right", "knuckle_left", "wheel_right", "wheel_left")
    # Exudyn's outputs are read per sample; the rotations, quaternions and wheel points after the loop, for all
    # samples at once
    axle_pos, axle_rot = np.zeros((n, 3)), np.zeros((n, 9))
    knuckle_pos, knuckle_rot = np.zeros((2, n, 3)), np.zeros((2, n, 9))
    tie = np.zeros((n, 2, 3))
    drag = np.zeros((n, 2, 3))
    cpoint = {k: np.zeros((n, 3)) for k in ("right", "left")}
    cforce = {k: np.zeros((n, 3)) for k in ("right", "left")}
    labels = ["right" if side < 0 else "left" for side in SIDES]
    for k in range(n):
        system.set_state(y[k])
        axle_pos[k] = get(mk.axle, OV.Position)
        axle_rot[k] = get(mk.axle, OV.RotationMatrix)
        states: list = []
        forces.evaluate(float(t[k]), list(y[k, 0:m]) + [0.0, 0.0], list(y[k, m:2 * m + 2]), states=states)
        for i, label in enumerate(labels):
            knuckle_pos[i, k] = get(mk.knuckles[i], OV.Position)
            knuckle_rot[i, k] = get(mk.knuckles[i], OV.RotationMatrix)
            tie[k, i] = get(mk.tie_rod[i], OV.Position)
            cpoint[label][k] = states[i].point
            cforce[label][k] = states[i].force
        drag[k, 0] = get(mk.drag_link[0], OV.Position)
        drag[k, 1] = get(mk.drag_link[1], OV.Position)
    # the roll link's frame is turned onto the (sloped) roll axis: undo that for the axle's own frame
    roll_frame = np.array(forces.g_exact.roll_joint_rotation)
    pos = {"axle": axle_pos}
    quat = {"axle": quaternions_xyzw(axle_rot.reshape(n, 3, 3) @ roll_frame.T)}
    c, s = np.cos(spin_angle), np.sin(spin_angle)
    spin = np.zeros((n, 3, 3))       # rotation about the wheel axis (y) by the spin angle
    spin[:, 0, 0], spin[:, 0, 2], spin[:, 1, 1], spin[:, 2, 0], spin[:, 2, 2] = c, s, 1.0, -s, c
    for i, (side, label) in enumerate(zip(SIDES, labels)):
        T = np.array(forces.g_exact.joint_rotation(side))
        rot = knuckle_rot[i].reshape(n, 3, 3) @ T.T             # the axle frame at zero steer
        pos[f"knuckle_{label}"] = knuckle_pos[i]
        quat[f"knuckle_{label}"] = quaternions_xyzw(rot)
        pos[f"wheel_{label}"] = knuckle_pos[i] + side * model.params.l * rot[:, :, 1]
        quat[f"wheel_{label}"] = quaternions_xyzw(rot @ spin)
    return {"bodies": {k: {"position": pos[k], "quaternion_xyzw": quat[k]} for k in names},
            "links": {"tie_rod": tie, "drag_link": drag},
            "contact": {k: {"point": cpoint[k], "force": cforce[k]} for k in ("right", "left")},
            "travel": travel}


@dataclass(frozen=True)
class Convergence:
    """A run against the same run at half the step: max state difference relative to each state's amplitude."""

    step: float
    max_relative_difference: float        # max over states of max_t |x_h - x_h/2| / max_t |x_h/2|
    per_state: dict = field(compare=False, default_factory=dict)

    @property
    def converged(self) -> bool:
        return self.max_relative_difference <= 1e-4


def convergence(trajectory: Trajectory, finer: Trajectory) -> Convergence:
    """Compare two runs on their common samples (relative to each state's amplitude in the finer run)."""
    n = min(len(trajectory.t), len(finer.t))
    if n == 0 or not np.allclose(trajectory.t[:n], finer.t[:n], atol=1e-9):
        raise ValueError("trajectories have no common sample times")
    diff = np.max(np.abs(trajectory.x[:n] - finer.x[:n]), axis=0)
    amp = np.max(np.abs(finer.x[:n]), axis=0)
    rel = {name: float(d / a) if a > 0 else 0.0 for name, d, a in zip(STATE_NAMES, diff, amp)}
    return Convergence(float(trajectory.extra.get("step", math.nan)), max(rel.values()), rel)

