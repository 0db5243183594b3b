"""The kick that sets shimmy off, in the paper's bistable window (1.5 bar, t0 = 0.25 m: yaw and tramp cycles
coexist from about 159 to 185 km/h)."""

import pytest

from comparisons.axles.units import BAR, KMH
from mbs_shimmy import Fidelity
from mbs_shimmy.kick import KickStatus, coexisting_states, kick_threshold, kicks, settle_function, settled_on
from mbs_shimmy.linearisation import MbsFamily, MbsModel
from reduced_model.bifurcation.cycles.branches import cycle_diagram
from reduced_model.family import SpeedFamily
from reduced_model.model import ShimmyModel
from reduced_model.parameters import YANG2024

PRESSURE = 1.5 * BAR
PARAMS = YANG2024.replace(t0=0.25)


@pytest.fixture(scope="module")
def reduced():
    family = SpeedFamily(ShimmyModel(params=PARAMS), pressure=PRESSURE)
    return family, cycle_diagram(family, PRESSURE, 100.0 * KMH, 300.0 * KMH)


def test_kick_in_the_bistable_window_is_bracketed_by_two_runs(reduced):
    family, diagram = reduced
    (kick,) = kicks(family, diagram)
    assert 159.0 * KMH < kick.speed < 185.0 * KMH
    assert kick.status is KickStatus.FOUND
    assert kick.leaves / kick.stays <= 1.02
    # The two runs that bracket it: just below it settles on the lower state, just above on the other.
    states = (kick.lower, kick.upper)
    assert kick.stays_run.settled and settled_on(kick.stays_run, states) == 0
    assert kick.leaves_run.settled and settled_on(kick.leaves_run, states) == 1
    assert kick.stays_run.theta1 == pytest.approx(kick.lower.theta1, rel=1e-2)
    assert kick.leaves_run.theta1 == pytest.approx(kick.upper.theta1, rel=1e-2)


@pytest.mark.slow
def test_mbs_with_every_assumption_on_has_the_same_kick(reduced):
    family, diagram = reduced
    (kick,) = kicks(family, diagram)
    mbs = MbsFamily(MbsModel(PARAMS, fidelity=Fidelity.reduced()), pressure=PRESSURE)
    states, unstable = coexisting_states(family, diagram, kick.speed)
    other = kick_threshold(settle_function(mbs, kick.speed), kick.speed, states, unstable)
    assert other.status is KickStatus.FOUND
    assert other.lower == kick.lower
    # The two brackets overlap: the same threshold to the bisection's tolerance.
    assert other.stays < kick.leaves and kick.stays < other.leaves
