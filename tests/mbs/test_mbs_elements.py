"""The linear terms each new geometric element adds, against independent calculations (issue 9, items 3-4).

Each element of the full geometry (kingpin inclination, raised roll axis, lateral axle mounts, steering gear) is
checked where its terms enter: the generalized forces of the tyres and the slip rates, computed here by hand
(lever arms at straight running) or from an independent numpy description of the knuckle's pose (rotation about
the raised roll axis, then Rodrigues about the inclined kingpin; the contact point of a disc on a flat road), and
compared with what the multibody model computes from Exudyn's poses.  (The steering gear's series stiffness and
roll steer, and the inertia of the new coordinates: ``tests/test_mbs_model.py``.)  Also the two terms by which
``slip_heading_only`` differs from the full slip kinematics, one at a time.
"""

import math

import numpy as np
import pytest

from axles.units import BAR, KMH, kmh
from axles.dimensions import DEFAULT_DIMENSIONS
from hand_pose import rot, wheel_pose
from mbs_shimmy import Fidelity, tyre_element
from mbs_shimmy.fidelity import ISSUE_18, Assumption
from mbs_shimmy.linearisation import MbsFamily
from mbs_shimmy.evaluator import constant_speed
from mbs_shimmy.model import MbsModel
from reduced_model import tyre
from bifurcation.equilibria.hopf import find_hopf_points
from reduced_model.model import Effects, ShimmyModel
from axles.parameters import YANG2024
from axles.pressures import TyrePressures

P, D = YANG2024, DEFAULT_DIMENSIONS


def _forces_at(system, q, qd):
    """The Python-side generalized forces (tyres, rotor moments, alignment) and slip rates at (q, q')."""
    m = system.layout.n_mech
    system.set_state(np.concatenate([q, qd[:m], qd[m:]]))
    return np.array(system.forces.evaluate(0.0, list(q) + [0.0, 0.0], list(qd)))


def _cornering():
    """dF_y/dalpha at zero slip, 1.5 bar, static load (reduced_model.tyre, central difference)."""
    h = 1e-7
    return float((tyre.lateral_force(P, h, 1.5 * BAR) - tyre.lateral_force(P, -h, 1.5 * BAR)) / (2 * h))


def test_tyre_terms_of_the_raised_roll_axis_lateral_mounts_and_kingpin_inclination():
    """Full geometry, straight running, V = 0 (no rotor moments): derivatives of the tyre forces and slip rates.

    The lateral force F_y = C_a alpha acts at the contact point P = (0, s L/2, 0); the roll axis runs along x through
    O = (0, 0, R + h); the kingpin e = (-tan g, -s tan d, 1) / N, N = sqrt(1 + tan^2 g + tan^2 d), passes through
    K = (0, s (L/2 - l), R).  Hence dQ_psi/dalpha = (R + h) C_a, dQ_y/dalpha = C_a and, with the trail moment
    -t F_y e_z, dQ_theta/dalpha = -(R tan g + t) C_a / N.  The contact point moves sideways at (R + h) psi' + y'
    and at -R tan(g) theta' / N, the leading point a ahead turns at theta' / N: d alpha'/d(psi', y', theta') =
    ((R + h), 1, (a - R tan g) / N) / sigma.
    """
    system = MbsModel(fidelity=Fidelity(ISSUE_18)).system(TyrePressures.uniform(1.5 * BAR), constant_speed(0.0))
    L = system.layout
    m = L.n_mech
    h = D.roll_axis_above_wheel_centre
    N = math.sqrt(1 + math.tan(P.gamma) ** 2 + math.tan(D.kingpin_inclination) ** 2)
    Ca = _cornering()
    zero = np.zeros(m)
    for i, (th, alpha) in enumerate((("theta1", m), ("theta2", m + 1))):
        dq = 1e-7
        qd = np.zeros(m + 2)
        qd[alpha] = dq
        up = _forces_at(system, zero, qd)
        qd[alpha] = -dq
        down = _forces_at(system, zero, qd)
        dQ = (up - down) / (2 * dq)
        assert dQ[L.index("psi")] == pytest.approx((P.R + h) * Ca, rel=1e-7)
        assert dQ[L.index("y_axle")] == pytest.approx(Ca, rel=1e-7)
        assert dQ[L.index(th)] == pytest.approx(-(P.R * math.tan(P.gamma) + P.t0) * Ca / N, rel=1e-7)
        for name, expected in (("psi", P.R + h), ("y_axle", 1.0), (th, (P.a0 - P.R * math.tan(P.gamma)) / N)):
            qd = np.zeros(m + 2)
            qd[L.index(name)] = 1.0
            rate = _forces_at(system, zero, qd)[alpha]
            assert rate == pytest.approx(expected / P.sigma0, rel=1e-12), name


def _static_load_moment(side, theta, kpi, psi=0.0, h=0.0):
    """Independent: moment about the kingpin and about the roll axis of the vertical load F_z = F_z0 + k5 (R - rho)
    at the contact point and of the rolling resistance f F_z at the wheel centre (a free-rolling wheel: its bearing
    carries no moment about the spin axis), for the axle rolled by psi about x through O = (0, 0, R + h) and the
    knuckle steered by theta (no lateral travel).

    The kingpin through K = (0, s (L/2 - l), R) along e (axle frame, then rolled); the wheel centre
    C = K + R_k (0, s l, 0), spin axis s = R_k (0, 1, 0), R_k the rotation by theta about e; the contact point is the
    wheel plane's lowest point P = C + rho d, d = (-z + (z.s) s) / |...|, rho = C_z / |d_z| (the loaded radius).
    Returns (moment about the kingpin, moment about the roll axis)."""
    w = wheel_pose(P, side, theta, psi, kpi, h)
    O, e, K, C, Pc, rho = w.O, w.e, w.K, w.C, w.contact, w.rho
    k5 = ShimmyModel(P, Effects()).tyres(TyrePressures.uniform(1.5 * BAR))[0].k5
    Fz = P.Fz + k5 * (P.R - rho)
    vertical, rolling = np.array([0.0, 0.0, Fz]), -P.f * Fz * w.heading
    about_kingpin = e @ (np.cross(Pc - K, vertical) + np.cross(C - K, rolling))
    about_roll = np.cross(Pc - O, vertical)[0] + np.cross(C - O, rolling)[0]
    return float(about_kingpin), float(about_roll)


@pytest.mark.parametrize("kpi", [0.0, D.kingpin_inclination])
def test_static_load_moment_with_kingpin_inclination(kpi):
    """Kingpin inclination adds weight jacking: the steered wheel rises on the inclined kingpin, and the load at the
    scrub radius l - R tan(kpi) turns it back.  The model's moment about the kingpin (Exudyn's poses, the tyre
    element) equals the independent one at any steer angle, less the alignment at straight running; the linear
    term (the jacking stiffness) therefore too."""
    fidelity = Fidelity(frozenset({Assumption.RIGID_AXLE_MOUNTS, Assumption.ROLL_AXIS_AT_WHEEL_CENTRE,
                                   Assumption.RIGID_STEERING_GEAR}
                                  | ({Assumption.NO_KINGPIN_INCLINATION} if kpi == 0.0 else set())) | ISSUE_18)
    system = MbsModel(fidelity=fidelity).system(TyrePressures.uniform(1.5 * BAR), constant_speed(0.0))
    L = system.layout
    stiffness = {}
    for i, (name, side) in enumerate((("theta1", -1.0), ("theta2", 1.0))):
        for theta in (-0.3, -0.05, 0.02, 0.2):
            q = np.zeros(L.n_mech)
            q[L.index(name)] = theta
            ours = _forces_at(system, q, np.zeros(L.n_mech + 2))[L.index(name)]
            expected = _static_load_moment(side, theta, kpi)[0] - _static_load_moment(side, 0.0, kpi)[0]
            assert ours == pytest.approx(expected, rel=1e-9, abs=1e-9)
        h = 1e-5
        stiffness[name] = -(_static_load_moment(side, h, kpi)[0] - _static_load_moment(side, -h, kpi)[0]) / (2 * h)
    # the numbers behind the README's reading (N m/rad): jacking stiffness about each kingpin
    if kpi:
        assert stiffness["theta1"] == pytest.approx(stiffness["theta2"], rel=1e-6)
        assert stiffness["theta1"] > 0.0


def test_free_rolling_wheel_rolling_resistance_at_the_wheel_centre():
    """Issue 18, item 1: the rolling resistance reaches the knuckle at the wheel centre.  Full geometry with roll
    about the raised axis and steer (no tyre slip, V = 0): the model's moments about both kingpins and the roll axis
    equal the independent ones at rolled and steered poses.  Hand derivation of what moving the force from P to C
    changes: at P it adds (P - C) x (-f F_z x_w) = rho f F_z s (the loaded radius along the wheel plane's downward
    d, d x x_w = -s), whose component about the kingpin f rho F_z (e.s) has e.s = -side tan(kpi) / N fixed by the
    knuckle (invariant under roll and steer); so the old form added to dQ_theta/dpsi (roll to kingpin)
    f (e.s) d(rho F_z)/dpsi = -f tan(kpi) / N (L/2) (F_z0 - k5 R) per wheel (226 N m/rad with Table 1, 1.5 bar)."""
    system = MbsModel(fidelity=Fidelity(frozenset({Assumption.RIGID_AXLE_MOUNTS,
                                                   Assumption.RIGID_STEERING_GEAR}) | ISSUE_18)).system(
        TyrePressures.uniform(1.5 * BAR), constant_speed(0.0))
    L = system.layout
    h, kpi = D.roll_axis_above_wheel_centre, D.kingpin_inclination
    ref = [_static_load_moment(side, 0.0, kpi, 0.0, h) for side in (-1.0, 1.0)]
    for psi, th1, th2 in ((0.05, 0.0, 0.0), (-0.03, 0.1, -0.2), (0.08, -0.15, 0.05)):
        q = np.zeros(L.n_mech)
        q[L.index("psi")], q[L.index("theta1")], q[L.index("theta2")] = psi, th1, th2
        Q = _forces_at(system, q, np.zeros(L.n_mech + 2))
        m1 = _static_load_moment(-1.0, th1, kpi, psi, h)
        m2 = _static_load_moment(1.0, th2, kpi, psi, h)
        assert Q[L.index("theta1")] == pytest.approx(m1[0] - ref[0][0], rel=1e-9, abs=1e-8)
        assert Q[L.index("theta2")] == pytest.approx(m2[0] - ref[1][0], rel=1e-9, abs=1e-8)
        assert Q[L.index("psi")] == pytest.approx(m1[1] + m2[1] - ref[0][1] - ref[1][1], rel=1e-9, abs=1e-8)
    # the hand formula of the brake-like term the old form added (difference of the two forms, independent side)
    k5 = ShimmyModel(P, Effects()).tyres(TyrePressures.uniform(1.5 * BAR))[0].k5
    N = math.sqrt(1 + math.tan(P.gamma) ** 2 + math.tan(kpi) ** 2)
    hand = -P.f * math.tan(kpi) / N * 0.5 * P.L * (P.Fz - k5 * P.R)
    assert hand == pytest.approx(226.16, abs=0.01)

    def brake_term(side, psi):
        """f rho F_z (e.s) about the kingpin: the moment of the force at P less the same force at C."""
        O = np.array([0.0, 0.0, P.R + h])
        Rx = rot([1.0, 0.0, 0.0], psi)
        C = O + Rx @ (np.array([0.0, side * 0.5 * P.L, P.R]) - O)
        s = Rx @ np.array([0.0, 1.0, 0.0])
        e = np.array([-math.tan(P.gamma), -side * math.tan(kpi), 1.0])
        e = Rx @ (e / np.linalg.norm(e))
        rho = C[2] / math.sqrt(1 - s[2] ** 2)
        return P.f * rho * (P.Fz + k5 * (P.R - rho)) * (e @ s)
    dpsi = 1e-6
    for side in (-1.0, 1.0):
        numeric = -(brake_term(side, dpsi) - brake_term(side, -dpsi)) / (2 * dpsi)
        assert -numeric == pytest.approx(hand, rel=1e-6)


def _slip_with_one_term(keep):
    """TyreElement.linear whose slip rate has only one of the two terms slip_heading_only leaves out."""
    original = tyre_element.TyreElement.linear

    def linear(self, psi, theta, psi_d, theta_d, alpha, speed, record=False, braked=True):
        self.heading_only = True
        r = list(original(self, psi, theta, psi_d, theta_d, alpha, speed, record, braked))
        r[2] += {"roll": self.R * psi_d, "trail": -self.gamma * self.R * theta_d}[keep] / self.sigma
        return tuple(r)
    return linear


@pytest.mark.parametrize("keep,expected", [
    ("roll", {1.5: [30.46, 101.70], 2.5: [53.92, 69.85]}),
    ("trail", {1.5: [28.60, 93.36, 192.15, 341.93], 2.5: []}),
])
def test_slip_heading_only_terms_one_at_a_time(keep, expected, monkeypatch):
    """The reduced model with one of the two missing slip terms added: R psi' (the rolling axle slides the contact
    patch) removes the tramp mode at 1.5 bar but at 2.5 bar only narrows the yaw window (46.14-70.50 ->
    53.92-69.85 km/h); the caster trail -R gamma theta' is what closes it."""
    monkeypatch.setattr(tyre_element.TyreElement, "linear", _slip_with_one_term(keep))
    for bar, speeds in expected.items():
        family = MbsFamily(MbsModel(fidelity=Fidelity.reduced()), pressures=TyrePressures.uniform(bar * BAR))
        got = [kmh(h.p) for h in find_hopf_points(family, bar * BAR, 0.0, 400 * KMH, lyapunov=False)]
        assert got == pytest.approx(speeds, abs=0.01)
