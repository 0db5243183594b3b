"""``shimmy modes``: eigenvalues of straight running with frequency, damping ratio and character."""

import json
import math

import numpy as np
import pytest

from axles.units import from_kmh
from comparisons.cli.main import main
from bifurcation.equilibria.hopf import find_hopf_points
from reduced_model.family import SpeedFamily
from reduced_model.mode_shapes import mode_shapes
from reduced_model.model import STATE_NAMES, ShimmyModel
from axles.pressures import TyrePressures

I = {n: k for k, n in enumerate(STATE_NAMES)}


def test_linear_oscillator_by_hand():
    """theta1'' + 2 zeta w theta1' + w^2 theta1 = 0, the other states decaying on their own."""
    zeta, w = 0.1, 2 * math.pi * 5.0
    A = -np.diag(np.arange(1.0, 9.0)) * 50.0
    A[I["theta1"], :] = 0.0
    A[I["theta1_dot"], :] = 0.0
    A[I["theta1"], I["theta1_dot"]] = 1.0
    A[I["theta1_dot"], I["theta1"]] = -w ** 2
    A[I["theta1_dot"], I["theta1_dot"]] = -2 * zeta * w
    modes = mode_shapes(A, I1=6.0, I3=160.0)
    osc = [m for m in modes if m.frequency_hz > 0]
    assert len(osc) == 1 and len(modes) == 7          # one pair counted once, six real eigenvalues
    m = osc[0]
    assert m.frequency_hz == pytest.approx(5.0 * math.sqrt(1 - zeta ** 2), rel=1e-12)
    assert m.damping_ratio == pytest.approx(zeta, rel=1e-12)
    assert m.character == "yaw" and m.yaw_share == 1.0 and m.left_share == 0.0 and m.stable


def test_modes_at_the_first_hopf_point():
    """At HB1 the Hopf solver's frequency (an independent computation) is the undamped yaw mode's."""
    family = SpeedFamily(ShimmyModel(), pressures=TyrePressures.uniform(1.5e5))
    hb1 = find_hopf_points(family, 1.5e5, 0.0, from_kmh(400), lyapunov=False)[0]
    modes = mode_shapes(family.linear_matrix(hb1.p, 1.5e5), 6.0, 160.0)
    critical = modes[0]
    assert abs(critical.eigenvalue.real) < 1e-6
    assert critical.frequency_hz == pytest.approx(hb1.frequency_hz, rel=1e-8)
    assert critical.character == "yaw" and abs(math.degrees(critical.wheel_phase)) < 20    # wheels steer together
    tramp = [m for m in modes if m.character == "tramp"]
    assert len(tramp) == 1 and tramp[0].tramp_share > 0.9 and 8.0 < tramp[0].frequency_hz < 12.0
    assert sum(m.character == "slip" for m in modes) == 2


def test_cli_both_models_agree_with_reduced_fidelity(capsys):
    assert main(["modes", "--pressure", "1.5", "--speed", "60", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["speed_kmh"] == 60 and out["pressure_bar"] == 1.5 and out["fidelity"] == "reduced"
    red, mbs = out["models"]["reduced"], out["models"]["mbs"]
    assert len(red) == len(mbs) == 5
    for a, b in zip(red, mbs):
        assert b["real_per_s"] == pytest.approx(a["real_per_s"], abs=1e-6 * abs(a["imag_rad_per_s"]) + 1e-6)
        assert b["frequency_hz"] == pytest.approx(a["frequency_hz"], rel=1e-6, abs=1e-9)
        assert a["character"] == b["character"]
    assert [m["character"] for m in red] == ["yaw", "tramp", "yaw", "slip", "slip"]
    assert red[0]["stable"] is False
    assert main(["modes", "--pressure", "1.5", "--speed", "60"]) == 0
    text = capsys.readouterr().out
    assert "UNSTABLE" in text and "MBS, fidelity reduced" in text


def test_cli_bad_speed(capsys):
    assert main(["modes", "--pressure", "1.5", "--speed", "2000"]) == 2
    err = capsys.readouterr().err
    assert "at most 1000 km/h" in err and len(err.splitlines()) == 1


def test_an_oscillator_in_the_steering_gear_is_a_gear_mode():
    """Twelve states, the full geometry's order: a lightly damped oscillation of phi_gear that drags the wheels
    along by a tenth of its angle is named by its energy, which sits in the gear (inertia 30 kg m^2)."""
    from mbs_shimmy.layout import EXTRA_COORDINATES

    names = STATE_NAMES + tuple(x for c in EXTRA_COORDINATES for x in (c, c + "_dot"))
    at = {n: k for k, n in enumerate(names)}
    w = 2 * math.pi * 9.0
    A = -np.eye(len(names)) * 80.0
    g, gd = at["phi_gear"], at["phi_gear_dot"]
    A[g, :], A[gd, :] = 0.0, 0.0
    A[g, gd], A[gd, g], A[gd, gd] = 1.0, -w ** 2, -2 * 0.05 * w
    for wheel in ("theta1", "theta2"):          # theta_i follows 0.1 phi_gear (a steady forced response)
        A[at[wheel], :], A[at[wheel + "_dot"], :] = 0.0, 0.0
        A[at[wheel], at[wheel + "_dot"]] = 1.0
        A[at[wheel + "_dot"], at[wheel]] = -(3 * w) ** 2
        A[at[wheel + "_dot"], g] = 0.1 * ((3 * w) ** 2 - w ** 2)
    inertias = {"theta1": 6.0, "theta2": 6.0, "psi": 160.0, "y_axle": 400.0, "phi_gear": 30.0}
    modes = mode_shapes(A, inertias=inertias, names=names)
    (gear,) = [m for m in modes if abs(m.frequency_hz - 9.0) < 0.1]
    assert set(gear.shares) == {"yaw", "tramp", "lateral", "gear"}
    assert gear.shares["gear"] > 0.5 and gear.yaw_share > 0.0 and gear.character == "gear"
    assert sum(gear.shares.values()) == pytest.approx(1.0, rel=1e-12)


def test_cli_full_geometry_names_modes_by_every_energy_share(capsys):
    """With the full geometry the MBS has the axle's lateral travel and the steering gear: each oscillating mode
    is named by the largest of all its energy shares, so the gear mode near 9 Hz is not 'yaw'."""
    assert main(["modes", "--pressure", "2.5", "--speed", "60", "--fidelity", "full", "--json"]) == 0
    mbs = json.loads(capsys.readouterr().out)["models"]["mbs"]
    for m in mbs:
        shares = m["energy_shares"]
        assert set(shares) == {"yaw", "tramp", "lateral", "bounce", "gear"}
        assert sum(shares.values()) == pytest.approx(1.0, rel=1e-9)
        if m["frequency_hz"] > 0:
            assert m["character"] == max(shares, key=shares.get)
    gear = [m for m in mbs if m["character"] == "gear"]
    assert len(gear) == 1 and 5.0 < gear[0]["frequency_hz"] < 15.0
    assert gear[0]["yaw_share"] < gear[0]["energy_shares"]["gear"]
