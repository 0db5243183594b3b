"""Accuracy of the benchmark's integrator settings (``shimmy bench mbs_simulation_full mbs_simulation_reduced``,
:data:`mbs_shimmy.simulation.BENCH_SETTINGS`).

DOPRI5 samples fall on its adaptive steps, so the reference (RK67 at 1/960 s, itself within 1e-8 of 1/1920 s) is
interpolated to them by a cubic spline (interpolation error below 1e-6 of an amplitude at 114 rad/s, the model's
fastest mode).
"""

import numpy as np
import pytest
from scipy.interpolate import CubicSpline

from axles.units import from_kmh
from mbs_shimmy import Fidelity
from mbs_shimmy.simulation import BENCH_SETTINGS, extended_states, integrate
from reduced_model.model import Effects
from reduced_model.trajectory import SimulationStatus, SpeedSchedule
from axles.pressures import TyrePressures


@pytest.mark.parametrize("fidelity", ["full", "reduced"])
def test_benchmark_settings_keep_1e4_accuracy(fidelity):
    """The benchmark's 10 s run at 1.5 bar, 100 km/h: every state (the new coordinates included) within 1e-4 of
    its amplitude in the reference run, and the error shrinks when the tolerances (the step) do, so it is the
    setting, not luck, that holds it.  The adaptive setting of the full geometry needs fewer force evaluations
    than RK67 at 1/240 s (16 800)."""
    x0 = np.zeros(8)
    x0[0] = 0.01
    kwargs = dict(effects=Effects(), fidelity=Fidelity.parse(fidelity), pressures=TyrePressures.uniform(1.5e5),
                  schedule=SpeedSchedule.constant(from_kmh(100)), x0=x0, duration=10.0, poses=False)
    ref = integrate(method="RK67", step=1 / 960, output_interval=1 / 960, **kwargs)
    states = extended_states(ref)
    spline, amplitude = CubicSpline(ref.t, states), np.max(np.abs(states), axis=0)

    def error(setting):
        run = integrate(**setting, **kwargs)
        assert run.status is SimulationStatus.COMPLETE and abs(run.t[-1] - 10.0) < 1e-9
        return float(np.max(np.max(np.abs(extended_states(run) - spline(run.t)), axis=0) / amplitude)), run

    setting = BENCH_SETTINGS[fidelity]
    finer_setting = (dict(setting, rtol=setting["rtol"] / 10, atol=setting["atol"] / 10) if "rtol" in setting
                     else dict(setting, step=setting["step"] / 2))
    coarse, run = error(setting)
    finer, _ = error(finer_setting)
    assert coarse < 1e-4
    assert finer < coarse / 2
    if "rtol" in setting:
        assert run.extra["force_evaluations"] < 0.7 * 16800


@pytest.mark.parametrize("tol", [{"rtol": 0.0}, {"atol": -1e-7}, {"rtol": float("nan")}])
def test_bad_tolerances(tol):
    from axles.parameters import ParameterError
    with pytest.raises(ParameterError, match="must be a positive number"):
        integrate(method="DOPRI5", **tol)


def test_scalar_tyre_formulas_equal_the_numpy_ones():
    """The MBS evaluates the Magic Formula and the trail with :mod:`math` on floats (``mf_force``, ``mf_trail``
    with math's functions, as its tyre elements and compiled stage call them): the same formula as the numpy form,
    equal to rounding over the slip range."""
    import math

    from reduced_model import tyre
    from axles.parameters import YANG2024
    mf, tr = tyre.magic_formula(YANG2024, 1.5e5), tyre.trail_formula(YANG2024, 1.5e5)
    alphas = np.linspace(-0.5, 0.5, 201)
    force = [tyre.mf_force(mf.B, mf.C, mf.D, mf.E, float(a), math.sin, math.atan) for a in alphas]
    trail = [tyre.mf_trail(tr.Bt, tr.Ct, tr.Dt, tr.Et0, tr.q_ez4, float(a), math.cos, math.atan) for a in alphas]
    assert np.allclose(force, mf.force(alphas), rtol=1e-14, atol=1e-9)
    assert np.allclose(trail, tr.trail(alphas), rtol=1e-14, atol=1e-15)
