"""The linearisation of the full multibody axle (all states: the new coordinates and the slip angles) against its
own simulations (issue 9, item 5): near each Hopf point of the full geometry, a small oscillation started along
the critical mode grows or decays at the real part of the critical eigenvalue (:mod:`comparisons.studies.growth`, which the
verify section `full_geometry` uses to bracket the Hopf points).
"""

import pytest

from axles.units import BAR, KMH
from mbs_shimmy import Fidelity
from comparisons.studies.growth import RATE_TOL, envelope_rate
from mbs_shimmy.linearisation import MbsFamily
from mbs_shimmy.model import MbsModel
from bifurcation.equilibria.hopf import find_hopf_points
from axles.pressures import TyrePressures

OFFSET_KMH = 4.0


def full_hopf_speeds(pressure):
    family = MbsFamily(MbsModel(fidelity=Fidelity.full()), pressures=TyrePressures.uniform(pressure))
    return family, [h.p for h in find_hopf_points(family, pressure, 0.0, 400 * KMH, lyapunov=False)]


@pytest.mark.parametrize("side", [-1.0, 1.0])
@pytest.mark.parametrize("index", [0, 1])
def test_growth_rate_equals_critical_eigenvalue_at_1_5_bar(index, side):
    pressure = 1.5 * BAR
    family, speeds = full_hopf_speeds(pressure)
    assert len(speeds) == 2            # 39.23 and 91.79 km/h (tests/studies/test_mbs_assumptions.py)
    speed = speeds[index] + side * OFFSET_KMH * KMH
    found = envelope_rate(family, speed)
    assert abs(found.real) > 0.02      # away from the Hopf point: a rate that means something
    assert found.complete and found.rate == pytest.approx(found.real, abs=RATE_TOL)


def test_decay_rate_at_2_5_bar_without_hopf_points():
    """At 2.5 bar the full geometry has no Hopf point (straight running is stable at every speed): there the
    least-damped mode near its weakest speed decays at its eigenvalue's real part."""
    pressure = 2.5 * BAR
    family, speeds = full_hopf_speeds(pressure)
    assert speeds == []
    found = envelope_rate(family, 60 * KMH)
    assert found.real < -0.02
    assert found.complete and found.rate == pytest.approx(found.real, abs=RATE_TOL)
