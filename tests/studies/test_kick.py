"""The kick that sets shimmy off, in the paper's bistable window (1.5 bar, t0 = 0.25 m: yaw and tramp cycles
coexist from about 159 to 185 km/h)."""

import numpy as np
import pytest

from axles.units import BAR, KMH
from mbs_shimmy import Fidelity
from comparisons.studies.kick import KickStatus, coexisting_states, kick_threshold, kicks, settle_function, settled_on
from mbs_shimmy.linearisation import MbsFamily
from mbs_shimmy.model import MbsModel
from bifurcation.cycles.branches import cycle_diagram
from reduced_model.family import SpeedFamily
from reduced_model.model import ShimmyModel
from axles.parameters import YANG2024
from axles.pressures import TyrePressures

PRESSURE = 1.5 * BAR
PARAMS = YANG2024.replace(t0=0.25)


@pytest.fixture(scope="module")
def reduced():
    family = SpeedFamily(ShimmyModel(params=PARAMS), pressures=TyrePressures.uniform(PRESSURE))
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
    mbs = MbsFamily(MbsModel(PARAMS, fidelity=Fidelity.reduced()), pressures=TyrePressures.uniform(PRESSURE))
    states, unstable = coexisting_states(family, diagram, kick.speed)
    other = kick_threshold(settle_function(mbs, kick.speed), kick.speed, states, unstable)
    assert other.status is KickStatus.FOUND
    assert other.lower == kick.lower
    # The two brackets overlap: the same threshold to the bisection's tolerance.
    assert other.stays < kick.leaves and kick.stays < other.leaves


@pytest.mark.slow
def test_full_geometry_kick_in_its_own_window_at_t0_0_25():
    """The full geometry's subcritical onset at t0 = 0.25 m, 1.5 bar: straight running and a large stable cycle
    coexist between its Hopf point (about 194.6 km/h) and the cycle fold (about 204 km/h); the kick between them is
    bracketed by two full-MBS runs.  The window is continued narrowly at 1e-5 (about 2 min on 2 cores): below
    194 km/h the stable cycles need hundreds of intervals (docs/results.md)."""
    from comparisons.studies.kick import bistable_windows
    from bifurcation.cycles.problem import CycleSettings
    from bifurcation.special_points import PointKind
    family = MbsFamily(MbsModel(PARAMS, fidelity=Fidelity.full()), pressures=TyrePressures.uniform(PRESSURE))
    diagram = cycle_diagram(family, PRESSURE, 194.5 * KMH, 206.0 * KMH, settings=CycleSettings(tolerance=1e-5))
    assert diagram.complete
    (hopf,) = diagram.hopf
    assert hopf.first_lyapunov > 0.0                       # subcritical: the unstable cycles lie where it is stable
    (fold,) = diagram.points_of(PointKind.CYCLE_FOLD)
    ((low, high),) = bistable_windows(diagram, family)
    assert low == hopf.p and hopf.p < high < fold.p
    assert not diagram.points_of(PointKind.TORUS)           # (the double multiplier near +1 is no torus)
    (kick,) = kicks(family, diagram)
    assert kick.status is KickStatus.FOUND and low < kick.speed < high
    assert kick.lower.label == "straight running"
    states = (kick.lower, kick.upper)
    assert settled_on(kick.stays_run, states) == 0 and settled_on(kick.leaves_run, states) == 1
    # The separating unstable cycle is smaller than the kick needs: its other states carry the rest.
    assert kick.unstable_theta1 < kick.kick < kick.upper.theta1


def test_a_run_starts_from_the_kick_in_its_own_order_and_under_braking_from_the_steady_state():
    """The full verify's orbit checks start MBS runs from an orbit's every state (14 on the full geometry): with
    the braking's steady state of the reduced model's length that raised 'negative dimensions' (fixed)."""
    from comparisons.studies.kick import start_state
    orbit_state = np.arange(14.0)
    assert np.array_equal(start_state(np.zeros(8), None, orbit_state), orbit_state)
    steady = np.linspace(0.1, 0.8, 8)
    got = start_state(steady, steady, orbit_state)
    assert np.array_equal(got[:8], steady + orbit_state[:8]) and np.array_equal(got[8:], orbit_state[8:])
    assert np.array_equal(start_state(steady, steady, np.ones(8)), steady + 1.0)
