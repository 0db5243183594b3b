"""The Exudyn model of the axle: a kinematic tree with two first-order tyre states, and the Exudyn connectors of
the steering linkage.

Why a kinematic tree: minimal coordinates need no constraints, so Exudyn's explicit Runge-Kutta solvers apply and
the mass matrix is exact (with Euler-parameter bodies and joints the built-in
linearisation is wrong for spinning wheels, and constrained models need implicit solvers).

Links, in the tree's coordinate order (bracketed ones only when their element is on):

* [``y_axle``: the axle's lateral travel on its mounts, prismatic along y on the frame; the leaf springs' lateral
  stiffness and damping are the joint's P/D control; the link itself is massless, its children move with it];
* [``z_axle``: the axle's bounce on its mounts, prismatic along z; the leaf springs' vertical stiffness and damping
  are the joint's P/D control; massless like the lateral link];
* ``psi``: the axle's roll, revolute about x through O = (0, y, R + h + z) (h: roll axis above the wheel centres;
  with roll steer the joint frame is turned so that the axis slopes in side view by atan(axle_roll_steer)); roll
  spring-damper k3, c3 as joint P/D control.  Its own roll inertia is I3 less the knuckles' and wheels' share
  about the wheel-centre line, and its centre of mass is on that line, so the assembly has Table 1's I3 about the
  wheel-centre line and I3 + m h^2 about a raised roll axis;
* ``theta1``, ``theta2``: the knuckles with their wheels (non-spinning: the spin is a rotor moment,
  :mod:`mbs_shimmy.forces`), revolute about the kingpin (caster and kingpin inclination in the joint transform),
  through K = (0, -+(L/2 - l), 0) relative to the wheel-centre line; damper c4 as joint D control.  Bodies: a
  knuckle (centre of mass on the kingpin, inertia about the kingpin chosen so that the assembly has I1 about it)
  and a wheel (mass and diametral inertia from :class:`AxleDimensions`, I2 about its axis, centre l outboard of K);
* [``phi_gear``: the steering gear's output shaft, revolute about y on the frame, with the Pitman arm; the gear's
  torsional stiffness and damping to the frame are its joint P/D control, its inertia the link's];
* ``p1``, ``p2``: the two slip angles, carried as the velocities of auxiliary coordinates: prismatic joints on the
  ground with unit mass, coupled to nothing, so p_i'' = g_i is the tyre's relaxation equation alpha_i' = g_i for
  alpha_i = p_i' (one user function per stage that receives every state, instead of an ``ObjectGenericODE1``
  right-hand side plus state reads: about a fifth of the run time).

With the ``uncoupled_inertia`` assumption the tree carrying the inertia has its kingpins perpendicular to the roll
axis and each knuckle-wheel assembly lumped on its kingpin axis: its mass matrix is diag(I1, I1, I3, ...) in every
configuration, as on the left of (2.1)-(2.3).  The caster-tilted geometry the forces need is then a second, massless
tree on the same node (:attr:`MbsSystem.geometry_tree`), which carries the markers.

Poses: :class:`~mbs_shimmy.forces.AxleForces` reads the kingpin point, velocity, rotation and angular velocity of
each knuckle from ``MarkerKinematicTreeRigid`` markers at the stage's state (Exudyn's own forward kinematics: no
second copy in Python).  Linkage: with the exact geometry the tie-rod and drag link are
``ObjectConnectorSpringDamper`` between markers at the arm ends (the drag link to the Pitman-arm marker on the gear
link, or to a ground marker with the rigid gear), their axial stiffness and damping scaled so that about the
kingpins they are exactly k1, c1 and k2, c2; with the first-order kinematics (``small_angles``) they are
``ObjectConnectorCoordinateSpringDamper`` on the steer angles, k1 (theta2 - theta1) and k2 theta2 exactly as in
(2.1)-(2.2).  (``CreateKinematicTree`` drops a force user function silently, so the tree is built with
``ObjectKinematicTree`` and the function set afterwards with ``SetObjectParameter``.)
"""

from __future__ import annotations

import math
import weakref
from dataclasses import dataclass, field

from mbs_shimmy import engine  # noqa: F401  (before exudyn: chooses Exudyn's compiled module)

# isort: split
import exudyn as exu
import numpy as np
from exudyn.itemInterface import (
    MarkerBodyPosition,
    MarkerKinematicTreeRigid,
    MarkerNodeCoordinate,
    NodeGenericODE2,
    NodePointGround,
    ObjectConnectorCoordinateSpringDamper,
    ObjectConnectorSpringDamper,
    ObjectGround,
    ObjectKinematicTree,
    SensorNode,
)

from axles.dimensions import AxleDimensions
from mbs_shimmy.fidelity import Assumption, Fidelity
from mbs_shimmy.forces import AxleForces
from mbs_shimmy.geometry import AxleGeometry, cross, dot
from mbs_shimmy.layout import Layout
from reduced_model.model import Effects
from axles.parameters import ParameterError, ShimmyParameters
from bifurcation.messages import Message, Quantity

CURRENT = exu.ConfigurationType.Current
REFERENCE = exu.ConfigurationType.Reference
# mass of the geometry tree's links: Exudyn's tree gives NaN for a subtree of zero mass; 1e-20 kg changes the
# mass matrix by 1e-20 relative, far below rounding
MASSLESS = 1e-20




def _shift(m: float, r: np.ndarray) -> np.ndarray:
    """Parallel-axis term: inertia of a point mass m at r about the origin."""
    return m * (np.dot(r, r) * np.eye(3) - np.outer(r, r))


def _rows(m) -> np.ndarray:
    return np.array(m, dtype=float)


@dataclass(frozen=True)
class TreeInertia:
    """Joint transforms, masses, centres of mass and inertias of the two knuckle links and the axle (SI)."""

    joint_rotations: tuple[np.ndarray, np.ndarray]   # kingpin joint frame -> axle frame
    masses: tuple[float, float, float]               # axle, knuckle 1, knuckle 2
    coms: tuple[np.ndarray, np.ndarray, np.ndarray]  # in each link's joint frame
    inertias: tuple[np.ndarray, np.ndarray, np.ndarray]  # about the centre of mass, joint frame
    gear_extra: float = 0.0          # the drag link's half on the Pitman-arm ball, about the gear shaft (kg m^2)

    @classmethod
    def build(cls, params: ShimmyParameters, dims: AxleDimensions, uncoupled: bool,
              geometry: AxleGeometry | None = None, roll_height: float = 0.0,
              links_mass: tuple[float, float] = (0.0, 0.0)) -> "TreeInertia":
        """``geometry`` gives the kingpin axes (default: caster only); the axle's centre of mass lies
        ``roll_height`` below the roll joint (the roll axis above the wheel centres).

        ``links_mass`` = (tie rod, drag link) masses (assumption ``massless_links`` off): each rod is two point
        masses, half at each ball joint, carried by the link the joint sits on (the steering arms' ends on the
        knuckles, the Pitman ball on the gear; with a rigid gear that half is on the frame).  That is exact for the
        rods' translation; their inertia about their own centres is m L^2 / 4 instead of m L^2 / 12 (a kinematic
        tree cannot carry a body between two of its links without a closing constraint).  The whole axle keeps
        Table 1's I3 about the wheel-centre line (the axle's own share is what is left), I1 grows by the arm ends'
        m r^2."""
        dims.check(params)
        P = params
        g = geometry or AxleGeometry.build(P, dims, exact=True)
        m0 = dims.knuckle_mass + dims.wheel_mass
        links = []
        masses = []
        roll_share = 0.0
        for side in (-1.0, 1.0):
            m = m0
            K = np.array([0.0, side * (0.5 * P.L - P.l), 0.0])
            if uncoupled:
                T = np.eye(3)
                transverse = dims.wheel_diametral_inertia + dims.knuckle_transverse_inertia
                J = np.diag([transverse, transverse, P.I1])   # symmetric about its (vertical) kingpin
                com = np.zeros(3)
            else:
                T = _rows(g.joint_rotation(side))              # maps the joint z-axis onto the kingpin axis
                e = T[:, 2]
                c = np.array([0.0, side * P.l, 0.0])
                Jw = np.diag([dims.wheel_diametral_inertia, P.I2, dims.wheel_diametral_inertia])
                Jk_e = P.I1 - e @ (Jw + _shift(dims.wheel_mass, c)) @ e   # knuckle's share of I1 about the kingpin
                if not Jk_e > 0.0:
                    raise ParameterError(Message.of(Quantity("I1", P.I1, 6, "kg m^2"), " is smaller than the wheel's own "
                                                    f"inertia about the kingpin ({P.I1 - Jk_e:g} kg m^2): choose a "
                                                    "lighter wheel"))
                Jk = dims.knuckle_transverse_inertia * (np.eye(3) - np.outer(e, e)) + Jk_e * np.outer(e, e)
                com = dims.wheel_mass * c / m
                J = Jk + _shift(dims.knuckle_mass, -com) + Jw + _shift(dims.wheel_mass, c - com)
                ends = [(0.5 * links_mass[0], np.array(g.tie_rod_arm_vector_of(side)))]
                if side > 0.0:
                    ends.append((0.5 * links_mass[1], np.array(g.drag_link_arm_vector)))
                for me, a in ends:           # a ball joint's point mass at the arm end a (relative to K)
                    if me > 0.0:
                        moved = (m * com + me * a) / (m + me)
                        J = J + _shift(m, com - moved) + _shift(me, a - moved)
                        m, com = m + me, moved
            roll_share += (J + _shift(m, K + com))[0, 0]
            links.append((T, T.T @ com, T.T @ J @ T))
            masses.append(m)
        axle_roll = P.I3 - roll_share
        if not axle_roll > 0.0:
            raise ParameterError(Message.of(Quantity("I3", P.I3, 6, "kg m^2"), " is less than the wheels' and "
                                            f"knuckles' share of the roll inertia ({roll_share:.4g} kg m^2): choose "
                                            "lighter wheels or knuckles"))
        axle = np.diag([axle_roll, axle_roll, axle_roll])  # only the roll component is ever used
        gear_extra = 0.5 * links_mass[1] * g.pitman_arm ** 2      # the ball at the Pitman arm's end
        return cls((links[0][0], links[1][0]), (dims.axle_mass, masses[0], masses[1]),
                   (np.array([0.0, 0.0, -roll_height]), links[0][1], links[1][1]), (axle, links[0][2], links[1][2]),
                   gear_extra)


@dataclass
class Markers:
    """Marker numbers on the geometry tree: the knuckles at their kingpin points, the linkage ends."""

    knuckles: tuple[int, int]
    tie_rod: tuple[int, int]
    drag_link: tuple[int, int]        # (steering-arm end, gear end)
    axle: int


@dataclass
class MbsSystem:
    """One assembled Exudyn system of the axle and the forces it calls; see the module docstring."""

    container: exu.SystemContainer
    mbs: exu.MainSystem
    tree: int
    tree_node: int
    forces: AxleForces
    layout: Layout
    geometry_tree: int = -1
    markers: Markers | None = None
    connectors: dict = field(default_factory=dict)
    sensors: dict = field(default_factory=dict)
    calls: int = 0
    error: tuple[float, BaseException] | None = None   # (time, exception) of the first failed evaluation

    def _tree_force(self, mbs, t, itemNumber, q, q_t):
        """The tree's force user function: generalized forces on the tree's coordinates, then alpha1', alpha2'."""
        self.calls += 1
        try:
            return self.forces.evaluate(t, q, q_t)
        except Exception as exc:   # Exudyn reports only that a user function failed: keep the reason
            if self.error is None:
                self.error = (t, exc)
            raise

    def set_state(self, y: np.ndarray, configuration=CURRENT, time: float | None = None) -> None:
        """Write the MBS state y = (q, q', alpha1, alpha2) (see :class:`Layout`) into a configuration, and the
        time ``time`` into the current one (what the force user function receives as t)."""
        y = np.asarray(y, dtype=float)
        m = self.layout.n_mech
        sd = self.mbs.systemData
        if time is not None:
            sd.SetTime(float(time))
        sd.SetODE2Coordinates(list(y[0:m]) + [0.0, 0.0], configuration=configuration)
        sd.SetODE2Coordinates_t(list(y[m:2 * m]) + [y[2 * m], y[2 * m + 1]], configuration=configuration)


def _tree_object(node: int, layout: Layout, g: AxleGeometry, inertia: TreeInertia, dims: AxleDimensions,
                 params: ShimmyParameters, massless: bool, control: bool) -> ObjectKinematicTree:
    """One kinematic tree on the shared node (module docstring); ``massless``: the geometry-only tree."""
    J = exu.JointType
    none = np.zeros((3, 3))
    types, parents, rotations, offsets, inertias, coms, masses, P_, D_ = [], [], [], [], [], [], [], [], []

    def link(joint, parent, rotation, offset, mass, com, jcom, p, d):
        types.append(joint)
        parents.append(parent)
        rotations.append(np.asarray(rotation, dtype=float))
        offsets.append([float(v) for v in offset])
        masses.append(MASSLESS if massless else mass)
        coms.append([0.0, 0.0, 0.0] if massless else [float(v) for v in com])
        inertias.append(none if massless else jcom)
        P_.append(p if control else 0.0)
        D_.append(d if control else 0.0)

    roll_parent = -1
    if layout.lateral:
        link(J.PrismaticY, -1, np.eye(3), (0.0, 0.0, 0.0), 0.0, (0.0, 0.0, 0.0), none,
             1.0 / dims.axle_mount_lateral_compliance, dims.axle_mount_lateral_damping)
        roll_parent = len(types) - 1
    if layout.vertical:
        # bounce on the leaf springs' vertical stiffness and damping at the seats (massless link: the axle, knuckles
        # and wheels hanging on it are its mass); the static load's preload is in the alignment
        link(J.PrismaticZ, roll_parent, np.eye(3), (0.0, 0.0, 0.0), 0.0, (0.0, 0.0, 0.0), none,
             1.0 / dims.axle_mount_vertical_compliance, dims.axle_mount_vertical_damping)
        roll_parent = len(types) - 1
    iroll = len(types)
    # roll about the roll axis u (sloped by the roll steer): the roll link's frame is turned so that its x-axis is u,
    # and what hangs on it (the axle's centre of mass, the kingpins) is given in that frame
    Rr = _rows(g.roll_joint_rotation)
    link(J.RevoluteX, roll_parent, Rr, g.origin, inertia.masses[0], Rr.T @ inertia.coms[0],
         Rr.T @ inertia.inertias[0] @ Rr, params.k3, params.c3)
    for i, side in enumerate((-1.0, 1.0)):
        K = g.kingpin_point(side)
        link(J.RevoluteZ, iroll, Rr.T @ inertia.joint_rotations[i], Rr.T @ np.array((K[0], K[1], K[2] - g.roll_height)),
             inertia.masses[1 + i], inertia.coms[1 + i], inertia.inertias[1 + i], 0.0, params.c4)
    if layout.gear:
        link(J.RevoluteY, -1, np.eye(3), g.gear_shaft_point(), 1.0, (0.0, 0.0, 0.0),
             np.diag([1.0, dims.steering_gear_inertia + inertia.gear_extra, 1.0]), 1.0 / dims.steering_gear_compliance,
             dims.steering_gear_damping)
    for _ in range(2):
        link(J.PrismaticX, -1, np.eye(3), (0.0, 0.0, 0.0), 1.0, (0.0, 0.0, 0.0), none, 0.0, 0.0)
    n = len(types)
    return ObjectKinematicTree(
        nodeNumber=node, jointTypes=types, linkParents=parents,
        jointTransformations=exu.Matrix3DList(rotations), jointOffsets=exu.Vector3DList(offsets),
        linkInertiasCOM=exu.Matrix3DList(inertias), linkCOMs=exu.Vector3DList(coms), linkMasses=masses,
        jointPControlVector=P_, jointDControlVector=D_, jointPositionOffsetVector=[0.0] * n,
        jointVelocityOffsetVector=[0.0] * n,
        visualization={"show": False, "showLinks": False, "showJoints": False, "color": [-1.0] * 4,
                       "graphicsDataList": []})


def _lever(e: tuple, arm: tuple, direction: tuple) -> float:
    """d(length along ``direction``)/d(rotation about e) of an arm end: direction . (e x arm)."""
    return dot(direction, cross(e, arm))


def _weak_user_function(system: MbsSystem):
    """The tree's force user function as Exudyn keeps it: a closure over a weak reference to ``system``.  Exudyn
    holds the function in C++, where Python's garbage collector cannot see it; a bound method there closed a cycle
    (system -> container -> C++ system -> method -> system) that was never freed: 2.4 MB per system, and a Hopf
    curve of the full geometry builds a system per parameter value (5 GB in 60 s at 0.05-0.2 bar, 2026-12-07)."""
    ref = weakref.ref(system)

    def force(mbs, t, itemNumber, q, q_t):
        owner = ref()
        if owner is None:
            raise RuntimeError("an Exudyn system was evaluated after its MbsSystem was freed: keep the MbsSystem")
        return owner._tree_force(mbs, t, itemNumber, q, q_t)
    return force


def build_system(params: ShimmyParameters, effects: Effects, fidelity: Fidelity, dims: AxleDimensions,
                 forces: AxleForces, y0: np.ndarray | None = None, output_interval: float | None = None,
                 drawing: bool = False) -> MbsSystem:
    """Assemble the Exudyn system; ``y0`` is the initial MBS state (q, q', alpha1, alpha2) in :class:`Layout` order.

    With ``output_interval`` the tree's coordinates and velocities are recorded by sensors (in memory);
    ``drawing`` adds the markers (and the geometry tree) also where the forces do not need them, for poses.
    """
    P = params
    layout = forces.layout
    g = forces.g_exact
    uncoupled = Assumption.UNCOUPLED_INERTIA in fidelity
    m = layout.n_mech
    y0 = np.zeros(layout.n) if y0 is None else np.asarray(y0, dtype=float)
    container = exu.SystemContainer()
    mbs = container.AddSystem()
    node = mbs.AddNode(NodeGenericODE2(referenceCoordinates=[0.0] * (m + 2),
                                       initialCoordinates=list(y0[0:m]) + [0.0, 0.0],
                                       initialCoordinates_t=list(y0[m:2 * m]) + [y0[2 * m], y0[2 * m + 1]],
                                       numberOfODE2Coordinates=m + 2))
    links_mass = ((0.0, 0.0) if Assumption.MASSLESS_LINKS in fidelity
                  else (dims.tie_rod_mass, dims.drag_link_mass))
    coupled = TreeInertia.build(P, dims, False, g, g.roll_height, links_mass)
    if uncoupled:
        lumped = TreeInertia.build(P, dims, True, g, 0.0)
        flat = AxleGeometry.build(P, dims, exact=True)     # roll axis at the wheel centres: no m h^2, no coupling
        tree = mbs.AddObject(_tree_object(node, layout, flat, lumped, dims, P, massless=False, control=True))
    else:
        tree = mbs.AddObject(_tree_object(node, layout, g, coupled, dims, P, massless=False, control=True))
    geometry_tree = tree
    need_geometry = forces.need_exact or not forces.linear or drawing
    if uncoupled and need_geometry:
        geometry_tree = mbs.AddObject(_tree_object(node, layout, g, coupled, dims, P, massless=True, control=False))
    system = MbsSystem(container, mbs, tree, node, forces, layout, geometry_tree)
    mbs.SetObjectParameter(tree, "forceUserFunction", _weak_user_function(system))
    i = layout.index
    if need_geometry:
        T = coupled.joint_rotations
        ik = (i("theta1"), i("theta2"))

        def marker(link: int, r) -> int:
            return mbs.AddMarker(MarkerKinematicTreeRigid(objectNumber=geometry_tree, linkNumber=link,
                                                          localPosition=[float(v) for v in r]))
        knuckles = (marker(ik[0], (0.0, 0.0, 0.0)), marker(ik[1], (0.0, 0.0, 0.0)))
        tie = tuple(marker(ik[k], T[k].T @ np.array(g.tie_rod_arm_vector_of(side)))
                    for k, side in enumerate((-1.0, 1.0)))
        drag_arm = marker(ik[1], T[1].T @ np.array(g.drag_link_arm_vector))
        if layout.gear:
            drag_end = marker(i("phi_gear"), (0.0, 0.0, -g.pitman_arm))
        else:
            ground = mbs.AddObject(ObjectGround())
            drag_end = mbs.AddMarker(MarkerBodyPosition(bodyNumber=ground,
                                                        localPosition=list(g.drag_link_frame_point())))
        system.markers = Markers(knuckles, tie, (drag_arm, drag_end), marker(i("psi"), (0.0, 0.0, 0.0)))
    if forces.linear:
        # the paper's linkage: k1 (theta2 - theta1), c1 (...) and k2 theta2, c2 theta2' on the coordinates
        ground_node = mbs.AddNode(NodePointGround())
        g_coord = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=ground_node, coordinate=0))
        c1 = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=node, coordinate=i("theta1")))
        c2 = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=node, coordinate=i("theta2")))
        system.connectors["tie_rod"] = mbs.AddObject(ObjectConnectorCoordinateSpringDamper(
            markerNumbers=[c1, c2], stiffness=P.k1, damping=P.c1))
        system.connectors["drag_link"] = mbs.AddObject(ObjectConnectorCoordinateSpringDamper(
            markerNumbers=[g_coord, c2], stiffness=P.k2, damping=P.c2))
    else:
        # geometric tie-rod and drag link; their straight-running levers about the kingpins scale the axial
        # stiffness and damping to k1, c1 and k2, c2
        e1, e2 = g.kingpin_axis_of(-1.0), g.kingpin_axis_of(1.0)
        a1, a2 = g.tie_rod_arm_vector_of(-1.0), g.tie_rod_arm_vector_of(1.0)
        p1, p2 = g.absolute(-1.0, a1), g.absolute(1.0, a2)
        tie_len = math.dist(p1, p2)
        n = tuple((b - a) / tie_len for a, b in zip(p1, p2))
        j_tr = _lever(e2, a2, n)       # = -n.(e1 x a1) by symmetry: length change per (theta2 - theta1)
        ad = g.drag_link_arm_vector
        pa, pd = g.absolute(1.0, ad), g.drag_link_frame_point()
        drag_len = math.dist(pa, pd)
        nd = tuple((b - a) / drag_len for a, b in zip(pa, pd))
        j_dl = _lever(e2, ad, nd)
        mk = system.markers
        system.connectors["tie_rod"] = mbs.AddObject(ObjectConnectorSpringDamper(
            markerNumbers=list(mk.tie_rod), referenceLength=tie_len, stiffness=P.k1 / j_tr ** 2,
            damping=P.c1 / j_tr ** 2))
        system.connectors["drag_link"] = mbs.AddObject(ObjectConnectorSpringDamper(
            markerNumbers=list(mk.drag_link), referenceLength=drag_len, stiffness=P.k2 / j_dl ** 2,
            damping=P.c2 / j_dl ** 2))
    if output_interval is not None:
        for name, var in (("q", exu.OutputVariableType.Coordinates),
                          ("q_t", exu.OutputVariableType.Coordinates_t)):
            system.sensors[name] = mbs.AddSensor(SensorNode(nodeNumber=node, outputVariableType=var,
                                                            storeInternal=True, writeToFile=False))
    mbs.Assemble()
    forces.attach(system)
    return system
