"""The Exudyn model of the axle: a kinematic tree (roll, two kingpins) with two first-order tyre states.

Why a kinematic tree: minimal coordinates (psi, theta1, theta2) need no constraints, so Exudyn's explicit
Runge-Kutta solvers apply and the mass matrix is exact (``shared/notes/exudyn.md``: with Euler-parameter bodies
and joints the built-in linearisation is wrong for spinning wheels, and constrained models need implicit solvers).

* Link 0, the axle: revolute about x through O = (0, 0, R); its roll spring-damper k3, c3 to the frame is the
  tree's joint P/D control.  Its own roll inertia is I3 less the knuckles' and wheels' share, so that the roll
  inertia of the assembly at straight running is Table 1's I3.
* Links 1, 2, the knuckles with their wheels (non-spinning: the spin is a rotor moment, :mod:`mbs_shimmy.forces`):
  revolute about the kingpin, tilted rearward by gamma, through K = (0, -+(L/2 - l), 0) on the axle; damper c4 as
  joint D control.  Bodies: a knuckle (centre of mass on the kingpin, inertia about the kingpin chosen so that the
  assembly has I1 about it) and a wheel (mass and diametral inertia from :class:`AxleDimensions`, I2 about its
  axis, centre l outboard of K).
* With the ``uncoupled_inertia`` assumption the tree carrying the inertia has its kingpin joints perpendicular to
  the roll axis and each knuckle-wheel assembly lumped on its kingpin axis, symmetric about it: its mass matrix is
  diag(I1, I1, I3) in every configuration, as on the left of (2.1)-(2.3).  The forces still act through the
  caster-tilted geometry (:mod:`mbs_shimmy.forces`), which enters only through the generalized forces.
* The two slip angles are first-order states.  Each is carried as the velocity of an auxiliary coordinate p_i,
  links 3 and 4 of the tree: prismatic joints on the ground with unit mass, coupled to nothing, so their
  equation of motion p_i'' = g_i is the tyre's relaxation equation alpha_i' = g_i for alpha_i = p_i'
  (p_i, the integral of the slip angle, is never used).  Exudyn's explicit Runge-Kutta stages integrate
  (p, p') exactly as they would a ``NodeGenericODE1`` state; the difference is speed: one user function per
  stage that receives every state, instead of an ``ObjectGenericODE1`` right-hand side plus three state reads
  (about a fifth of the run time of the full model).

All forces and slip rates come from one force user function (:class:`~mbs_shimmy.forces.AxleForces`).
(``CreateKinematicTree`` drops a force user function silently, so the object is built with ``ObjectKinematicTree``
and the function set afterwards with ``SetObjectParameter``.)
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import exudyn as exu
import numpy as np
from exudyn.itemInterface import NodeGenericODE2, ObjectKinematicTree

from reduced_model.model import Effects
from reduced_model.parameters import ParameterError, ShimmyParameters

from .dimensions import AxleDimensions
from .fidelity import Assumption, Fidelity
from .forces import AxleForces

# Tree coordinate order (p1, p2: the auxiliary coordinates whose velocities are the slip angles) and the map of
# the MBS state to the reduced model's state order (theta1, theta1_dot, theta2, theta2_dot, psi, psi_dot, alpha1,
# alpha2).
TREE_COORDINATES = ("psi", "theta1", "theta2", "p1", "p2")
# first-order MBS state y = (psi, theta1, theta2, psi', theta1', theta2', alpha1, alpha2)
Y_TO_REDUCED = np.array([1, 4, 2, 5, 0, 3, 6, 7])   # reduced[k] = y[Y_TO_REDUCED[k]]
REDUCED_TO_Y = np.argsort(Y_TO_REDUCED)              # y[j] = reduced[REDUCED_TO_Y[j]]
CURRENT = exu.ConfigurationType.Current


def to_reduced(y: np.ndarray) -> np.ndarray:
    return np.asarray(y)[..., Y_TO_REDUCED]


def from_reduced(x: np.ndarray) -> np.ndarray:
    return np.asarray(x)[..., REDUCED_TO_Y]


def _ry(angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def _shift(m: float, r: np.ndarray) -> np.ndarray:
    """Parallel-axis term: inertia of a point mass m at r about the origin."""
    return m * (np.dot(r, r) * np.eye(3) - np.outer(r, r))


@dataclass(frozen=True)
class TreeInertia:
    """Link masses, centres of mass and inertias of the kinematic tree (axle frame, SI)."""

    joint_rotations: tuple[np.ndarray, np.ndarray]   # kingpin joint frame -> axle frame
    masses: tuple[float, float, float]
    coms: tuple[np.ndarray, np.ndarray, np.ndarray]  # in each link's joint frame
    inertias: tuple[np.ndarray, np.ndarray, np.ndarray]  # about the centre of mass, joint frame

    @classmethod
    def build(cls, params: ShimmyParameters, dims: AxleDimensions, uncoupled: bool) -> "TreeInertia":
        dims.check(params)
        P = params
        m = dims.knuckle_mass + dims.wheel_mass
        links = []
        roll_share = 0.0
        for side in (-1.0, 1.0):
            K = np.array([0.0, side * (0.5 * P.L - P.l), 0.0])
            if uncoupled:
                T = np.eye(3)
                transverse = dims.wheel_diametral_inertia + dims.knuckle_transverse_inertia
                J = np.diag([transverse, transverse, P.I1])   # symmetric about its (vertical) kingpin
                com = np.zeros(3)
            else:
                T = _ry(-P.gamma)                              # maps the joint z-axis onto the kingpin axis
                e = T[:, 2]
                Jk_e = dims.knuckle_kingpin_inertia(P)
                Jk = dims.knuckle_transverse_inertia * (np.eye(3) - np.outer(e, e)) + Jk_e * np.outer(e, e)
                c = np.array([0.0, side * P.l, 0.0])
                Jw = np.diag([dims.wheel_diametral_inertia, P.I2, dims.wheel_diametral_inertia])
                com = dims.wheel_mass * c / m
                J = Jk + _shift(dims.knuckle_mass, -com) + Jw + _shift(dims.wheel_mass, c - com)
            roll_share += (J + _shift(m, K + com))[0, 0]
            links.append((T, T.T @ com, T.T @ J @ T))
        axle_roll = P.I3 - roll_share
        if not axle_roll > 0.0:
            raise ParameterError(f"I3 = {P.I3:g} kg m^2 is less than the wheels' and knuckles' share of the roll "
                                 f"inertia ({roll_share:.4g} kg m^2): choose lighter wheels or knuckles")
        axle = np.diag([axle_roll, axle_roll, axle_roll])  # only the roll component is ever used
        return cls((links[0][0], links[1][0]), (dims.axle_mass, m, m),
                   (np.zeros(3), links[0][1], links[1][1]), (axle, links[0][2], links[1][2]))


@dataclass
class MbsSystem:
    """One assembled Exudyn system of the axle and the forces it calls; see the module docstring."""

    container: exu.SystemContainer
    mbs: exu.MainSystem
    tree: int
    tree_node: int
    forces: AxleForces
    sensors: dict = field(default_factory=dict)
    calls: int = 0
    error: tuple[float, BaseException] | None = None   # (time, exception) of the first failed evaluation

    def _tree_force(self, mbs, t, itemNumber, q, q_t):
        """The tree's force user function: (Q_psi, Q_theta1, Q_theta2, alpha1', alpha2')."""
        self.calls += 1
        try:
            r = self.forces.evaluate(t, q, q_t, (q_t[3], q_t[4]))
        except Exception as exc:   # Exudyn reports only that a user function failed: keep the reason
            if self.error is None:
                self.error = (t, exc)
            raise
        return [r[0], r[1], r[2], r[3], r[4]]

    def set_state(self, y: np.ndarray, configuration=CURRENT) -> None:
        """Write the MBS state y = (psi, theta1, theta2, rates, alpha1, alpha2) into a configuration."""
        y = np.asarray(y, dtype=float)
        sd = self.mbs.systemData
        sd.SetODE2Coordinates([y[0], y[1], y[2], 0.0, 0.0], configuration=configuration)
        sd.SetODE2Coordinates_t([y[3], y[4], y[5], y[6], y[7]], configuration=configuration)


def build_system(params: ShimmyParameters, effects: Effects, fidelity: Fidelity, dims: AxleDimensions,
                 forces: AxleForces, y0: np.ndarray | None = None, output_interval: float | None = None
                 ) -> MbsSystem:
    """Assemble the Exudyn system; ``y0`` is the initial MBS state (psi, theta1, theta2, rates, alpha1, alpha2).

    With ``output_interval`` the tree's coordinates and velocities are recorded by sensors (in memory).
    """
    P = params
    inertia = TreeInertia.build(P, dims, Assumption.UNCOUPLED_INERTIA in fidelity)
    y0 = np.zeros(8) if y0 is None else np.asarray(y0, dtype=float)
    container = exu.SystemContainer()
    mbs = container.AddSystem()
    node = mbs.AddNode(NodeGenericODE2(referenceCoordinates=[0.0] * 5,
                                       initialCoordinates=[y0[0], y0[1], y0[2], 0.0, 0.0],
                                       initialCoordinates_t=[y0[3], y0[4], y0[5], y0[6], y0[7]],
                                       numberOfODE2Coordinates=5))
    half = 0.5 * P.L - P.l
    J = exu.JointType
    none = np.zeros((3, 3))
    tree = mbs.AddObject(ObjectKinematicTree(
        nodeNumber=node,
        jointTypes=[J.RevoluteX, J.RevoluteZ, J.RevoluteZ, J.PrismaticX, J.PrismaticX],
        linkParents=[-1, 0, 0, -1, -1],
        jointTransformations=exu.Matrix3DList([np.eye(3), inertia.joint_rotations[0], inertia.joint_rotations[1],
                                               np.eye(3), np.eye(3)]),
        jointOffsets=exu.Vector3DList([[0.0, 0.0, P.R], [0.0, -half, 0.0], [0.0, half, 0.0], [0.0] * 3, [0.0] * 3]),
        linkInertiasCOM=exu.Matrix3DList(list(inertia.inertias) + [none, none]),
        linkCOMs=exu.Vector3DList([list(c) for c in inertia.coms] + [[0.0] * 3, [0.0] * 3]),
        linkMasses=list(inertia.masses) + [1.0, 1.0],
        jointPControlVector=[P.k3, 0.0, 0.0, 0.0, 0.0],
        jointDControlVector=[P.c3, P.c4, P.c4, 0.0, 0.0],
        jointPositionOffsetVector=[0.0] * 5,
        jointVelocityOffsetVector=[0.0] * 5,
        visualization={"show": False, "showLinks": False, "showJoints": False, "color": [-1.0] * 4,
                       "graphicsDataList": []}))
    system = MbsSystem(container, mbs, tree, node, forces)
    mbs.SetObjectParameter(tree, "forceUserFunction", system._tree_force)
    if output_interval is not None:
        from exudyn.itemInterface import SensorNode
        for name, var in (("q", exu.OutputVariableType.Coordinates),
                          ("q_t", exu.OutputVariableType.Coordinates_t)):
            system.sensors[name] = mbs.AddSensor(SensorNode(nodeNumber=node, outputVariableType=var,
                                                            storeInternal=True, writeToFile=False))
    mbs.Assemble()
    return system

