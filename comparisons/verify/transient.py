"""A transient of both models compared: from the same small yaw angle of wheel 1 at a constant speed, the MBS with
every assumption of the reduced model on (Exudyn, fixed-step RK67) against the reduced model (DOP853, rtol 1e-12),
every state within :data:`TRANSIENT_TOL` of its amplitude.

Used by the ``Transient`` section of ``shimmy verify`` and by the pytest plugin's ``test_transient_equal``
(:mod:`comparisons.verify.equivalence_checks`); where straight running is stable the kick decays in both models,
which is what an axle without shimmy still gets checked on.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from axles.axle import interface_text
from axles.units import from_kmh

TRANSIENT_TOL = 1e-4        # of the amplitude of each state (the MBS's fixed-step RK67 against DOP853 at rtol 1e-12)
KICK_RAD = 0.01             # initial yaw angle of wheel 1


@dataclass(frozen=True)
class TransientCheck:
    speed_kmh: float
    duration: float              # s
    complete: bool               # the MBS run reached the end
    message: str                 # why it stopped, when it did
    worst_relative: float        # largest difference of a state, over that state's amplitude
    decay_reduced: float         # |x(end)| / |x(0)| of the reduced model's (theta1, theta2, psi)
    decay_mbs: float

    @property
    def ok(self) -> bool:
        return self.complete and self.worst_relative <= TRANSIENT_TOL

    @property
    def decays(self) -> bool:
        return self.decay_reduced < 1.0 and self.decay_mbs < 1.0


def transient_check(axle, pressures, speed_kmh: float, duration: float) -> TransientCheck:
    """Both models from a yaw kick of wheel 1 at ``speed_kmh`` for ``duration`` s, compared."""
    from scipy.integrate import solve_ivp

    from mbs_shimmy.fidelity import Fidelity
    from mbs_shimmy.simulation import integrate
    from reduced_model.model import STATE_NAMES, Effects, ShimmyModel
    from reduced_model.trajectory import SpeedSchedule
    model = ShimmyModel(axle.params)
    x0 = np.zeros(len(STATE_NAMES))
    x0[STATE_NAMES.index("theta1")] = KICK_RAD
    V = from_kmh(speed_kmh)
    traj = integrate(axle.params, Effects(), Fidelity.reduced(), pressures, SpeedSchedule.constant(V), x0, duration,
                    dims=axle.dims, poses=False)
    if not traj.complete:
        return TransientCheck(speed_kmh, duration, False, interface_text(traj.message), math.inf, math.nan, math.nan)
    ref = solve_ivp(lambda t, x: model.rhs(x, V, pressures), (0.0, duration), x0, method="DOP853", rtol=1e-12,
                    atol=1e-14, dense_output=True)
    xr = ref.sol(traj.t).T
    amplitude = np.max(np.abs(xr), axis=0)
    worst = np.max(np.abs(traj.x - xr), axis=0)
    rel = float(np.max((worst - 1e-12).clip(min=0.0) / (amplitude + 1e-300)))
    angles = [STATE_NAMES.index(n) for n in ("theta1", "theta2", "psi")]

    def decay(x: np.ndarray) -> float:
        return float(np.linalg.norm(x[-1, angles]) / np.linalg.norm(x0[angles]))
    return TransientCheck(speed_kmh, duration, True, "", rel, decay(xr), decay(traj.x))
