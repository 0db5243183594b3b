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

from axles.units import BAR, KMH
from axles.dimensions import DEFAULT_DIMENSIONS
from mbs_shimmy import Fidelity
from mbs_shimmy.fidelity import ELEMENT_ASSUMPTIONS, Assumption
from mbs_shimmy.evaluator import constant_speed
from mbs_shimmy.model import MbsModel
from reduced_model import tyre
from axles.parameters import YANG2024
from axles.pressures import TyrePressures

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
    system = MbsModel(fidelity=only(Assumption.NO_AXLE_ROLL_STEER)).system(TyrePressures.uniform(1.5 * BAR), constant_speed(10.0))
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
    system = MbsModel(fidelity=only(Assumption.NO_AXLE_ROLL_STEER)).system(TyrePressures.uniform(1.5 * BAR), constant_speed(V))
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
    from mbs_shimmy.linearisation import MbsFamily
    a = MbsFamily(MbsModel(fidelity=Fidelity.full(), dims=D.replace(axle_roll_steer=0.0)))
    b = MbsFamily(MbsModel(fidelity=Fidelity(frozenset({Assumption.NO_AXLE_ROLL_STEER}))))
    A, B = a.direct_linear_matrix(70 * KMH, 1.5 * BAR), b.direct_linear_matrix(70 * KMH, 1.5 * BAR)
    assert np.max(np.abs(A - B)) <= 1e-12 * np.max(np.abs(B))


# --- camber force ----------------------------------------------------------------------------------------------
def _mf61_lateral(alpha, gamma, load, pressure=1.5 * BAR):
    """Independent MF 6.1 pure side slip with camber (Pacejka 2012, sec. 4.3.2), ISO signs, on the paper's B, C, D,
    E at this load: K_ya = -B C D (1 - p_Ky3 |g|), S_Vg = F_z (p_Vy3 + p_Vy4 df_z) g,
    S_Hy = (F_z (p_Ky6 + p_Ky7 df_z) g - S_Vg) / K_ya, F_y = D sin(C atan(B_y a_y - E (B_y a_y - atan(B_y a_y))))
    + S_Vg with B_y = K_ya / (C D), a_y = alpha + S_Hy; the camber moment F_z R (q_Dz8 + q_Dz9 df_z) g
    cos(atan(q_Bz9 (a_y + S_Vg / K_ya)))."""
    mf = tyre.magic_formula(P.replace(Fz=load), pressure)
    dfz = (load - P.Fz0) / P.Fz0
    Kya = -mf.B * mf.C * mf.D * (1 - D.camber_p_ky3 * abs(gamma))
    Svg = load * (D.camber_p_vy3 + D.camber_p_vy4 * dfz) * gamma
    Shy = (load * (D.camber_p_ky6 + D.camber_p_ky7 * dfz) * gamma - Svg) / Kya
    By = Kya / (mf.C * mf.D)
    ay = alpha + Shy
    Fy = mf.D * math.sin(mf.C * math.atan(By * ay - mf.E * (By * ay - math.atan(By * ay)))) + Svg
    Mz = (load * P.R * (D.camber_q_dz8 + D.camber_q_dz9 * dfz) * gamma
          * math.cos(math.atan(D.camber_q_bz9 * (ay + Svg / Kya))))
    return Fy, Mz


def test_camber_terms_equal_an_independent_mf61():
    """The element's camber force and moment at finite slip, camber and load against the independent MF 6.1 form;
    at zero slip dF_y/dgamma is the camber stiffness F_z (p_Ky6 + p_Ky7 df_z) (-5.39 kN/rad at 6 kN)."""
    from mbs_shimmy.camber import CamberTerms, camber_terms
    from mbs_shimmy.scalar_ops import MATH
    c = CamberTerms.of(D, P).coefficients

    def terms(mf, alpha, load, gamma, plain):     # as the tyre element calls it
        return camber_terms(c, mf.B, mf.C, mf.D, mf.E, alpha, load, gamma, plain, MATH)
    for alpha, gamma, load in ((0.0, 0.02, 6000.0), (0.03, -0.05, 7500.0), (-0.1, 0.08, 4000.0)):
        mf = tyre.magic_formula(P.replace(Fz=load), 1.5 * BAR)
        dFy, mz = terms(mf, alpha, load, gamma, mf.force(alpha))
        Fy, Mz = _mf61_lateral(alpha, gamma, load)
        assert mf.force(alpha) + dFy == pytest.approx(Fy, rel=1e-12, abs=1e-9)
        assert mz == pytest.approx(Mz, rel=1e-12, abs=1e-12)
    h = 1e-6
    mf = tyre.magic_formula(P, 1.5 * BAR)
    stiffness = (terms(mf, 0.0, P.Fz, h, 0.0)[0] - terms(mf, 0.0, P.Fz, -h, 0.0)[0]) / (2 * h)
    assert stiffness == pytest.approx(P.Fz * D.camber_p_ky6, rel=1e-8)
    assert stiffness == pytest.approx(-5392.2, abs=0.1)


def test_camber_linear_terms():
    """What the camber terms add to the stiffness at straight running (V = 0; the model with them less the model
    without; every other element out).  Camber gamma = asin(s_z): a tramp psi cambers both wheels by psi, a steer
    theta by -sin(g) theta (the caster tilts the spin axis).  Per unit of camber the camber force
    K_g = F_z p_Ky6 acts at P = (0, s L/2, 0) along y: R K_g on psi (lever R about the roll axis through (0, 0, R))
    and e.((P - K) x y) K_g = -R sin(g) K_g on the kingpin; the camber moment M_g = F_z R q_Dz8 about z gives
    cos(g) M_g on the kingpin."""
    with_c = MbsModel(fidelity=only(Assumption.NO_CAMBER_FORCE)).system(TyrePressures.uniform(1.5 * BAR), constant_speed(0.0))
    without = MbsModel(fidelity=Fidelity(frozenset(ELEMENT_ASSUMPTIONS))).system(TyrePressures.uniform(1.5 * BAR), constant_speed(0.0))
    L = with_c.layout
    assert L == without.layout
    g = P.gamma
    Kg, Mg = P.Fz * D.camber_p_ky6, P.Fz * P.R * D.camber_q_dz8
    on_kingpin = -P.R * math.sin(g) * Kg + math.cos(g) * Mg       # per unit of camber
    dgamma = {"psi": 1.0, "theta1": -math.sin(g), "theta2": -math.sin(g)}
    for name in ("psi", "theta1", "theta2"):
        added = (_derivative(with_c, "q", L.index(name), 1e-6) - _derivative(without, "q", L.index(name), 1e-6))
        wheels = (("theta1", "theta2") if name == "psi" else (name,))
        assert added[L.index("psi")] == pytest.approx(len(wheels) * P.R * Kg * dgamma[name], rel=1e-6)
        for th in ("theta1", "theta2"):
            expected = on_kingpin * dgamma[name] if th in wheels else 0.0
            assert added[L.index(th)] == pytest.approx(expected, rel=1e-6, abs=1e-6 * abs(on_kingpin))


# --- bounce on the vertical mounts -----------------------------------------------------------------------------
class _NoForces:
    """Stands in for the Python force element: Exudyn's own elements (tree, joint springs, connectors) alone."""

    def __init__(self, n):
        self.n = n

    def evaluate(self, t, q, qd, states=None):
        return [0.0] * self.n


def test_bounce_linear_terms():
    """The axle's bounce z (only this element in, V = 0).  Hand derivation:

    * mass: the whole axle moves with z, M_zz = m_axle + 2 (m_knuckle + m_wheel); steering moves the knuckle-wheel
      centre of mass c = m_wheel (0, s l, 0) / m vertically by (e x c)_z = -sin(g) s l m_wheel / m per unit of steer,
      so M_z,theta = -m_wheel s l sin(g); roll moves the symmetric masses in opposite vertical senses: M_z,psi = 0;
    * springs: the mounts' own 1 / compliance (Exudyn's joint P control) and the two tyres, dF_z/dz = -k5 each;
    * toe from the load change: the load change -k5 z at the contact point (lever about the kingpin -s l sin(g)) and
      its rolling resistance f k5 z at the wheel centre (lever s l cos(g)): dQ_theta/dz = s l k5 (sin g - f cos g),
      the paper's l (gamma - f) lever; on psi the two wheels' load changes cancel;
    * bump steer: the drag link rises at eps towards the gear, so lifting its arm end by z shortens it by
      z sin(eps): K[theta2, z] = k_d j (-sin eps) with j = -r_d cos(g - eps) its lever about the kingpin and
      k_d = k2 / j^2 (as the roll steer of tests/mbs/test_mbs_model.py)."""
    from mbs_shimmy.evaluator import MbsEvaluator
    from reduced_model.model import Effects, ShimmyModel
    system = MbsModel(fidelity=only(Assumption.RIGID_VERTICAL_MOUNTS)).system(TyrePressures.uniform(1.5 * BAR), constant_speed(0.0))
    L = system.layout
    assert L.coordinates == ("z_axle", "psi", "theta1", "theta2")
    m = L.n_mech
    iz, ip = L.index("z_axle"), L.index("psi")
    g = P.gamma
    k5 = ShimmyModel(P, Effects()).tyres(TyrePressures.uniform(1.5 * BAR))[0].k5
    M = MbsEvaluator(system).mass_matrix(np.zeros(2 * m + 2))
    m_total = D.axle_mass + 2 * (D.knuckle_mass + D.wheel_mass)
    assert M[iz, iz] == pytest.approx(m_total, rel=1e-13)
    assert abs(M[iz, ip]) < 1e-12 * m_total
    for th, side in (("theta1", -1.0), ("theta2", 1.0)):
        assert M[iz, L.index(th)] == pytest.approx(-D.wheel_mass * side * P.l * math.sin(g), rel=1e-10)
    dz = _derivative(system, "q", iz, 1e-6)
    assert dz[iz] == pytest.approx(-2 * k5, rel=1e-7)
    assert abs(dz[ip]) < 1e-6 * k5
    for th, side in (("theta1", -1.0), ("theta2", 1.0)):
        assert dz[L.index(th)] == pytest.approx(side * P.l * k5 * (math.sin(g) - P.f * math.cos(g)), rel=1e-6)
    # Exudyn's own elements: the mounts' spring; with the rigid gear the drag link is level (no bump steer), with
    # the gear in it rises at eps to the Pitman arm and bounce steers the left wheel
    for fidelity, eps in ((only(Assumption.RIGID_VERTICAL_MOUNTS), 0.0),
                          (Fidelity(only(Assumption.RIGID_VERTICAL_MOUNTS).assumed - {Assumption.RIGID_STEERING_GEAR}),
                           D.drag_link_inclination)):
        K = _connector_stiffness(fidelity, "z_axle")
        layout = MbsModel(fidelity=fidelity).forces(TyrePressures.uniform(1.5 * BAR), constant_speed(0.0)).layout
        j = -D.drag_link_arm * math.cos(g - eps)
        assert K[layout.index("z_axle")] == pytest.approx(
            1.0 / D.axle_mount_vertical_compliance + P.k2 / j ** 2 * math.sin(eps) ** 2, rel=1e-6)
        assert K[layout.index("theta2")] == pytest.approx(P.k2 / j * (-math.sin(eps)), rel=1e-6, abs=1e-6 * P.k2)
        assert abs(K[layout.index("theta1")]) < 1e-6 * P.k2


def _connector_stiffness(fidelity, name):
    """-dQ/d(name) of Exudyn's own elements (tree, joint springs, connectors) without the Python force element."""
    from mbs_shimmy.evaluator import MbsEvaluator
    system = MbsModel(fidelity=fidelity).system(TyrePressures.uniform(1.5 * BAR), constant_speed(0.0))
    m = system.layout.n_mech
    system.forces = _NoForces(m + 2)
    ev = MbsEvaluator(system)

    def Q(q):
        system.set_state(np.concatenate([q, np.zeros(m + 2)]))
        ev.solver.ComputeODE2RHS(system.mbs)
        return np.array(ev.solver.GetSystemResidual())[:m]
    h = 1e-6
    e = np.eye(m)[system.layout.index(name)]
    return -(Q(h * e) - Q(-h * e)) / (2 * h)


# --- link masses -----------------------------------------------------------------------------------------------
@pytest.mark.parametrize("with_mounts_and_gear", [False, True])
def test_link_masses_in_the_mass_matrix(with_mounts_and_gear):
    """Each rod as two point masses, half at each ball joint: the change of Exudyn's mass matrix against an
    independent sum over the joints' velocities.  A ball at p on knuckle i moves at
    v = y' y + psi' x x (p - O) + theta_i' e x (p - K) (roll axis x through O = (0, 0, R), kingpin e through K),
    the Pitman ball at -r_p phi' x on the gear; so each mass m_b adds m_b (J_a . J_b) to M[a, b].  The arms (no
    Ackermann, no inclination): tie-rod a_t = -r_t (cos g, 0, sin g) rearward, drag-link a_d = (0, -r_d, 0) inboard
    on the left knuckle.  The axle keeps Table 1's I3 about the wheel-centre line (the axle's own share shrinks)."""
    from mbs_shimmy.evaluator import MbsEvaluator
    off = {Assumption.RIGID_AXLE_MOUNTS, Assumption.RIGID_STEERING_GEAR} if with_mounts_and_gear else set()
    fid = Fidelity(only(Assumption.MASSLESS_LINKS).assumed - off)
    ref = Fidelity(fid.assumed | {Assumption.MASSLESS_LINKS})
    systems = [MbsModel(fidelity=f).system(TyrePressures.uniform(1.5 * BAR), constant_speed(0.0)) for f in (fid, ref)]
    L = systems[0].layout
    assert L == systems[1].layout
    M, M0 = (MbsEvaluator(s).mass_matrix(np.zeros(L.n)) for s in systems)
    g = P.gamma
    e = np.array([-math.sin(g), 0.0, math.cos(g)])
    x, y = np.array([1.0, 0.0, 0.0]), np.array([0.0, 1.0, 0.0])
    O = np.array([0.0, 0.0, P.R])
    n = L.n_mech
    expected = np.zeros((n, n))
    balls = []
    for name, side in (("theta1", -1.0), ("theta2", 1.0)):
        K = np.array([0.0, side * (0.5 * P.L - P.l), P.R])
        arms = [(0.5 * D.tie_rod_mass, -D.tie_rod_arm * np.array([math.cos(g), 0.0, math.sin(g)]))]
        if side > 0:
            arms.append((0.5 * D.drag_link_mass, np.array([0.0, -D.drag_link_arm, 0.0])))
        for mb, a in arms:
            J = np.zeros((n, 3))
            J[L.index("psi")] = np.cross(x, K + a - O)
            J[L.index(name)] = np.cross(e, a)
            if L.lateral:
                J[L.index("y_axle")] = y
            balls.append((mb, J))
    if L.gear:
        J = np.zeros((n, 3))
        J[L.index("phi_gear")] = -D.pitman_arm * x
        balls.append((0.5 * D.drag_link_mass, J))
    for mb, J in balls:
        expected += mb * J @ J.T
    ip = L.index("psi")
    roll_share = expected[ip, ip]     # the balls' roll inertia is taken from the axle's own share: I3 stays
    assert roll_share == pytest.approx(6.2437, abs=1e-4)
    expected[ip, ip] = 0.0
    assert M - M0 == pytest.approx(expected, abs=1e-12 * np.max(np.abs(M0)))
    assert M[ip, ip] == pytest.approx(P.I3, rel=1e-12)           # Table 1's roll inertia kept
    assert expected[L.index("theta1"), L.index("theta1")] == pytest.approx(0.5 * D.tie_rod_mass * D.tie_rod_arm ** 2)
