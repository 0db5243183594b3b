"""The multibody model with every assumption of the reduced model on (``--fidelity reduced``) against the reduced
model (issue 4, item 7): eigenvalues, Hopf speeds, a transient and a limit cycle.

The MBS side is computed through Exudyn (kinematic tree, tyre elements, solver-evaluated right-hand sides); the
reduced side is :class:`reduced_model.model.ShimmyModel`.  Nothing here feeds one into the other.
"""

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from axles.units import BAR, KMH, kmh
from axles.dimensions import AxleDimensions
from mbs_shimmy import Fidelity
from comparisons.studies.limit_cycle import mbs_steady_amplitude, reduced_steady_amplitude
from mbs_shimmy.linearisation import MbsFamily
from mbs_shimmy.model import MbsModel
from mbs_shimmy.simulation import integrate
from bifurcation.equilibria.hopf import find_hopf_points
from reduced_model.family import SpeedFamily
from reduced_model.model import Effects, ShimmyModel
from axles.parameters import YANG2024
from reduced_model.trajectory import SpeedSchedule
from axles.pressures import TyrePressures


def _eigs(A):
    lam = np.linalg.eigvals(A)
    return lam[np.lexsort((lam.imag, lam.real))]


@pytest.mark.parametrize("effects", ["", "all"])
@pytest.mark.parametrize("pressure", [1.5, 2.5])
def test_jacobian_eigenvalues_equal_reduced(effects, pressure):
    mbs = MbsFamily(MbsModel(effects=Effects.parse(effects), fidelity=Fidelity.reduced()))
    red = SpeedFamily(ShimmyModel(effects=Effects.parse(effects)))
    for kmh in (20, 60, 150, 300):
        # the direct difference Jacobian at this speed, not the affine form
        a = _eigs(mbs.direct_linear_matrix(kmh * KMH, pressure * BAR))
        b = _eigs(red.linear_matrix(kmh * KMH, pressure * BAR))
        assert np.max(np.abs(a - b) / np.abs(b)) < 1e-9, (kmh, a, b)


@pytest.mark.parametrize("overrides,pressure", [({}, 1.5), ({}, 2.5), ({"t0": 0.25}, 1.5), ({"t0": 0.25}, 2.5)])
def test_hopf_speeds_equal_reduced(overrides, pressure):
    params = YANG2024.replace(**overrides)
    mbs = find_hopf_points(MbsFamily(MbsModel(params=params, fidelity=Fidelity.reduced())), pressure * BAR, 0.0,
                      400 * KMH, lyapunov=False)
    red = find_hopf_points(SpeedFamily(ShimmyModel(params)), pressure * BAR, 0.0, 400 * KMH, lyapunov=False)
    assert len(mbs) == len(red) >= 2
    for h, r in zip(mbs, red):
        assert abs(kmh(h.p) - kmh(r.p)) < 0.01
        assert abs(h.omega - r.omega) < 1e-6 * r.omega


def test_chosen_dimensions_do_not_enter_the_reduced_equations():
    """Masses, wheel inertia and arm lengths the paper does not give: other values, same linearisation."""
    other = AxleDimensions(wheel_mass=25.0, wheel_diametral_inertia=2.5, knuckle_mass=35.0,
                           knuckle_transverse_inertia=0.8, axle_mass=60.0, tie_rod_arm=0.13, drag_link_arm=0.31,
                           drag_link_length=1.4)
    a = MbsFamily(MbsModel(fidelity=Fidelity.reduced())).direct_linear_matrix(80 * KMH, 1.5 * BAR)
    b = MbsFamily(MbsModel(fidelity=Fidelity.reduced(), dims=other)).direct_linear_matrix(80 * KMH, 1.5 * BAR)
    assert np.max(np.abs(a - b)) < 1e-9 * np.max(np.abs(a))
    # ...whereas with the full geometry they do matter (the inertial coupling, the linkage geometry)
    c = MbsFamily(MbsModel(fidelity=Fidelity.full())).direct_linear_matrix(80 * KMH, 1.5 * BAR)
    d = MbsFamily(MbsModel(fidelity=Fidelity.full(), dims=other)).direct_linear_matrix(80 * KMH, 1.5 * BAR)
    assert np.max(np.abs(c - d)) > 1e-4 * np.max(np.abs(c))


@pytest.mark.parametrize("effects", ["", "all"])
def test_right_hand_side_equals_reduced_where_a_wheel_would_lift(effects):
    """A large tramp (0.3 rad) drives one wheel's first-order load negative; the reduced model knows no lifting
    (constant load), so its slip force stays: the MBS with every assumption on must give the same right-hand side
    there, with both slip angles non-zero so that a zeroed grip would show."""
    from reduced_model.model import STATE_NAMES
    model = ShimmyModel(effects=Effects.parse(effects))
    p, V = 1.5 * BAR, 100.0 * KMH
    x = np.zeros(len(STATE_NAMES))
    for name, value in (("psi", 0.3), ("theta1", 0.1), ("alpha1", 0.05), ("alpha2", -0.04), ("psi_dot", 0.5)):
        x[STATE_NAMES.index(name)] = value
    mbs = MbsFamily(MbsModel(YANG2024, Effects.parse(effects), fidelity=Fidelity.reduced()), pressures=TyrePressures.uniform(p))
    reduced = SpeedFamily(model, pressures=TyrePressures.uniform(p)).rhs(x[:, None], V, p)[:, 0]
    np.testing.assert_allclose(mbs.rhs(x[:, None], V, p)[:, 0], reduced, rtol=1e-10, atol=1e-9)


def test_transient_matches_reduced_model():
    """2 s from a small initial yaw angle at 60 km/h and 1.5 bar (unstable: the oscillation grows)."""
    V, p = 60 * KMH, 1.5 * BAR
    x0 = np.zeros(8)
    x0[0] = 0.01
    traj = integrate(fidelity=Fidelity.reduced(), pressures=TyrePressures.uniform(p), schedule=SpeedSchedule.constant(V), x0=x0,
                    duration=2.0, poses=False)
    assert traj.complete and traj.model == "mbs" and "RK44" in traj.integrator
    model = ShimmyModel()
    ref = solve_ivp(lambda t, x: model.rhs(x, V, TyrePressures.uniform(p)), (0.0, 2.0), x0, method="DOP853", rtol=1e-12, atol=1e-14,
                    dense_output=True)
    xr = ref.sol(traj.t).T
    amplitude = np.max(np.abs(xr), axis=0)
    assert np.all(np.max(np.abs(traj.x - xr), axis=0) <= 1e-4 * amplitude)
    assert amplitude[0] > 0.015       # it did grow: the test compares a non-trivial motion


def test_transient_along_speed_ramp_matches_reduced_model():
    schedule = SpeedSchedule.ramp(40 * KMH, 120 * KMH, 2.0)
    x0 = np.zeros(8)
    x0[4] = 0.005
    traj = integrate(fidelity=Fidelity.reduced(), pressures=TyrePressures.uniform(1.5 * BAR), schedule=schedule, x0=x0, duration=2.0,
                    poses=False)
    model = ShimmyModel()
    ref = solve_ivp(lambda t, x: model.rhs(x, float(schedule.speed(t)), TyrePressures.uniform(1.5 * BAR)), (0.0, 2.0), x0,
                    method="DOP853", rtol=1e-12, atol=1e-14, dense_output=True)
    xr = ref.sol(traj.t).T
    assert np.all(np.max(np.abs(traj.x - xr), axis=0) <= 1e-4 * np.max(np.abs(xr), axis=0))
    assert np.allclose(traj.speed, schedule.speed(traj.t))


def test_limit_cycle_amplitude_matches_reduced_model():
    """60 km/h, 1.5 bar: the steady theta1 amplitude of the MBS against the reduced model's.

    The reference is a long reduced-model simulation (periodic-orbit continuation of the reduced model is not
    available yet); the MBS starts where the reduced run ended and runs 6 s more."""
    V, p = 60 * KMH, 1.5 * BAR
    reference = reduced_steady_amplitude(ShimmyModel(), TyrePressures.uniform(p), V, settle=20.0)
    assert reference.settled and np.degrees(reference.theta1) > 5.0
    mbs = mbs_steady_amplitude(YANG2024, Effects(), Fidelity.reduced(), TyrePressures.uniform(p), V, reference.final_state, settle=6.0)
    assert mbs.settled
    assert abs(mbs.theta1 - reference.theta1) <= 0.005 * reference.theta1
    assert abs(mbs.psi - reference.psi) <= 0.005 * reference.psi


def test_limit_cycle_amplitude_matches_continuation():
    """60 km/h, 1.5 bar: the MBS cycle against the reduced model's periodic-orbit continuation
    (:mod:`bifurcation.cycles.problem`, orthogonal collocation), to 0.5 %."""
    from bifurcation.cycles.branches import branch_from_hopf, cycle_at
    V, p = 60 * KMH, 1.5 * BAR
    family = SpeedFamily(ShimmyModel())
    hopf = find_hopf_points(family, p, 0.0, 400 * KMH)
    branch = branch_from_hopf(family, hopf[0], 0.0, 400 * KMH, others=tuple(hopf[1:]))
    near = min(branch.points, key=lambda c: abs(c.p - V))
    cycle = cycle_at(family, near, V)
    start = reduced_steady_amplitude(ShimmyModel(), TyrePressures.uniform(p), V, settle=6.0)   # a state near the cycle
    mbs = mbs_steady_amplitude(YANG2024, Effects(), Fidelity.reduced(), TyrePressures.uniform(p), V, start.final_state, settle=6.0)
    assert mbs.settled
    assert abs(mbs.theta1 - cycle.max_abs("theta1")) <= 0.005 * cycle.max_abs("theta1")
    assert abs(mbs.psi - cycle.max_abs("psi")) <= 0.005 * cycle.max_abs("psi")
