"""The multibody model's parts: fidelity switches, geometry against Exudyn's own kinematics, inertia, the spinning
wheels, the linkage, the load table, straight running and the speed-affine Jacobian."""

import math

import exudyn as exu
import numpy as np
import pytest
from exudyn.itemInterface import MarkerKinematicTreeRigid, NodeGenericODE2, ObjectKinematicTree

from mbs_shimmy import DEFAULT_DIMENSIONS, Assumption, AxleDimensions, Fidelity, MbsFamily, MbsModel, assumptions_table
from mbs_shimmy.assumption_study import study_fidelities
from mbs_shimmy.geometry import SIDES, disc_contact, knuckle_frame, knuckle_pose
from mbs_shimmy.linearisation import ConstantSpeed, MbsEvaluator
from mbs_shimmy.system import TreeInertia
from reduced_model.model import Effects
from reduced_model.parameters import YANG2024, ParameterError

BAR, KMH = 1e5, 1 / 3.6
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
    assert [name for name, _ in study_fidelities()][-1] == "full"


def _random_states(n, seed=3):
    rng = np.random.default_rng(seed)
    y = rng.standard_normal((n, 8)) * np.array([0.1, 0.4, 0.4, 1.0, 3.0, 3.0, 0.05, 0.05])
    return y


def test_exact_kinematics_is_the_kinematic_tree():
    """Poses and velocities the tyre element uses = Exudyn's own kinematic-tree output (full geometry)."""
    model = MbsModel(fidelity=Fidelity.full())
    system = model.system(1.5 * BAR, ConstantSpeed(20.0))
    mbs = system.mbs
    g = system.forces.g_exact
    inertia = TreeInertia.build(model.params, model.dims, uncoupled=False)
    markers = []
    for i, side in enumerate(SIDES):
        T = inertia.joint_rotations[i]
        for r in (g.wheel_centre(side), g.tie_rod_arm_vector, (0.1, 0.2, -0.3)):
            m = mbs.AddMarker(MarkerKinematicTreeRigid(objectNumber=system.tree, linkNumber=i + 1,
                                                       localPosition=list(T.T @ np.array(r))))
            markers.append((i, side, r, m))
    mbs.Assemble()
    for y in _random_states(5):
        system.set_state(y)
        for i, side, r, m in markers:
            pose = knuckle_pose(g, side, math.cos(y[0]), math.sin(y[0]), y[1 + i])
            p = np.array(pose.point(r))
            omega = y[3] * np.array([1.0, 0, 0]) + y[4 + i] * np.array(pose.kingpin_axis)
            v = np.cross([y[3], 0, 0], p - np.array(g.origin)) + y[4 + i] * np.cross(
                pose.kingpin_axis, p - np.array(pose.kingpin_point))
            assert np.allclose(p, mbs.GetMarkerOutput(m, exu.OutputVariableType.Position, CURRENT), atol=1e-14)
            assert np.allclose(v, mbs.GetMarkerOutput(m, exu.OutputVariableType.Velocity, CURRENT), atol=1e-13)
            rot = np.array(mbs.GetMarkerOutput(m, exu.OutputVariableType.RotationMatrix, CURRENT)).reshape(3, 3)
            assert np.allclose(np.array(pose.rotation) @ inertia.joint_rotations[i], rot, atol=1e-14)
            assert np.allclose(omega, mbs.GetMarkerOutput(m, exu.OutputVariableType.AngularVelocity, CURRENT),
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
    for fidelity in (Fidelity.reduced(), Fidelity.full()):
        ev = MbsEvaluator(MbsModel(fidelity=fidelity).system(1.5 * BAR, ConstantSpeed(0.0)))
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


def test_spinning_wheel_equals_rotor_moment():
    """A kinematic tree with the wheels as spinning links (spin V/R) gives the same forces on (psi, theta1,
    theta2) as the model's non-spinning wheels plus the rotor moment -I2 Omega (omega x s), at any state."""
    P, d = YANG2024, DEFAULT_DIMENSIONS
    V = 25.0
    Omega = V / P.R
    model = MbsModel(fidelity=Fidelity.full())
    inertia = TreeInertia.build(P, d, uncoupled=False)
    g = model.forces(1.5 * BAR, ConstantSpeed(V)).g_exact
    # spinning model: knuckle links carry the knuckle only; each wheel is a link spinning about its axis y
    e_knuckle = [inertia.joint_rotations[i] for i in range(2)]
    Jk_e = d.knuckle_kingpin_inertia(P)
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
        jointTransformations=exu.Matrix3DList([np.eye(3), e_knuckle[0], e_knuckle[1], np.eye(3), np.eye(3)]),
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
    forces = model.forces(1.5 * BAR, ConstantSpeed(V))

    class RotorOnly:
        def evaluate(self, t, q, qd, alpha, states=None):
            c, s = math.cos(q[0]), math.sin(q[0])
            f1 = knuckle_frame(g, -1.0, c, s, q[1])
            f2 = knuckle_frame(g, 1.0, c, s, q[2])
            return (*forces.rotor_moments(f1, f2, qd[0], qd[1], qd[2], V), 0.0, 0.0)

    system = model.system(1.5 * BAR, ConstantSpeed(V))
    system.forces = RotorOnly()
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


def test_linkage_stiffness_about_kingpins_is_k1_k2():
    """Full geometry: the tie-rod and drag-link spring-dampers give exactly k1, c1 and k2, c2 about the kingpins."""
    P = YANG2024
    forces = MbsModel(fidelity=Fidelity.full()).forces(1.5 * BAR, ConstantSpeed(0.0))
    g = forces.g_exact
    h = 1e-6

    def Q(th1, th2, thd1, thd2):
        f1 = knuckle_frame(g, -1.0, 1.0, 0.0, th1)
        f2 = knuckle_frame(g, 1.0, 1.0, 0.0, th2)
        return np.array(forces._linkage_exact(0.0, 0.0, 0.0, 0.0, thd1, thd2, f1, f2))

    K1 = -(Q(h, 0, 0, 0) - Q(-h, 0, 0, 0)) / (2 * h)
    K2 = -(Q(0, h, 0, 0) - Q(0, -h, 0, 0)) / (2 * h)
    C1 = -(Q(0, 0, 1.0, 0) - Q(0, 0, -1.0, 0)) / 2
    C2 = -(Q(0, 0, 0, 1.0) - Q(0, 0, 0, -1.0)) / 2
    assert K1[1:] == pytest.approx([P.k1, -P.k1], rel=1e-8)
    assert K2[1:] == pytest.approx([-P.k1, P.k1 + P.k2], rel=1e-8)
    assert C1[1:] == pytest.approx([P.c1, -P.c1], rel=1e-12)
    assert C2[1:] == pytest.approx([-P.c1, P.c1 + P.c2], rel=1e-12)


@pytest.mark.parametrize("name,fidelity", study_fidelities())
def test_straight_running_is_equilibrium_and_jacobian_affine_in_speed(name, fidelity):
    family = MbsFamily(MbsModel(effects=Effects.parse("all"), fidelity=fidelity))
    family.validate(1.5 * BAR)            # equilibrium at 1 m/s and the affine check at a third speed
    for kmh in (5.0, 120.0, 330.0):
        assert family.affine_residual(kmh * KMH, 1.5 * BAR) < 1e-9
        assert np.max(np.abs(family.rhs(np.zeros(8), kmh * KMH, 1.5 * BAR))) < 1e-9


def table_error(element, loads) -> float:
    """Largest relative interpolation error of a wheel's load table against direct evaluation."""
    pick = list(element.table._pick)
    worst = 0.0
    for load in loads:
        a = np.array(element.table.values(float(load)))[pick]
        b = np.array(element.table.direct(float(load)))[pick]
        worst = max(worst, float(np.max(np.abs(a - b) / np.abs(b))))
    return worst


def test_load_table_interpolation():
    forces = MbsModel(effects=Effects.parse("all"), fidelity=Fidelity.full()).forces((1.5 * BAR, 2.2 * BAR),
                                                                                       ConstantSpeed(10.0))
    loads = np.linspace(0.05, 2.9, 157) * YANG2024.Fz + 3.1
    for element in forces.tyres:
        assert table_error(element, loads) < 1e-10


def test_dimensions_are_checked():
    with pytest.raises(ParameterError, match="wheel_mass = -1 kg is outside its physical range"):
        AxleDimensions(wheel_mass=-1.0)
    with pytest.raises(ParameterError, match="unknown dimension"):
        DEFAULT_DIMENSIONS.replace(wheel_radius=0.3)
    with pytest.raises(ParameterError, match="roll inertia"):
        MbsModel(dims=DEFAULT_DIMENSIONS.replace(wheel_mass=200.0, wheel_diametral_inertia=3.0)).system(
            2.5 * BAR, ConstantSpeed(1.0))
    with pytest.raises(ParameterError, match="I1"):
        MbsModel(params=YANG2024.replace(I1=2.0), fidelity=Fidelity.full()).system(2.5 * BAR, ConstantSpeed(1.0))


def test_family_over_a_table_entry_and_bad_values():
    from reduced_model.hopf import hopf_points
    by_param = MbsFamily(MbsModel(fidelity=Fidelity.full()), param="t0", pressure=1.5 * BAR)
    direct = MbsFamily(MbsModel(params=YANG2024.replace(t0=0.25), fidelity=Fidelity.full()))
    a = hopf_points(by_param, 0.25, 0.0, 400 * KMH, lyapunov=False)
    b = hopf_points(direct, 1.5 * BAR, 0.0, 400 * KMH, lyapunov=False)
    assert [h.speed for h in a] == pytest.approx([h.speed for h in b], rel=1e-10)
    with pytest.raises(ParameterError, match="unknown parameter"):
        MbsFamily(param="tyre_colour")
    with pytest.raises(ParameterError, match="pressure must be positive"):
        hopf_points(MbsFamily(), -1.0 * BAR, 0.0, 100.0, lyapunov=False)
    with pytest.raises(ParameterError, match="t0 = -0.1 m is outside its physical range"):
        MbsFamily(param="t0").validate(-0.1)
