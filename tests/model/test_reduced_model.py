"""The reduced model, its tyre and its exact Jacobian."""

import dataclasses

import numpy as np
import pytest

from axles.units import BAR
from reduced_model import tyre
from reduced_model.model import Effects, ShimmyModel
from axles.parameters import YANG2024, ParameterError, ShimmyParameters
from axles.pressures import TyrePressures


def test_every_parameter_has_unit_source_and_description():
    for f in dataclasses.fields(ShimmyParameters):
        assert f.metadata["unit"] and f.metadata["source"] and f.metadata["description"], f.name
    names = ShimmyParameters.names()
    for required in "I1 I2 I3 k1 k2 k3 k4 k5_0 c1 c2 c3 c4 R L f l gamma a0 sigma0 t0 c_y0 Fz0 pi0".split():
        assert required in names
    for coeff in ("p_dy1", "p_dy2", "p_py3", "p_py4", "p_py1", "p_py2", "q_bz1", "q_ez4", "p_cy1", "p_cy1_rl"):
        assert coeff in names


def test_table1_values_in_si():
    assert YANG2024.k1 == 35.5e3 and YANG2024.k5_0 == 400e3 and YANG2024.c_y0 == 96.92e3
    assert YANG2024.pi0 == 2.5e5 and YANG2024.p_cy1 == 1.29 and YANG2024.p_cy1_rl == 0.5


def test_overrides_and_bad_values():
    assert YANG2024.replace(t0=0.25).t0 == 0.25
    with pytest.raises(ParameterError, match="unknown parameter"):
        YANG2024.replace(t1=0.2)
    for bad in ({"sigma0": -0.1}, {"t0": 0.0}, {"a0": -1.0}, {"k4": -5.0}, {"c3": -1.0}):
        with pytest.raises(ParameterError):
            YANG2024.replace(**bad)


def test_nominal_tyre_matches_section3_constants():
    """At p_i0 the extended relations give sigma = K/c_y0 = 0.650 m and t = D_t = 0.07 m (docs/paper-notes.md)."""
    assert tyre.relaxation_length(YANG2024, 2.5 * BAR) == pytest.approx(0.650, abs=5e-4)
    assert tyre.pneumatic_trail(YANG2024, 0.0, 2.5 * BAR) == pytest.approx(0.07, rel=1e-12)
    assert tyre.half_contact_length(YANG2024, 2.5 * BAR) == pytest.approx(YANG2024.a0, rel=1e-15)
    assert tyre.vertical_stiffness(YANG2024, 2.5 * BAR) == pytest.approx(YANG2024.k5_0, rel=1e-15)


def test_magic_formula_slope_is_cornering_stiffness():
    for p in (1.0, 2.5, 3.2):
        mf = tyre.magic_formula(YANG2024, p * BAR)
        slope = (mf.force(1e-7) - mf.force(-1e-7)) / 2e-7
        assert slope == pytest.approx(-tyre.cornering_stiffness(YANG2024, p * BAR), rel=1e-7)
        assert mf.force(0.0) == 0.0


def test_pressure_trends_of_figures_12_and_16():
    """Lower pressure: longer contact, longer trail, longer relaxation length, softer tyre."""
    lo, hi = 1.5 * BAR, 3.0 * BAR
    assert tyre.half_contact_length(YANG2024, lo) > tyre.half_contact_length(YANG2024, hi)
    assert tyre.pneumatic_trail(YANG2024, 0.0, lo) > tyre.pneumatic_trail(YANG2024, 0.0, hi)
    assert tyre.relaxation_length(YANG2024, lo) > tyre.relaxation_length(YANG2024, hi)
    assert tyre.vertical_stiffness(YANG2024, lo) < tyre.vertical_stiffness(YANG2024, hi)
    # The trail falls with slip angle (figure 12).
    assert tyre.pneumatic_trail(YANG2024, 0.1, 2.5 * BAR) < tyre.pneumatic_trail(YANG2024, 0.0, 2.5 * BAR)


@pytest.mark.parametrize("effects", ["", "hcl", "pt", "rl", "vs", "all"])
def test_jacobian_matches_finite_differences(effects):
    model = ShimmyModel(effects=Effects.parse(effects))
    x = np.array([0.02, -0.3, -0.01, 0.4, 0.003, -0.05, 0.015, -0.02])
    J = model.jacobian(x, 25.0, TyrePressures(1.7 * BAR, 2.2 * BAR))
    h = 1e-6
    fd = np.column_stack([(model.rhs(x + h * e, 25.0, TyrePressures(1.7 * BAR, 2.2 * BAR))
                           - model.rhs(x - h * e, 25.0, TyrePressures(1.7 * BAR, 2.2 * BAR))) / (2 * h) for e in np.eye(8)])
    assert np.allclose(J, fd, rtol=1e-6, atol=1e-6 * np.max(np.abs(J)))


def test_straight_running_is_equilibrium_and_jacobian_affine_in_speed():
    model = ShimmyModel(effects=Effects.parse("all"))
    assert np.all(model.rhs(np.zeros(8), 30.0, TyrePressures.uniform(1.8 * BAR)) == 0.0)
    A = [model.linear_matrix(V, TyrePressures.uniform(1.8 * BAR)) for V in (0.0, 10.0, 50.0)]
    assert np.allclose(A[2], A[0] + 5.0 * (A[1] - A[0]), rtol=1e-12, atol=1e-9)


def test_per_wheel_pressure_breaks_symmetry_only_when_different():
    model = ShimmyModel(effects=Effects.parse("all"))
    same = model.linear_matrix(20.0, TyrePressures(2.0 * BAR, 2.0 * BAR))
    assert np.array_equal(same, model.linear_matrix(20.0, TyrePressures.uniform(2.0 * BAR)))
    skew = model.linear_matrix(20.0, TyrePressures(1.2 * BAR, 2.0 * BAR))
    assert not np.allclose(skew[6], same[6])  # right-wheel relaxation row follows the right pressure
    assert np.allclose(skew[7], same[7])


def test_effects_parse():
    assert Effects.parse("all").names == ("hcl", "pt", "rl", "vs")
    assert Effects.parse("pt, rl").names == ("pt", "rl")
    assert Effects.parse("").names == ()
    with pytest.raises(ParameterError, match="unknown effect"):
        Effects.parse("hcl,xx")


def test_meaningless_pressure_is_refused():
    model = ShimmyModel(effects=Effects.parse("rl,pt"))
    with pytest.raises(ParameterError):
        model.rhs(np.zeros(8), 10.0, TyrePressures.uniform(0.0))
    with pytest.raises(ParameterError, match="cornering stiffness"):
        model.rhs(np.zeros(8), 10.0, TyrePressures.uniform(9.0 * BAR))  # 1 + p_py1 dp_i < 0 beyond 6.5 bar
    with pytest.raises(ParameterError, match="pneumatic trail"):
        model.with_params(p_pz1=3.0).rhs(np.zeros(8), 10.0, TyrePressures.uniform(3.5 * BAR))
