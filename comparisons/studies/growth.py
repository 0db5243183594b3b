"""Growth or decay of a small oscillation of the full multibody axle against its linearisation: a simulation
started along the critical mode near straight running grows or decays at the real part of the critical
eigenvalue (issue 9, item 5).  On either side of a Hopf point this brackets it by simulation.

The envelope is that of the critical mode's modal coordinate z(t) = w^H x(t) (w the left eigenvector of the
critical eigenvalue of the Jacobian A(V)), which the other modes do not enter for a linear system; its logarithm
is fitted by a straight line over the run.  Amplitudes of 1e-5 rad keep the nonlinear terms ~1e-10 of the linear
ones; Exudyn's RK44 at 1 ms integrates the rate to far below 1e-3 /s (:data:`RATE_TOL`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from mbs_shimmy.linearisation import MbsFamily
from mbs_shimmy.simulation import extended_states, integrate
from reduced_model.trajectory import SpeedSchedule

DURATION = 4.0          # s
AMPLITUDE = 1e-5        # largest state of the starting mode shape (rad, or m for the lateral travel)
RATE_TOL = 1e-3         # 1/s: how closely the fitted envelope rate follows Re of the critical eigenvalue


@dataclass(frozen=True)
class EnvelopeRate:
    """At one speed (m/s): the fitted envelope rate of a simulation and Re of the critical eigenvalue, 1/s."""

    speed: float
    rate: float
    real: float
    complete: bool           # False: the simulation stopped (the rate is NaN)

    @property
    def agrees(self) -> bool:
        return self.complete and abs(self.rate - self.real) <= RATE_TOL


def envelope_rate(family: MbsFamily, speed: float, duration: float = DURATION,
                  near: complex | None = None) -> EnvelopeRate:
    """The envelope rate of a small oscillation started along a mode at ``speed`` (m/s), at the family's own
    operating point, against Re of its eigenvalue: the critical one (largest real part), or with ``near`` the
    eigenvalue closest to it (e.g. i omega of a Hopf point, whose mode another unstable one must not hide).  Under
    the family's braking the run starts at the braked steady state x* plus the mode, and z = w^H (x - x*)."""
    A = family.linear_matrix(speed, family.nominal)
    lam, right = np.linalg.eig(A)
    k = int(np.argmax(lam.real)) if near is None else int(np.argmin(np.abs(lam - near)))
    lam_left, left = np.linalg.eig(A.T)
    w = left[:, int(np.argmin(np.abs(lam_left - lam[k])))]
    v = right[:, k] / np.max(np.abs(right[:, k]))
    m = family.model
    steady = family.equilibrium(speed, family.nominal)
    traj = integrate(m.params, m.effects, m.fidelity, family.pressures, SpeedSchedule.constant(speed),
                     steady + AMPLITUDE * v.real, duration, dims=m.dims, poses=False, braking=family.braking)
    if not traj.complete:
        return EnvelopeRate(speed, float("nan"), float(lam[k].real), False)
    z = np.abs((extended_states(traj) - steady) @ w)
    slope = np.polyfit(traj.t, np.log(z), 1)[0]
    return EnvelopeRate(speed, float(slope), float(lam[k].real), True)
