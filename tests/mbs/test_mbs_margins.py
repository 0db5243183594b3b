"""The MBS with every assumption of the reduced model on has the reduced model's margin map (least damping ratio
of straight running over speed and pressure), on the paper's axle and on one with other dimensions and Table 1."""

import numpy as np
import pytest

from mbs_shimmy.model import MbsModel
from axles.units import BAR, from_kmh
from axles.dimensions import DEFAULT_DIMENSIONS
from mbs_shimmy.fidelity import Fidelity
from mbs_shimmy.linearisation import MbsFamily
from bifurcation.equilibria.margins import margin_map
from reduced_model.family import SpeedFamily
from reduced_model.model import Effects, ShimmyModel
from axles.parameters import YANG2024

TOL = 1e-9


def _maps(params, effects, dims, speeds_kmh, pressures_bar):
    speeds, pressures = from_kmh(np.asarray(speeds_kmh)), np.asarray(pressures_bar) * BAR
    reduced = margin_map(SpeedFamily(ShimmyModel(params=params, effects=effects), "pressure"), speeds, pressures)
    mbs = margin_map(MbsFamily(MbsModel(params, effects, Fidelity.reduced(), dims)), speeds, pressures)
    return reduced, mbs


def test_the_mbs_with_every_assumption_has_the_reduced_margin_map():
    reduced, mbs = _maps(YANG2024, Effects(), DEFAULT_DIMENSIONS, np.linspace(1, 400, 40), (0.8, 1.5, 2.5, 3.3))
    assert np.max(np.abs(reduced.damping_ratio - mbs.damping_ratio)) <= TOL
    a, b = reduced.minimum(), mbs.minimum()
    assert (a.p, a.q) == (b.p, b.q)
    assert abs(a.omega - b.omega) <= TOL * a.omega


@pytest.mark.slow
def test_the_mbs_margin_map_on_another_axle_and_every_effect():
    import dataclasses
    params = YANG2024.replace(c4=120.0, t0=0.27)
    dims = dataclasses.replace(DEFAULT_DIMENSIONS, drag_link_inclination=np.radians(11.1))
    reduced, mbs = _maps(params, Effects.parse("all"), dims, np.linspace(0.5, 400, 200), np.linspace(0.5, 3.5, 16))
    assert np.max(np.abs(reduced.damping_ratio - mbs.damping_ratio)) <= TOL
