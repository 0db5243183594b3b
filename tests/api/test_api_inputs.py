"""The Python API keeps the command line's promises (issue 33): argument checks name the argument and its unit,
numpy scalars are numbers, integers too large for a float are refused by name, and ``simulate`` has the
command's guards on simulated time and on the number of periods, with ``allow_long`` to override them."""

from __future__ import annotations

import numpy as np
import pytest

from axles.parameters import ParameterError
from comparisons import api
from comparisons.api import Axle, TyrePressures, hopf_points, simulate, stability_margins

HUGE = 10 ** 400


@pytest.fixture(scope="module")
def family():
    return Axle.paper().reduced().family(TyrePressures.both(2.5))


@pytest.mark.parametrize("call, names", [
    (lambda f: TyrePressures.both(HUGE), ("tyre pressure", "bar")),
    (lambda f: TyrePressures.of_bar(1.5, HUGE), ("left tyre pressure", "bar")),
    (lambda f: TyrePressures(1.5e5, HUGE), ("left tyre pressure", "Pa")),
    (lambda f: hopf_points(f, vmax_kmh=HUGE), ("vmax_kmh", "km/h")),
    (lambda f: hopf_points(f, vmin_kmh=-HUGE), ("vmin_kmh", "km/h")),
    (lambda f: simulate(Axle.paper().reduced(), TyrePressures.both(2), speed_kmh=60, duration_s=HUGE),
     ("duration_s", "s")),
    (lambda f: simulate(Axle.paper().reduced(), TyrePressures.both(2), speed_kmh=HUGE, duration_s=1),
     ("speed_kmh", "km/h")),
    (lambda f: Axle.paper().with_values(I1=HUGE), ("I1", "kg m^2")),
    (lambda f: Axle.paper().with_values({"gamma": -HUGE}), ("gamma", "deg")),
    (lambda f: stability_margins(Axle.paper().reduced(), (1.0, HUGE)), ("pressure_range_bar", "bar")),
])
def test_huge_integers_are_refused_naming_the_argument_and_unit(family, call, names):
    with pytest.raises(ParameterError) as err:
        call(family)
    message = str(err.value)
    assert not isinstance(err.value, OverflowError)
    assert all(n in message for n in names), message
    assert "\n" not in message and len(message) < 300


def test_numpy_scalars_are_numbers(family):
    assert TyrePressures.both(np.float32(1.5)).right_bar == 1.5
    assert TyrePressures.of_bar(np.int64(2), np.float64(1.5)) == TyrePressures(2e5, 1.5e5)
    assert Axle.paper().with_values(t0=np.float32(0.25)).value("t0") == pytest.approx(0.25)
    assert Axle.paper().with_values(I1=np.int64(6)).value("I1") == 6.0
    points = hopf_points(family, vmin_kmh=np.int64(40), vmax_kmh=np.float32(80.0)).points
    assert [round(p.speed_kmh, 1) for p in points] == [46.1, 70.5]
    result = stability_margins(Axle.paper().reduced(), (np.float32(2.5), np.int64(3)), 40, 80,
                               pressure_points=np.int64(1), speed_points=np.int32(3))
    assert np.isfinite(result.minimum.damping_ratio)


@pytest.mark.parametrize("value", [True, "1.5", None, [1.5], complex(1, 0)])
def test_non_numbers_are_refused_by_name(value):
    with pytest.raises(ParameterError, match="right tyre pressure must be a number"):
        TyrePressures.of_bar(value, 1.5)


def test_simulate_refuses_a_kilohertz_axle_for_long_runs():
    """k1 = 1e8 N m/rad with I1 = 0.1 kg m^2 oscillates at kHz (the reduced model needs no consistent wheel):
    20 s would take hours; refused before any integration, as by the command."""
    axle = Axle.paper().with_values(k1=1e8, I1=0.1)
    with pytest.raises(ParameterError, match=r"fastest oscillation, 7\d{3} Hz.*shorten duration_s"):
        simulate(axle.reduced(), TyrePressures.both(2), speed_kmh=60, duration_s=20)


def test_simulate_refuses_long_mbs_runs_before_building_the_model():
    model = Axle.paper().mbs(fidelity="full")
    with pytest.raises(ParameterError, match="duration_s of the multibody model must be at most 100 s"):
        simulate(model, TyrePressures.both(2), speed_kmh=60, duration_s=500)
    assert "model" not in vars(model)            # refused before Exudyn built anything


def test_allow_long_overrides_the_guard(monkeypatch):
    import comparisons.simulations as simulations
    monkeypatch.setattr(simulations, "MAX_CYCLES", 1.0)   # any run is now "too long"
    model = Axle.paper().reduced()
    with pytest.raises(ParameterError, match="periods"):
        simulate(model, TyrePressures.both(2), speed_kmh=60, duration_s=0.5)
    run = simulate(model, TyrePressures.both(2), speed_kmh=60, duration_s=0.5, allow_long=True)
    assert run.status.value == "complete"
