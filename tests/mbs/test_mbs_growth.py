"""The linearisation of the full multibody axle (all states: the new coordinates and the slip angles) against its
own simulations (issue 9, item 5): near each Hopf point of the full geometry, a small oscillation started along
the critical mode grows or decays at the real part of the critical eigenvalue.

The envelope is that of the critical mode's modal coordinate z(t) = w^H x(t) (w the left eigenvector of the
critical eigenvalue of the Jacobian A(V)), which the other modes do not enter for a linear system; its logarithm
is fitted by a straight line over the run.  Amplitudes of 1e-5 rad keep the nonlinear terms ~1e-10 of the linear
ones; Exudyn's RK44 at 1 ms integrates the rate to far below 1e-3 /s.
"""

import numpy as np
import pytest

from comparisons.axles.units import BAR, KMH
from mbs_shimmy import Fidelity
from mbs_shimmy.linearisation import MbsFamily, MbsModel
from mbs_shimmy.simulation import extended_states, simulate
from reduced_model.bifurcation.equilibria.hopf import hopf_points
from reduced_model.trajectory import SpeedSchedule

OFFSET_KMH = 4.0
DURATION = 4.0


def envelope_rate(family: MbsFamily, pressure: float, speed: float) -> tuple[float, float]:
    """(fitted envelope rate of a simulation, Re of the critical eigenvalue) at this speed (m/s), 1/s."""
    A = family.linear_matrix(speed, pressure)
    lam, right = np.linalg.eig(A)
    k = int(np.argmax(lam.real))
    lam_left, left = np.linalg.eig(A.T)
    w = left[:, int(np.argmin(np.abs(lam_left - lam[k])))]
    v = right[:, k] / np.max(np.abs(right[:, k]))
    x0 = 1e-5 * v.real
    traj = simulate(fidelity=family.model.fidelity, pressure=pressure, schedule=SpeedSchedule.constant(speed),
                    x0=x0, duration=DURATION, poses=False)
    assert traj.complete
    x = extended_states(traj)
    z = np.abs(x @ w)
    slope = np.polyfit(traj.t, np.log(z), 1)[0]
    return float(slope), float(lam[k].real)


def full_hopf_speeds(pressure):
    family = MbsFamily(MbsModel(fidelity=Fidelity.full()), pressure=pressure)
    return family, [h.p for h in hopf_points(family, pressure, 0.0, 400 * KMH, lyapunov=False)]


@pytest.mark.parametrize("side", [-1.0, 1.0])
@pytest.mark.parametrize("index", [0, 1])
def test_growth_rate_equals_critical_eigenvalue_at_1_5_bar(index, side):
    pressure = 1.5 * BAR
    family, speeds = full_hopf_speeds(pressure)
    assert len(speeds) == 2            # 39.23 and 91.79 km/h (tests/mbs/test_mbs_assumptions.py)
    speed = speeds[index] + side * OFFSET_KMH * KMH
    rate, real = envelope_rate(family, pressure, speed)
    assert abs(real) > 0.02            # away from the Hopf point: a rate that means something
    assert rate == pytest.approx(real, abs=1e-3)


def test_decay_rate_at_2_5_bar_without_hopf_points():
    """At 2.5 bar the full geometry has no Hopf point (straight running is stable at every speed): there the
    least-damped mode near its weakest speed decays at its eigenvalue's real part."""
    pressure = 2.5 * BAR
    family, speeds = full_hopf_speeds(pressure)
    assert speeds == []
    rate, real = envelope_rate(family, pressure, 60 * KMH)
    assert real < -0.02
    assert rate == pytest.approx(real, abs=1e-3)
