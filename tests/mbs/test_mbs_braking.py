"""Braking in both models (issue 32, part 2): the MBS with every assumption on against the reduced model under
braking (right-hand sides, steady states, eigenvalues), the MBS's brake moments against a hand derivation, and the
linear growth rate at the braked steady state against a simulation.

The reduced side is :class:`reduced_model.model.ShimmyModel` with its F_x moment -side l F_x; the MBS side puts F_x
at the contact point of the knuckle's pose along the wheel's heading (:func:`mbs_shimmy.tyre_element.brake_forces`).
"""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from axles.braking import Braking
from hand_pose import wheel_pose
from axles.dimensions import DEFAULT_DIMENSIONS
from axles.parameters import YANG2024
from axles.pressures import TyrePressures
from axles.units import BAR, KMH, kmh
from comparisons.api import family_of
from mbs_shimmy import Fidelity
from mbs_shimmy.fidelity import ISSUE_18
from mbs_shimmy.evaluator import constant_speed
from mbs_shimmy.model import MbsModel
from reduced_model import tyre
from reduced_model.model import Effects, ShimmyModel

BRAKINGS = {"both": Braking.of_slip(0.05, 0.05), "right": Braking.of_slip(0.08, 0.0),
            "force": Braking.of_force(1500.0, 3000.0), "driving": Braking.of_slip(-0.06, 0.02),
            "drive force": Braking.of_force(-2500.0, 0.0)}


def _eigs(A):
    lam = np.linalg.eigvals(A)
    return lam[np.lexsort((lam.imag, lam.real))]


def _pair(effects, braking, pressure):
    e = Effects.parse(effects)
    p = TyrePressures.uniform(pressure * BAR)
    red = family_of(ShimmyModel(effects=e), p, "pressure", braking)
    mbs = family_of(MbsModel(effects=e, fidelity=Fidelity.reduced()), p, "pressure", braking)
    return red, mbs


@pytest.mark.parametrize("effects", ["", "all"])
@pytest.mark.parametrize("name", sorted(BRAKINGS))
def test_mbs_with_every_assumption_reproduces_the_reduced_model_under_braking(effects, name):
    red, mbs = _pair(effects, BRAKINGS[name], 1.5)
    q = red.nominal
    rng = np.random.default_rng(32)
    for speed_kmh in (30.0, 90.0, 200.0):
        V = speed_kmh * KMH
        x_red, x_mbs = red.equilibrium(V, q), mbs.equilibrium(V, q)
        assert np.max(np.abs(x_red)) > 1e-4                    # braking deflects the steering
        assert np.max(np.abs(x_red - x_mbs)) < 1e-9 * np.max(np.abs(x_red))
        for _ in range(3):
            x = x_red + rng.normal(scale=0.02, size=8)
            a, b = red.rhs(x, V, q), mbs.rhs(x, V, q)
            assert np.max(np.abs(a - b)) < 1e-9 * np.max(np.abs(a))
        a, b = _eigs(red.linear_matrix(V, q)), _eigs(mbs.linear_matrix(V, q))
        assert np.max(np.abs(a - b) / np.abs(a)) < 1e-9


def test_free_rolling_given_as_zero_braking_is_the_paper_model_exactly():
    red, _ = _pair("", Braking.of_slip(0.0, 0.0), 1.5)
    free = family_of(ShimmyModel(), TyrePressures.uniform(1.5 * BAR))
    V, q = 80 * KMH, 1.5 * BAR
    assert np.array_equal(red.equilibrium(V, q), np.zeros(8))
    assert np.array_equal(red.linear_matrix(V, q), free.linear_matrix(V, q))


def _forces_at_zero(system, braked):
    m = system.layout.n_mech
    system.set_state(np.zeros(2 * m + 2))
    return np.array(system.forces.evaluate(0.0, [0.0] * (m + 2), [0.0] * (m + 2), python=True,
                                           free_rolling=not braked))


def test_brake_moments_of_the_full_geometry_against_a_hand_derivation():
    """Full geometry (kingpin inclination d, caster g, raised roll axis, lateral mounts), straight running, alpha = 0,
    a tyre without the slip-induced side force (r_Vy1 = r_Vy2 = 0) and without the aligning moment's lever s F_x
    (s_Sz1 = s_Sz2 = 0), so that braking adds only F_x = F_x0(kappa) along x at the contact point P = (0, s L/2, 0).

    The kingpin e = (-tan g, -s tan d, 1) / N, N = sqrt(1 + tan^2 g + tan^2 d), through K = (0, s (L/2 - l), R),
    meets the road at G = K - R N e = (R tan g, s (L/2 - l + R tan d), 0).  The moment of F = (F_x, 0, 0) at P about
    the kingpin is e.((P - G) x F) = -e_z (P_y - G_y) F_x = -s r_s F_x / N with the scrub radius r_s = l - R tan d;
    about the roll axis (x through O) ((P - O) x F)_x = 0, and no lateral force."""
    params = YANG2024.replace(r_vy1=0.0, r_vy2=0.0, s_sz1=0.0, s_sz2=0.0)
    braking = Braking.of_slip(0.06, 0.03)
    pressures = TyrePressures.uniform(2.0 * BAR)
    model = MbsModel(params=params, fidelity=Fidelity(ISSUE_18))
    system = model.system(pressures, constant_speed(20.0), braking=braking)
    L = system.layout
    dQ = _forces_at_zero(system, True) - _forces_at_zero(system, False)
    d, g = DEFAULT_DIMENSIONS.kingpin_inclination, params.gamma
    N = math.sqrt(1 + math.tan(g) ** 2 + math.tan(d) ** 2)
    rs = params.l - params.R * math.tan(d)
    lf = tyre.longitudinal_formula(params, pressures.right)
    for name, side, slip in (("theta1", -1.0, braking.right), ("theta2", 1.0, braking.left)):
        Fx = lf.force(-slip)
        assert Fx < -1000.0
        assert dQ[L.index(name)] == pytest.approx(-side * rs * Fx / N, rel=1e-10, abs=1e-9)
    assert abs(dQ[L.index("psi")]) < 1e-9 and abs(dQ[L.index("y_axle")]) < 1e-9
    assert np.all(dQ[L.n_mech:] == 0.0)             # the slip rates do not see braking


def test_aligning_moment_lever_of_the_brake_force_against_a_hand_derivation():
    """MF 6.1's s F_x of the combined aligning moment (4.E71), s = R s_Sz1 at alpha = 0 (F_y = 0 without S_Vyk), the
    right wheel's s_Sz1 mirrored: a moment s F_x about the road normal, whose kingpin component at straight running
    is e_z s F_x = s F_x / N (full geometry, as the test above) and s F_x with every assumption on."""
    params = YANG2024.replace(r_vy1=0.0, r_vy2=0.0, s_sz2=0.0)
    bare = params.replace(s_sz1=0.0)
    braking = Braking.of_slip(0.06, 0.03)
    pressures = TyrePressures.uniform(2.0 * BAR)
    lf = tyre.longitudinal_formula(params, pressures.right)
    d, g = DEFAULT_DIMENSIONS.kingpin_inclination, params.gamma
    for fidelity, N in ((Fidelity(ISSUE_18), math.sqrt(1 + math.tan(g) ** 2 + math.tan(d) ** 2)),
                        (Fidelity.reduced(), 1.0)):
        Q = [_forces_at_zero(MbsModel(params=p, fidelity=fidelity).system(pressures, constant_speed(20.0),
                                                                          braking=braking), True)
             for p in (params, bare)]
        L = MbsModel(params=params, fidelity=fidelity).system(pressures, constant_speed(20.0)).layout
        dQ = Q[0] - Q[1]
        for name, side, slip in (("theta1", -1.0, braking.right), ("theta2", 1.0, braking.left)):
            s = side * params.R * params.s_sz1           # the right wheel (side -1) mirrored
            assert dQ[L.index(name)] == pytest.approx(s * lf.force(-slip) / N, rel=1e-10)
        assert abs(dQ[L.index("psi")]) < 1e-9


def test_first_order_brake_moment_is_the_wheel_offset_times_the_force():
    """All assumptions on: the kingpin moment of F_x is -side l F_x at the straight-running arm, as the rolling
    resistance's in (2.1)-(2.2), and F_x has no tramp moment."""
    params = YANG2024.replace(r_vy1=0.0, r_vy2=0.0, s_sz1=0.0, s_sz2=0.0)
    braking = Braking.of_slip(0.06, 0.03)
    pressures = TyrePressures.uniform(2.0 * BAR)
    system = MbsModel(params=params, fidelity=Fidelity.reduced()).system(pressures, constant_speed(20.0),
                                                                         braking=braking)
    L = system.layout
    dQ = _forces_at_zero(system, True) - _forces_at_zero(system, False)
    lf = tyre.longitudinal_formula(params, pressures.right)
    assert dQ[L.index("theta1")] == pytest.approx(params.l * lf.force(-0.06), rel=1e-12)
    assert dQ[L.index("theta2")] == pytest.approx(-params.l * lf.force(-0.03), rel=1e-12)
    assert dQ[L.index("psi")] == 0.0


def test_asymmetric_braking_steers_toward_the_braked_wheel():
    """A positive scrub radius: the braked right wheel's rearward force turns it outward, and the tie rod takes the
    left wheel along: both steer right (theta < 0 about +z), and the slip angles hold the steer."""
    red, _ = _pair("", BRAKINGS["right"], 2.5)
    x = red.equilibrium(60 * KMH, red.nominal)
    assert x[0] < 0.0 and x[2] < 0.0
    assert x[6] == pytest.approx(-x[0], rel=1e-9) and x[7] == pytest.approx(-x[2], rel=1e-9)
    assert np.max(np.abs(x[[1, 3, 5]])) < 1e-12


@pytest.mark.parametrize("name", ["both", "right"])
def test_linear_growth_rate_at_the_braked_steady_state_against_a_simulation(name):
    """The least stable eigenvalue at the braked steady state against a simulation of the nonlinear equations
    started a 1e-7 rad step along its mode: the growth (or decay) rate of the oscillation's envelope and its
    frequency."""
    red, _ = _pair("", BRAKINGS[name], 1.5)
    q, V = red.nominal, 60 * KMH
    x0 = red.equilibrium(V, q)
    lam, vecs = np.linalg.eig(red.linear_matrix(V, q))
    k = int(np.argmax(lam.real + (lam.imag <= 0) * -1e9))
    v = vecs[:, k] / np.max(np.abs(vecs[:, k]))
    period = 2 * math.pi / lam[k].imag
    T = 6 * period
    sol = solve_ivp(lambda t, x: red.rhs(x, V, q), (0, T), x0 + 1e-7 * v.real, method="DOP853", rtol=1e-11,
                    atol=1e-16, dense_output=True)
    t = np.linspace(0, T, 6001)
    dev = sol.sol(t)[0] - x0[0]
    # envelope from the peaks of |theta1 - theta1_eq| in the first and last period
    first = np.max(np.abs(dev[t <= period])), np.max(np.abs(dev[t >= T - period]))
    rate = math.log(first[1] / first[0]) / (T - period)
    # sampled at 1000 points a period, the peaks are within 5e-6 of the envelope; measured agreement is 1e-8
    assert lam[k].real > 0.5 and rate == pytest.approx(lam[k].real, rel=1e-4)
    crossings = t[1:][np.diff(np.sign(dev)) != 0]
    freq = (len(crossings) - 1) / (2 * (crossings[-1] - crossings[0]))
    assert freq == pytest.approx(lam[k].imag / (2 * math.pi), rel=0.01)


def test_full_geometry_growth_rate_under_asymmetric_braking_against_exudyn():
    """The full geometry braked on the right wheel at 1.5 bar and 60 km/h (inside its yaw window): a small
    oscillation started along the least stable mode at the braked steady state, integrated by Exudyn, grows at Re of
    the eigenvalue of the difference Jacobian there (comparisons.studies.growth, as for the other elements)."""
    from comparisons.studies.growth import envelope_rate
    family = family_of(MbsModel(fidelity=Fidelity.full()), TyrePressures.uniform(1.5 * BAR), "pressure",
                       BRAKINGS["right"])
    result = envelope_rate(family, 60 * KMH, duration=2.0)
    assert result.complete and result.real > 0.1                # growing: measured 0.542 1/s, agreeing to 4e-8
    assert result.agrees, (result.rate, result.real)


def test_hopf_points_and_criticality_under_braking_equal_in_both_models():
    """Braking the right wheel (slip 0.05) at 2.5 bar: both Hopf points and their first Lyapunov coefficients, the reduced
    model's from complex-step multilinear forms at the braked steady state, the MBS's (every assumption on) from
    finite-difference forms at its own steady state.  Both supercritical, as free rolling (docs/results.md,
    "Braking": with the trail moment of the combined F_y instead of MF 6.1's combined M_z they were subcritical)."""
    from bifurcation.equilibria.hopf import find_hopf_points
    red, mbs = _pair("", Braking.of_slip(0.05, 0.0), 2.5)
    q = red.nominal
    a, b = find_hopf_points(red, q, 0.0, 150 * KMH), find_hopf_points(mbs, q, 0.0, 150 * KMH)
    assert len(a) == len(b) == 2
    for h, g in zip(a, b):
        assert abs(kmh(h.p) - kmh(g.p)) < 1e-6 and abs(h.omega - g.omega) < 1e-8 * h.omega
        assert h.first_lyapunov < 0.0 and g.first_lyapunov == pytest.approx(h.first_lyapunov, rel=1e-3)


def _brake_moment(side, theta, psi, kpi, Fx):
    """Independent pose (tests/mbs/hand_pose.py, as tests/mbs/test_mbs_elements.py uses it): the axle rolled by psi about x through
    O = (0, 0, R), the knuckle steered by theta about the kingpin e through K (caster g, inclination kpi); the wheel
    centre C = K + R_k (0, s l, 0), spin axis s = R_k (0, 1, 0), the contact point P the wheel plane's lowest point;
    the brake force F_x along the heading s x z at P.  Returns its moments about the kingpin and about the roll axis."""
    w = wheel_pose(YANG2024, side, theta, psi, kpi)
    F = Fx * w.heading
    return float(w.e @ np.cross(w.contact - w.K, F)), float(np.cross(w.contact - w.O, F)[0])


@pytest.mark.parametrize("theta,psi", [(0.05, 0.0), (-0.2, 0.03), (0.1, -0.05)])
def test_brake_moments_at_a_steered_and_tramped_pose_against_an_independent_pose(theta, psi):
    """The full geometry's brake moments away from straight running (both wheels steered by theta, the axle rolled
    by psi about an axis at wheel-centre height, no lateral travel), against the independent pose above: the force
    turns with the wheel and its arm follows the pose."""
    from mbs_shimmy.fidelity import Assumption
    params = YANG2024.replace(r_vy1=0.0, r_vy2=0.0, s_sz1=0.0, s_sz2=0.0)          # alpha = 0: braking adds F_x alone
    braking = Braking.of_slip(0.06, 0.03)
    pressures = TyrePressures.uniform(2.0 * BAR)
    fidelity = Fidelity(frozenset({Assumption.RIGID_AXLE_MOUNTS, Assumption.ROLL_AXIS_AT_WHEEL_CENTRE,
                                   Assumption.RIGID_STEERING_GEAR}) | ISSUE_18)
    system = MbsModel(params=params, fidelity=fidelity).system(pressures, constant_speed(20.0), braking=braking)
    L = system.layout
    m = L.n_mech
    q = np.zeros(m)
    q[L.index("theta1")], q[L.index("theta2")], q[L.index("psi")] = theta, theta, psi
    system.set_state(np.concatenate([q, np.zeros(m + 2)]))
    args = (0.0, list(q) + [0.0, 0.0], [0.0] * (m + 2))
    dQ = (np.array(system.forces.evaluate(*args, python=True))
          - np.array(system.forces.evaluate(*args, python=True, free_rolling=True)))
    lf = tyre.longitudinal_formula(params, pressures.right)
    states = []
    system.forces.evaluate(*args, states)
    roll = 0.0
    for name, side, slip, state in (("theta1", -1.0, braking.right, states[0]),
                                    ("theta2", 1.0, braking.left, states[1])):
        kingpin, about_x = _brake_moment(side, theta, psi, DEFAULT_DIMENSIONS.kingpin_inclination, lf.force(-slip))
        if state.vertical_force <= 0.0:          # a lifted wheel has no grip: no brake force either
            kingpin, about_x = 0.0, 0.0
        assert dQ[L.index(name)] == pytest.approx(kingpin, rel=1e-9, abs=1e-9)
        roll += about_x
    assert dQ[L.index("psi")] == pytest.approx(roll, rel=1e-9, abs=1e-9)


def test_twin_equals_exudyn_under_braking():
    """With braking in the compiled stage the twin (generated from it) covers the braked full geometry: its
    right-hand side equals Exudyn's (Python user function's combined slip) and its Jacobian Exudyn's five-point
    differences, as tests/mbs/test_mbs_twin.py checks free rolling (constant_load on: no load-table kinks)."""
    from mbs_shimmy.fidelity import Assumption
    from mbs_shimmy.evaluator import MbsEvaluator, speed_is_time
    from mbs_shimmy.twin import twin_of
    fidelity = Fidelity(frozenset({Assumption.CONSTANT_LOAD}))
    braking = Braking.of_slip(-0.04, 0.08)                  # the right wheel driven, the left braked
    system = MbsModel(fidelity=fidelity).system(TyrePressures.uniform(1.5 * BAR), speed_is_time, braking=braking)
    exudyn, twin = MbsEvaluator(system), twin_of(system)
    assert twin is not None
    rng = np.random.default_rng(32)
    m = system.layout.n_mech
    for speed in (5.0, 20.0):
        y = np.concatenate([rng.uniform(-0.004, 0.004, m), rng.uniform(-0.1, 0.1, m), rng.uniform(-0.05, 0.05, 2)])
        f, J, _, ok = twin.rhs_and_jacobian(y, speed)
        fe = exudyn.rhs(y, speed)
        assert ok and np.max(np.abs(f - fe)) <= 1e-10 * np.max(np.abs(fe))
        Je = exudyn.jacobian(y, speed)
        assert np.max(np.abs(J - Je)) <= 1e-10 * np.max(np.abs(Je))
