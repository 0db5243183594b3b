"""The freedoms and elements of issue 18, each against an independent calculation of the linear terms it adds.

Each test keeps every other element out (its switch on), so that the hand derivation stays short: caster-tilted
kingpins through K = (0, s (L/2 - l), R) along e = (-sin g, 0, cos g), roll axis through O = (0, 0, R), rigid
mounts and gear.  The model's side is what the multibody model computes from Exudyn's poses (the Python force
element) or Exudyn's own mass matrix; the expected side is written from the geometry alone.
"""

import math

import exudyn as exu
import numpy as np
import pytest

from comparisons.axles.units import BAR, KMH
from mbs_shimmy import DEFAULT_DIMENSIONS, Fidelity, MbsModel
from mbs_shimmy.fidelity import ELEMENT_ASSUMPTIONS, Assumption
from mbs_shimmy.linearisation import ConstantSpeed
from reduced_model import tyre
from reduced_model.parameters import YANG2024

P, D = YANG2024, DEFAULT_DIMENSIONS


def only(element: Assumption) -> Fidelity:
    """The full geometry with only this element of the new geometry in."""
    return Fidelity(frozenset(ELEMENT_ASSUMPTIONS) - {element})


def _rot(axis, angle):
    a = np.asarray(axis, dtype=float)
    a = a / np.linalg.norm(a)
    K = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + math.sin(angle) * K + (1 - math.cos(angle)) * K @ K


def _forces_at(system, q, qd, t=0.0):
    """The Python-side generalized forces (tyres, rotor moments, alignment) and slip rates at (q, q')."""
    m = system.layout.n_mech
    system.set_state(np.concatenate([q, qd[:m], qd[m:]]))
    return np.array(system.forces.evaluate(t, list(q) + [0.0, 0.0], list(qd)))


def _cornering(pressure=1.5 * BAR):
    h = 1e-7
    return float((tyre.lateral_force(P, h, pressure) - tyre.lateral_force(P, -h, pressure)) / (2 * h))


def _derivative(system, which, index, step=1e-7):
    """d(forces and slip rates)/d(coordinate or velocity ``index``) at straight running, central difference."""
    m = system.layout.n_mech
    out = []
    for sign in (1.0, -1.0):
        q, qd = np.zeros(m), np.zeros(m + 2)
        (q if which == "q" else qd)[index] = sign * step
        out.append(_forces_at(system, q, qd))
    return (out[0] - out[1]) / (2 * step)


# --- axle roll steer -------------------------------------------------------------------------------------------
def test_roll_steer_pose_is_a_rotation_about_the_sloped_axis():
    """Exudyn's kingpin points and kingpin axes at a roll psi: the rotation by psi about u = (1, 0, eps) / |...|
    through O (independent numpy), i.e. a roll psi ux about x and a yaw psi uz about z."""
    system = MbsModel(fidelity=only(Assumption.NO_AXLE_ROLL_STEER)).system(1.5 * BAR, ConstantSpeed(10.0))
    L = system.layout
    get = system.mbs.GetMarkerOutput
    O = np.array([0.0, 0.0, P.R])
    for psi in (0.03, -0.2):
        q = np.zeros(L.n_mech)
        q[L.index("psi")] = psi
        system.set_state(np.concatenate([q, np.zeros(L.n_mech + 2)]))
        Rot = _rot([1.0, 0.0, D.axle_roll_steer], psi)
        for i, side in enumerate((-1.0, 1.0)):
            K0 = np.array([0.0, side * (0.5 * P.L - P.l), P.R])
            mk = system.markers.knuckles[i]
            assert np.asarray(get(mk, exu.OutputVariableType.Position)) == pytest.approx(O + Rot @ (K0 - O),
                                                                                        abs=1e-12)
            e = np.reshape(get(mk, exu.OutputVariableType.RotationMatrix), (3, 3))[:, 2]
            assert e == pytest.approx(Rot @ np.array([-math.sin(P.gamma), 0.0, math.cos(P.gamma)]), abs=1e-12)


def test_roll_steer_linear_terms():
    """With the roll axis u = (ux, 0, uz), uz / ux = eps, a tramp rate psi' moves the contact point P (R below O)
    sideways at ux R psi' and turns the contact line at uz psi', so the leading point a ahead slides at
    (ux R + a uz) psi'; a tramp angle psi turns the wheel heading by uz psi against the road speed V: slip rate
    -V uz psi / sigma (as a steer angle does).  The lateral force at P and its trail moment -t F_y about z act on psi
    through u: dQ_psi/dalpha = (ux R - uz t) C_a.  The rotor moment -I2 Omega (omega x s) with omega = psi' u gives
    I2 Omega psi' (uz, 0, -ux): nothing on psi, -I2 Omega (ux cos g + uz sin g) psi' on each kingpin."""
    V = 60 * KMH
    system = MbsModel(fidelity=only(Assumption.NO_AXLE_ROLL_STEER)).system(1.5 * BAR, ConstantSpeed(V))
    L = system.layout
    m = L.n_mech
    eps = D.axle_roll_steer
    ux, uz = 1 / math.sqrt(1 + eps ** 2), eps / math.sqrt(1 + eps ** 2)
    ip = L.index("psi")
    Ca = _cornering()
    kg = P.I2 * V / P.R
    d_psi = _derivative(system, "q", ip)
    d_psid = _derivative(system, "qd", ip)
    for k, th in ((m, "theta1"), (m + 1, "theta2")):
        assert d_psi[k] == pytest.approx(-V * uz / P.sigma0, rel=1e-7)
        assert d_psid[k] == pytest.approx((ux * P.R + P.a0 * uz) / P.sigma0, rel=1e-7)
        d_alpha = _derivative(system, "qd", k)
        assert d_alpha[ip] == pytest.approx((ux * P.R - uz * P.t0) * Ca, rel=1e-7)
        assert d_psid[L.index(th)] == pytest.approx(-kg * (ux * math.cos(P.gamma) + uz * math.sin(P.gamma)),
                                                    rel=1e-7)
    assert abs(d_psid[ip]) < 1e-6 * kg


def test_roll_steer_neutral_is_the_old_model():
    """axle_roll_steer = 0 gives the model without the element to rounding (the same eigenvalues)."""
    from mbs_shimmy import MbsFamily
    a = MbsFamily(MbsModel(fidelity=Fidelity.full(), dims=D.replace(axle_roll_steer=0.0)))
    b = MbsFamily(MbsModel(fidelity=Fidelity(frozenset({Assumption.NO_AXLE_ROLL_STEER}))))
    A, B = a.direct_linear_matrix(70 * KMH, 1.5 * BAR), b.direct_linear_matrix(70 * KMH, 1.5 * BAR)
    assert np.max(np.abs(A - B)) <= 1e-12 * np.max(np.abs(B))
