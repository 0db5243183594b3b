"""Speed schedules and the trajectory type shared by every simulation in the project (reduced model and MBS).

The state columns are always the reduced model's, in its order and SI units (``model.STATE_NAMES``), so that
trajectories of both models compare column by column; a model with more states puts them in ``extra``.  A run about
a steady state off x = 0 (straight running under braking) carries it as ``origin``: amplitudes are measured about it
(:meth:`Trajectory.deviation`), never from 0.
"""

from __future__ import annotations

import enum
from dataclasses import dataclass, field

import numpy as np

from bifurcation.messages import NO_MESSAGE, Message
from reduced_model.model import STATE_NAMES


@dataclass(frozen=True)
class SpeedSchedule:
    """V(t): ``start`` (m/s) held until ``t_start``, linear to ``end`` over ``ramp_time`` s, then held."""

    start: float
    end: float | None = None
    ramp_time: float = 0.0
    t_start: float = 0.0

    def __post_init__(self) -> None:
        if not self.start > 0.0 or (self.end is not None and not self.end > 0.0):
            raise ValueError("speeds must be positive")
        if self.end is not None and not self.ramp_time > 0.0:
            raise ValueError("a ramp needs a positive duration")

    @classmethod
    def constant(cls, speed: float) -> "SpeedSchedule":
        return cls(start=speed)

    @classmethod
    def ramp(cls, start: float, end: float, seconds: float) -> "SpeedSchedule":
        return cls(start=start, end=end, ramp_time=seconds)

    @property
    def is_constant(self) -> bool:
        return self.end is None

    def speed(self, t):
        if self.end is None:
            return self.start + 0.0 * np.asarray(t, dtype=float)
        s = np.clip((np.asarray(t, dtype=float) - self.t_start) / self.ramp_time, 0.0, 1.0)
        return self.start + s * (self.end - self.start)

    def acceleration(self, t):
        if self.end is None:
            return 0.0 * np.asarray(t, dtype=float)
        tt = np.asarray(t, dtype=float) - self.t_start
        inside = (tt >= 0.0) & (tt < self.ramp_time)
        return np.where(inside, (self.end - self.start) / self.ramp_time, 0.0)


class SimulationStatus(enum.Enum):
    COMPLETE = "complete"
    SOLVER_FAILED = "solver_failed"   # the integrator gave up (step size, Newton); ``message`` says when
    DIVERGED = "diverged"             # states left the physically meaningful range


@dataclass(frozen=True)
class Trajectory:
    """A simulated run: time (s), states (N x 8, reduced-model order, SI), speed (m/s) at each sample."""

    t: np.ndarray
    x: np.ndarray
    speed: np.ndarray
    model: str                        # "reduced" or "mbs"
    integrator: str                   # method, tolerances or step: enough to reproduce the run
    status: SimulationStatus = SimulationStatus.COMPLETE
    message: Message = NO_MESSAGE
    extra: dict = field(default_factory=dict, compare=False)  # e.g. MBS body poses, tyre forces
    origin: np.ndarray | None = None  # (8,) the steady state the run oscillates about (None: x = 0, free rolling)

    def __post_init__(self) -> None:
        if self.x.ndim != 2 or self.x.shape != (len(self.t), len(STATE_NAMES)):
            raise ValueError(f"states must be (N, {len(STATE_NAMES)}), got {self.x.shape}")
        if self.origin is not None and np.shape(self.origin) != (len(STATE_NAMES),):
            raise ValueError(f"origin must be ({len(STATE_NAMES)},), got {np.shape(self.origin)}")

    @property
    def complete(self) -> bool:
        return self.status is SimulationStatus.COMPLETE

    def state(self, name: str) -> np.ndarray:
        return self.x[:, STATE_NAMES.index(name)]

    def deviation(self, name: str) -> np.ndarray:
        """The state ``name`` less its steady value (:attr:`origin`): what an amplitude max|x| is taken of."""
        k = STATE_NAMES.index(name)
        return self.x[:, k] if self.origin is None else self.x[:, k] - self.origin[k]
