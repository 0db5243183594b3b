"""The multibody model's parts: fidelity switches, geometry against Exudyn's own kinematics, inertia, the spinning
wheels, the linkage, the load table, straight running and the speed-affine Jacobian."""

import math

import exudyn as exu
import numpy as np
import pytest
from exudyn.itemInterface import NodeGenericODE2, ObjectKinematicTree

from axles.units import BAR, KMH
from axles.dimensions import DEFAULT_DIMENSIONS, AxleDimensions
from mbs_shimmy import Assumption, Fidelity, assumptions_table
from comparisons.studies.assumption_study import study_fidelities
from mbs_shimmy.fidelity import ELEMENT_ASSUMPTIONS, ISSUE_18
from mbs_shimmy.geometry import disc_contact
from mbs_shimmy.linearisation import MbsFamily
from mbs_shimmy.evaluator import constant_speed, MbsEvaluator
from mbs_shimmy.model import MbsModel
from mbs_shimmy.system import TreeInertia
from reduced_model.model import Effects
from axles.parameters import YANG2024, ParameterError
from axles.pressures import TyrePressures

# the full geometry of the paper's axle: every assumption off except the new elements (issue 9) kept out
PAPER_GEOMETRY = Fidelity(frozenset(ELEMENT_ASSUMPTIONS))
CURRENT = exu.ConfigurationType.Current


def test_fidelity_parse():
    assert Fidelity.parse("reduced").assumed == frozenset(Assumption)
    assert Fidelity.parse("full").assumed == frozenset()
    f = Fidelity.parse("small_angles, constant_load")
    assert f.assumed == {Assumption.SMALL_ANGLES, Assumption.CONSTANT_LOAD}
    assert f.label == "small_angles,constant_load"
    assert Fidelity.reduced().without("uncoupled_inertia").assumed == frozenset(Assumption) - {
        Assumption.UNCOUPLED_INERTIA}
    with pytest.raises(ParameterError, match="unknown assumption 'small_angle'"):
        Fidelity.parse("small_angle")
    assert [r.name for r in assumptions_table().rows] == [a.value for a in Assumption]
    names = [name for name, _ in study_fidelities()]
    assert names[names.index("full") + 1:] == [a.value for a in ELEMENT_ASSUMPTIONS]
    # the first-order kinematics have no form of the new elements: a clear error, not a silent neutral value
    with pytest.raises(ParameterError, match="small_angles .* has no first-order form of no_kingpin_inclination"):
        MbsModel(fidelity=Fidelity.parse("small_angles")).forces(TyrePressures.uniform(2.0 * BAR), constant_speed(1.0))


def _random_states(n, seed=3):
    rng = np.random.default_rng(seed)
    y = rng.standard_normal((n, 8)) * np.array([0.1, 0.4, 0.4, 1.0, 3.0, 3.0, 0.05, 0.05])
    return y


def _rot(axis, angle):
    """Rodrigues: rotation by angle about the unit axis."""
    a = np.asarray(axis, dtype=float)
    K = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + math.sin(angle) * K + (1 - math.cos(angle)) * K @ K


def test_knuckle_poses_are_exudyns_and_right():
    """The poses the tyres use (Exudyn's markers on the tree, full geometry with lateral travel, raised roll axis,
    kingpin inclination) against an independent hand computation: roll about x through O = (0, y, R + h), then
    the knuckle about its kingpin axis e0 = (-tan(gamma), -side tan(KPI), 1) / |...|."""
    P, d = YANG2024, DEFAULT_DIMENSIONS
    model = MbsModel(fidelity=Fidelity(ISSUE_18))   # the issue-9 elements (issue 18's: tests/mbs/test_mbs_freedoms.py)
    system = model.system(TyrePressures.uniform(1.5 * BAR), constant_speed(20.0))
    L = system.layout
    assert L.coordinates == ("y_axle", "psi", "theta1", "theta2", "phi_gear")
    rng = np.random.default_rng(5)
    h = d.roll_axis_above_wheel_centre
    for _ in range(5):
        q = rng.standard_normal(5) * np.array([0.01, 0.1, 0.4, 0.4, 0.1])
        qd = rng.standard_normal(5) * np.array([0.1, 1.0, 3.0, 3.0, 1.0])
        system.set_state(np.concatenate([q, qd, [0.01, -0.02]]))
        poses = system.forces.knuckle_poses(q, qd)
        y, psi = q[0], q[1]
        A = _rot([1, 0, 0], psi)
        O = np.array([0.0, y, P.R + h])
        for i, side in enumerate((-1.0, 1.0)):
            e0 = np.array([-math.tan(P.gamma), -side * math.tan(d.kingpin_inclination), 1.0])
            e0 /= np.linalg.norm(e0)
            K = O + A @ np.array([0.0, side * (0.5 * P.L - P.l), -h])
            e = A @ e0
            Rk = _rot(e, q[2 + i]) @ A
            vK = np.array([0.0, qd[0], 0.0]) + np.cross([qd[1], 0, 0], K - O)
            omega = qd[1] * np.array([1.0, 0, 0]) + qd[2 + i] * e
            K_, vK_, e_, s_, w_ = poses[i]
            assert np.allclose(K_, K, atol=1e-14) and np.allclose(vK_, vK, atol=1e-13)
            assert np.allclose(e_, e, atol=1e-14) and np.allclose(s_, Rk @ [0, 1, 0], atol=1e-14)
            assert np.allclose(w_, omega, atol=1e-13)
            # and the velocities are Exudyn's own marker velocities
            mk = system.markers.knuckles[i]
            assert np.allclose(vK_, system.mbs.GetMarkerOutput(mk, exu.OutputVariableType.Velocity), atol=1e-13)
            assert np.allclose(w_, system.mbs.GetMarkerOutput(mk, exu.OutputVariableType.AngularVelocity),
                               atol=1e-13)


def test_disc_contact_point_is_on_road_and_wheel_plane():
    rng = np.random.default_rng(1)
    for _ in range(20):
        s = rng.standard_normal(3) * np.array([0.2, 1.0, 0.2]) + np.array([0, 3.0, 0])
        s /= np.linalg.norm(s)
        C = np.array([0.1, -0.8, 0.4]) + 0.01 * rng.standard_normal(3)
        c = disc_contact(tuple(C), tuple(s))
        P = np.array(c.point)
        assert abs(P[2]) < 1e-15                                  # on the road
        assert abs(np.dot(P - C, s)) < 1e-14                      # in the wheel plane
        assert math.isclose(np.linalg.norm(P - C), c.depth, rel_tol=1e-14)
        assert abs(np.dot(c.heading, s)) < 1e-14 and abs(np.dot(c.lateral, c.heading)) < 1e-14


def test_inertia_at_straight_running():
    P, d = YANG2024, DEFAULT_DIMENSIONS
    for fidelity in (Fidelity.reduced(), PAPER_GEOMETRY):
        ev = MbsEvaluator(MbsModel(fidelity=fidelity).system(TyrePressures.uniform(1.5 * BAR), constant_speed(0.0)))
        M = ev.mass_matrix(np.zeros(8))
        assert np.allclose(np.diag(M), [P.I3, P.I1, P.I1], rtol=1e-13)
        assert abs(M[1, 2]) < 1e-14
        if Assumption.UNCOUPLED_INERTIA in fidelity:
            assert abs(M[0, 1]) < 1e-14
            for y in _random_states(3):   # and in every configuration
                assert np.allclose(ev.mass_matrix(y), np.diag([P.I3, P.I1, P.I1]), atol=1e-12)
        else:
            # kingpin axis e and roll axis x: coupling x.J.e of the knuckle-wheel about K plus the wheel's offset
            s = math.sin(P.gamma)
            expected = -(d.knuckle_kingpin_inertia(P) + d.wheel_diametral_inertia) * s \
                - d.wheel_mass * P.l * 0.5 * P.L * s
            assert M[0, 1] == pytest.approx(expected, rel=1e-12)
            assert M[0, 2] == pytest.approx(expected, rel=1e-12)


def test_inertia_of_the_new_coordinates():
    """Full geometry: I1 about each inclined kingpin, I3 + m h^2 about the raised roll axis, the whole axle's mass
    on the lateral travel and its roll coupling -m h, the gear's inertia; uncoupled: diagonal."""
    P, d = YANG2024, DEFAULT_DIMENSIONS
    m_total = d.axle_mass + 2 * (d.knuckle_mass + d.wheel_mass)
    h = d.roll_axis_above_wheel_centre
    full = MbsEvaluator(MbsModel(fidelity=Fidelity(ISSUE_18)).system(TyrePressures.uniform(1.5 * BAR), constant_speed(0.0)))
    M = full.mass_matrix(np.zeros(12))        # (y, psi, theta1, theta2, phi)
    assert M[0, 0] == pytest.approx(m_total, rel=1e-13)
    assert M[1, 1] == pytest.approx(P.I3 + m_total * h ** 2, rel=1e-12)
    assert M[0, 1] == pytest.approx(m_total * h, rel=1e-12)       # rolling moves the centres of mass by +h psi
    assert M[2, 2] == pytest.approx(P.I1, rel=1e-12) and M[3, 3] == pytest.approx(P.I1, rel=1e-12)
    assert M[4, 4] == pytest.approx(d.steering_gear_inertia, rel=1e-13) and np.allclose(M[4, :4], 0.0)
    lumped_model = MbsModel(fidelity=Fidelity(frozenset({Assumption.UNCOUPLED_INERTIA}) | ISSUE_18))
    lumped = MbsEvaluator(lumped_model.system(TyrePressures.uniform(1.5 * BAR), constant_speed(0.0)))
    assert np.allclose(lumped.mass_matrix(np.zeros(12)),
                       np.diag([m_total, P.I3, P.I1, P.I1, d.steering_gear_inertia]), rtol=1e-12, atol=1e-12)


def test_spinning_wheel_equals_rotor_moment():
    """A kinematic tree with the wheels as spinning links (spin V/R) gives the same forces on (psi, theta1,
    theta2) as the model's non-spinning wheels plus the rotor moment -I2 Omega (omega x s), at any state."""
    P, d = YANG2024, DEFAULT_DIMENSIONS
    V = 25.0
    Omega = V / P.R
    # kingpin inclination on (it tilts e against the wheel axis); no new coordinates
    fidelity = Fidelity(frozenset(ELEMENT_ASSUMPTIONS) - {Assumption.NO_KINGPIN_INCLINATION})
    model = MbsModel(fidelity=fidelity)
    g = model.forces(TyrePressures.uniform(1.5 * BAR), constant_speed(V)).g_exact
    inertia = TreeInertia.build(P, d, False, g)
    # spinning model: knuckle links carry the knuckle only; each wheel is a link spinning about its axis y
    e_knuckle = [inertia.joint_rotations[i] for i in range(2)]
    e = inertia.joint_rotations[1][:, 2]
    c = np.array([0.0, P.l, 0.0])
    Jk_e = P.I1 - e @ (np.diag([d.wheel_diametral_inertia, P.I2, d.wheel_diametral_inertia])
                       + d.wheel_mass * (c @ c * np.eye(3) - np.outer(c, c))) @ e
    Jk_joint = np.diag([d.knuckle_transverse_inertia, d.knuckle_transverse_inertia, Jk_e])
    Jw = np.diag([d.wheel_diametral_inertia, P.I2, d.wheel_diametral_inertia])
    half = 0.5 * P.L - P.l
    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    node = mbs.AddNode(NodeGenericODE2(referenceCoordinates=[0.0] * 5, initialCoordinates=[0.0] * 5,
                                       initialCoordinates_t=[0.0] * 5, numberOfODE2Coordinates=5))
    J = exu.JointType
    mbs.AddObject(ObjectKinematicTree(
        nodeNumber=node, jointTypes=[J.RevoluteX, J.RevoluteZ, J.RevoluteZ, J.RevoluteY, J.RevoluteY],
        linkParents=[-1, 0, 0, 1, 2],
        jointTransformations=exu.Matrix3DList([np.eye(3), e_knuckle[0], e_knuckle[1], e_knuckle[0].T,
                                               e_knuckle[1].T]),
        jointOffsets=exu.Vector3DList([[0, 0, P.R], [0, -half, 0], [0, half, 0],
                                       list(e_knuckle[0].T @ np.array(g.wheel_centre(-1.0))),
                                       list(e_knuckle[1].T @ np.array(g.wheel_centre(1.0)))]),
        linkInertiasCOM=exu.Matrix3DList([inertia.inertias[0], Jk_joint, Jk_joint, Jw, Jw]),
        linkCOMs=exu.Vector3DList([[0.0, 0, 0]] * 5),
        linkMasses=[d.axle_mass, d.knuckle_mass, d.knuckle_mass, d.wheel_mass, d.wheel_mass]))
    mbs.Assemble()
    spinning = exu.MainSolverExplicit()
    settings = exu.SimulationSettings()
    settings.solution.file.write = False
    settings.timeIntegration.solverType = exu.DynamicSolverType.RK44
    spinning.InitializeSolver(mbs, settings)
    # the model's tree (non-spinning wheels) with only the rotor moments as forces
    forces = model.forces(TyrePressures.uniform(1.5 * BAR), constant_speed(V))

    system = model.system(TyrePressures.uniform(1.5 * BAR), constant_speed(V))
    forces = system.forces

    class RotorOnly:
        def evaluate(self, t, q, qd, states=None):
            return [*forces.rotor_moments(*forces.knuckle_poses(q, qd), V), 0.0, 0.0]

    system.forces = RotorOnly()
    for connector in system.connectors.values():      # the linkage is not part of this comparison
        system.mbs.SetObjectParameter(connector, "activeConnector", False)
    ours = exu.MainSolverExplicit()
    ours.InitializeSolver(system.mbs, settings)
    for y in _random_states(6, seed=7):
        sd = mbs.systemData
        sd.SetODE2Coordinates(list(y[0:3]) + [0.3, -1.2], configuration=CURRENT)
        sd.SetODE2Coordinates_t(list(y[3:6]) + [Omega, Omega], configuration=CURRENT)
        spinning.ComputeODE2RHS(mbs)
        f_spin = np.array(spinning.GetSystemResidual())[0:3]
        # joint control is zero in the spinning tree; remove the model's roll and kingpin spring-dampers
        system.set_state(y)
        ours.ComputeODE2RHS(system.mbs)
        f_ours = np.array(ours.GetSystemResidual())[0:3]
        f_ours -= -np.array([P.k3 * y[0] + P.c3 * y[3], P.c4 * y[4], P.c4 * y[5]])
        assert np.allclose(f_ours, f_spin, rtol=1e-12, atol=1e-10), (f_ours, f_spin)
        spinning.ComputeMassMatrix(mbs)
        M5 = np.array(spinning.GetSystemMassMatrix())
        ours.ComputeMassMatrix(system.mbs)
        assert np.allclose(np.array(ours.GetSystemMassMatrix())[0:3, 0:3], M5[0:3, 0:3], rtol=1e-13, atol=1e-13)


class _NoForces:
    def __init__(self, n):
        self.n = n

    def evaluate(self, t, q, qd, states=None):
        return [0.0] * self.n


def _linkage_matrices(fidelity, dims=DEFAULT_DIMENSIONS):
    """-dQ/dq and -dQ/dq' of the Exudyn system without the user forces and joint controls (connectors only)."""
    P = YANG2024
    system = MbsModel(fidelity=fidelity, dims=dims).system(TyrePressures.uniform(1.5 * BAR), constant_speed(0.0))
    m = system.layout.n_mech
    system.forces = _NoForces(m + 2)
    ev = MbsEvaluator(system)

    def Q(q, qd):
        system.set_state(np.concatenate([q, qd, [0.0, 0.0]]))
        ev.solver.ComputeODE2RHS(system.mbs)
        return np.array(ev.solver.GetSystemResidual())[:m]
    h = 1e-6
    K = np.column_stack([-(Q(h * np.eye(m)[j], np.zeros(m)) - Q(-h * np.eye(m)[j], np.zeros(m))) / (2 * h)
                         for j in range(m)])
    C = np.column_stack([-(Q(np.zeros(m), np.eye(m)[j]) - Q(np.zeros(m), -np.eye(m)[j])) / 2 for j in range(m)])
    return system.layout, K, C


def test_linkage_stiffness_about_kingpins_is_k1_k2():
    """The tie-rod and drag-link connectors (Exudyn spring-dampers between the arm ends) give exactly k1, c1 and
    k2, c2 about the kingpins, with kingpin inclination and Ackermann arms; with the rigid gear no roll steer."""
    P = YANG2024
    fidelity = Fidelity(frozenset({Assumption.RIGID_STEERING_GEAR, Assumption.RIGID_AXLE_MOUNTS,
                                   Assumption.ROLL_AXIS_AT_WHEEL_CENTRE}) | ISSUE_18)
    for fid in (fidelity, Fidelity.reduced()):
        layout, K, C = _linkage_matrices(fid)
        i = [layout.index(n) for n in ("theta1", "theta2")]
        K2, C2 = K[np.ix_(i, i)] - np.diag([0, 0]), C[np.ix_(i, i)] - np.diag([P.c4, P.c4])
        assert K2 == pytest.approx(np.array([[P.k1, -P.k1], [-P.k1, P.k1 + P.k2]]), rel=1e-7)
        assert C2 == pytest.approx(np.array([[P.c1, -P.c1], [-P.c1, P.c1 + P.c2]]), rel=1e-10)
        ip = layout.index("psi")
        assert abs(K[i[1], ip]) < 1e-6 * P.k2          # no roll steer


def test_steering_gear_in_series_and_roll_steer():
    """Full geometry: the drag link between the steering arm and the Pitman arm: about the left kingpin k2, about
    the gear shaft k2 (r_p / j)^2 plus the gear's own stiffness, and the axle's roll steers the left wheel through
    the inclined drag link: K[theta2, psi] = -k2 (y_arm sin(eps)) / j, y_arm the arm end's distance from the roll
    axis, j its lever about the kingpin (hand derivation, level kingpin terms to first order)."""
    P, d = YANG2024, DEFAULT_DIMENSIONS
    fidelity = Fidelity(frozenset({Assumption.NO_KINGPIN_INCLINATION, Assumption.RIGID_AXLE_MOUNTS,
                                   Assumption.ROLL_AXIS_AT_WHEEL_CENTRE, Assumption.PARALLEL_STEERING_ARMS}) | ISSUE_18)
    layout, K, C = _linkage_matrices(fidelity)
    it, ig, ip = layout.index("theta2"), layout.index("phi_gear"), layout.index("psi")
    eps, rp = d.drag_link_inclination, d.pitman_arm
    # drag-link length change per coordinate (n = (cos eps, 0, sin eps) from the arm end A to the Pitman ball):
    # the arm -r_d y turns about e = (-sin g, 0, cos g) with velocity r_d (cos g, 0, sin g): -r_d cos(g - eps);
    # the roll moves A by psi' y_arm z: -y_arm sin(eps); the gear moves the ball by -r_p phi' x: -r_p cos(eps)
    d_theta = -d.drag_link_arm * math.cos(P.gamma - eps)
    d_psi = -(0.5 * P.L - P.l - d.drag_link_arm) * math.sin(eps)
    d_phi = -rp * math.cos(eps)
    k = P.k2 / d_theta ** 2
    assert K[it, it] - P.k1 == pytest.approx(P.k2, rel=1e-7)
    assert K[ig, ig] == pytest.approx(1.0 / d.steering_gear_compliance + k * d_phi ** 2, rel=1e-7)
    assert K[it, ig] == pytest.approx(k * d_theta * d_phi, rel=1e-7)
    assert K[it, ip] == pytest.approx(k * d_theta * d_psi, rel=1e-6)
    assert C[ig, ig] == pytest.approx(d.steering_gear_damping + P.c2 / d_theta ** 2 * d_phi ** 2, rel=1e-9)


@pytest.mark.parametrize("name,fidelity", study_fidelities())
def test_straight_running_is_equilibrium_and_jacobian_affine_in_speed(name, fidelity):
    family = MbsFamily(MbsModel(effects=Effects.parse("all"), fidelity=fidelity))
    family.validate(1.5 * BAR)            # equilibrium at 1 m/s and the affine check at a third speed
    for kmh in (5.0, 120.0, 330.0):
        assert family.affine_residual(kmh * KMH, 1.5 * BAR) < 1e-9
        assert np.max(np.abs(family.rhs(np.zeros(family.n), kmh * KMH, 1.5 * BAR))) < 1e-9


def table_error(element, loads) -> float:
    """Largest relative interpolation error of a wheel's load table against direct evaluation."""
    pick = list(element.table.columns)
    worst = 0.0
    for load in loads:
        a = np.array(element.table.values(float(load)))[pick]
        b = np.array(element.table.direct(float(load)))[pick]
        worst = max(worst, float(np.max(np.abs(a - b) / np.abs(b))))
    return worst


def test_load_table_interpolation():
    forces = MbsModel(effects=Effects.parse("all"), fidelity=Fidelity.full()).forces(TyrePressures(1.5 * BAR, 2.2 * BAR),
                                                                                       constant_speed(10.0))
    loads = np.linspace(0.05, 2.9, 157) * YANG2024.Fz + 3.1
    near_lift_off = np.geomspace(1.5e-4, 0.05, 61) * YANG2024.Fz * 1.0007
    for element in forces.tyres:
        assert table_error(element, loads) < 1e-10
        assert table_error(element, near_lift_off) < 1e-10


def test_systems_share_a_load_table_only_where_its_formulas_read_the_same_entries():
    """A family along t0 (the section 3 model's trail, which no load-table formula reads) builds a system per
    value: they share one table.  A changed tyre entry (p_ky1) or pressure gets its own."""
    pressures = TyrePressures.uniform(1.5 * BAR)

    def table(params, p=pressures):
        return MbsModel(params, Effects(), Fidelity.full()).forces(p, constant_speed(10.0)).tyres[0].table
    base = table(YANG2024)
    assert table(YANG2024.replace(t0=0.25)) is base
    assert table(YANG2024.replace(p_ky1=YANG2024.p_ky1 * 1.001)) is not base
    assert table(YANG2024, TyrePressures.uniform(1.6 * BAR)) is not base
    shared = table(YANG2024.replace(t0=0.25))
    assert shared.direct(3000.0) == base.direct(3000.0)


def test_dimensions_are_checked():
    with pytest.raises(ParameterError, match="wheel_mass = -1 kg is outside its physical range"):
        AxleDimensions(wheel_mass=-1.0)
    with pytest.raises(ParameterError, match="unknown dimension"):
        DEFAULT_DIMENSIONS.replace(wheel_radius=0.3)
    with pytest.raises(ParameterError, match="roll inertia"):
        MbsModel(dims=DEFAULT_DIMENSIONS.replace(wheel_mass=200.0, wheel_diametral_inertia=3.0)).system(
            TyrePressures.uniform(2.5 * BAR), constant_speed(1.0))
    with pytest.raises(ParameterError, match="I1"):
        MbsModel(params=YANG2024.replace(I1=2.0), fidelity=Fidelity.full()).system(TyrePressures.uniform(2.5 * BAR), constant_speed(1.0))


def test_family_over_a_table_entry_and_bad_values():
    from bifurcation.equilibria.hopf import find_hopf_points
    by_param = MbsFamily(MbsModel(fidelity=Fidelity.full()), param="t0", pressures=TyrePressures.uniform(1.5 * BAR))
    direct = MbsFamily(MbsModel(params=YANG2024.replace(t0=0.25), fidelity=Fidelity.full()))
    a = find_hopf_points(by_param, 0.25, 0.0, 400 * KMH, lyapunov=False)
    b = find_hopf_points(direct, 1.5 * BAR, 0.0, 400 * KMH, lyapunov=False)
    assert [h.p for h in a] == pytest.approx([h.p for h in b], rel=1e-10)
    with pytest.raises(ParameterError, match="unknown parameter"):
        MbsFamily(param="tyre_colour")
    with pytest.raises(ParameterError, match="pressure must be positive"):
        find_hopf_points(MbsFamily(), -1.0 * BAR, 0.0, 100.0, lyapunov=False)
    with pytest.raises(ParameterError, match="t0 = -0.1 m is outside its physical range"):
        MbsFamily(param="t0").validate(-0.1)


def test_an_assembled_system_is_freed_when_dropped():
    """Exudyn keeps the tree's force user function in C++, out of the garbage collector's sight; a bound method of
    the system there made every system immortal (2.4 MB each; a full-geometry Hopf curve builds one per parameter
    value and grew to 24 GB).  Dropped, a system is freed, and it still evaluates while it is kept."""
    import gc
    import weakref

    from mbs_shimmy.evaluator import speed_is_time

    model = MbsModel(fidelity=Fidelity.full())
    system = model.system(TyrePressures.uniform(1.5 * BAR), speed_is_time)
    y = np.zeros(system.layout.n)
    y[system.layout.index("theta1")] = 0.01
    assert np.any(MbsEvaluator(system).rhs(y, 20.0) != 0.0)
    ref = weakref.ref(system)
    del system
    gc.collect()
    assert ref() is None
