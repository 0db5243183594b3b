"""The assumptions of the reduced model as named switches of the multibody model.

Every simplification by which the paper's equations (2.1)-(2.11) (Yang, Knowles & Mavros, section 2) differ from
the geometry of a rigid axle with caster-tilted kingpins, two steered and spinning wheels and a tyre with a contact
patch is one :class:`Assumption`.  With all of them on (``Fidelity.parse("reduced")``) the multibody equations
are (2.1)-(2.11) exactly; with all off (``"full"``) every force acts where and in the direction the actual poses
put it.  :data:`ASSUMPTIONS` documents each one: where it enters the reduced equations and what the full geometry
does instead (the table in docs/results.md is generated from it by tools/docs_tables.py).
"""

from __future__ import annotations

import enum
from dataclasses import dataclass
from typing import Iterable

from axles.parameters import ParameterError


class Assumption(enum.Enum):
    SMALL_ANGLES = "small_angles"
    FIXED_STATIC_LOAD_ARMS = "fixed_static_load_arms"
    UNCOUPLED_INERTIA = "uncoupled_inertia"
    SLIP_HEADING_ONLY = "slip_heading_only"
    LOAD_TRAMP_ONLY = "load_tramp_only"
    LATERAL_STIFFNESS_TRAMP_ONLY = "lateral_stiffness_tramp_only"
    CONSTANT_LOAD = "constant_load"
    QUASI_STEADY_SPEED = "quasi_steady_speed"
    SEPARATE_LATERAL_SPRING = "separate_lateral_spring"
    NO_KINGPIN_INCLINATION = "no_kingpin_inclination"
    ROLL_AXIS_AT_WHEEL_CENTRE = "roll_axis_at_wheel_centre"
    RIGID_AXLE_MOUNTS = "rigid_axle_mounts"
    PARALLEL_STEERING_ARMS = "parallel_steering_arms"
    RIGID_STEERING_GEAR = "rigid_steering_gear"
    NO_AXLE_ROLL_STEER = "no_axle_roll_steer"
    NO_CAMBER_FORCE = "no_camber_force"
    RIGID_VERTICAL_MOUNTS = "rigid_vertical_mounts"
    MASSLESS_LINKS = "massless_links"


@dataclass(frozen=True)
class AssumptionInfo:
    """One row of the assumptions table."""

    assumption: Assumption
    summary: str          # the assumption in one line
    enters: str           # where it enters the reduced equations
    full_geometry: str    # what the multibody model does with the switch off
    linear: bool          # False: it changes only the nonlinear terms, so it cannot move a Hopf point
    element: bool = False  # True: a geometric element the paper leaves out; studied on the full geometry

    @property
    def name(self) -> str:
        return self.assumption.value


ASSUMPTIONS: tuple[AssumptionInfo, ...] = (
    AssumptionInfo(
        Assumption.SMALL_ANGLES,
        "kinematics to first order in the states and in the caster angle (sin gamma -> gamma, cos gamma -> 1)",
        "every lever arm of (2.1)-(2.3) (R gamma + t, l (gamma - f), L/2, R), the gyroscopic terms I2 V/R, "
        "theta and psi in (2.10)-(2.11)",
        "exact rotations about the roll axis and the caster-tilted kingpins; contact point of the steered, "
        "cambered wheel; force directions turn with the wheel and lever arms follow the pose; gyroscopic "
        "moment I2 Omega (omega x s), I2 V/R cos(gamma) at straight running; R sin(gamma) + t cos(gamma); slip as "
        "Pacejka's tan(alpha) with |v_x| of the contact",
        True),
    AssumptionInfo(
        Assumption.FIXED_STATIC_LOAD_ARMS,
        "the static wheel load Fz and its rolling resistance f Fz (and, under braking, the brake force F_x) act "
        "through the straight-running lever arms",
        "absent from (2.1)-(2.3), which keep only load changes (the k5 terms)",
        "Fz, f Fz and the brake force act at the moving contact point: geometric stiffness -2 Fz R in tramp (the "
        "contact of the "
        "cambered wheel moves R psi sideways), -Fz R sin(gamma)^2 in yaw, yaw-tramp couplings of about "
        "100 N m/rad",
        True),
    AssumptionInfo(
        Assumption.UNCOUPLED_INERTIA,
        "mass matrix diag(I1, I1, I3): no inertial yaw-tramp coupling, no centrifugal or Coriolis forces",
        "the left-hand sides I1 theta'', I3 psi'' of (2.1)-(2.3)",
        "the kinematic tree's mass matrix of the chosen bodies on the caster-tilted kingpins: yaw-tramp coupling "
        "-(J_knuckle + I_wheel) sin(gamma) - m_wheel l L/2 sin(gamma) (-0.32 kg m^2 with the chosen "
        "dimensions) and the velocity-dependent inertial forces",
        True),
    AssumptionInfo(
        Assumption.SLIP_HEADING_ONLY,
        "the slip angle is driven only by the wheel heading and the yaw rate at the leading contact point",
        "(2.10)-(2.11): -V theta + a theta' on the right-hand side",
        "velocity of the actual leading contact point: adds R psi' (the rolling axle moves the contact patch "
        "sideways) and -R sin(gamma) theta' (caster trail) to -V theta + a theta'",
        True),
    AssumptionInfo(
        Assumption.LOAD_TRAMP_ONLY,
        "the tyre's vertical deflection changes only with the tramp angle",
        "(L/2) k5 l (gamma - f) psi in (2.1)-(2.2), (L^2/2) k5 psi in (2.3)",
        "deflection from the actual wheel pose: steering raises the wheel centre by l sin(gamma) theta, adding "
        "k5 (L/2) l sin(gamma) (theta1 + theta2) to (2.3) and -k5 l^2 gamma (gamma - f) theta to (2.1)-(2.2)",
        True),
    AssumptionInfo(
        Assumption.LATERAL_STIFFNESS_TRAMP_ONLY,
        "the lateral tyre spring k4 is deflected only by the tramp angle",
        "k4 R^2 gamma psi in (2.1)-(2.2), 2 k4 R^2 psi in (2.3)",
        "deflection = lateral displacement of the actual contact point, which steering moves by "
        "-R sin(gamma) theta: adds the symmetric coupling k4 R^2 gamma (theta1 + theta2) to (2.3) and "
        "-k4 R^2 gamma^2 theta to (2.1)-(2.2)",
        True),
    AssumptionInfo(
        Assumption.CONSTANT_LOAD,
        "tyre properties at the static load Fz (the paper keeps Fz = Fz0)",
        "D_y, B_y, E_y of (2.7)-(2.9), the trail (4.5)-(4.8), a (4.1) and sigma (4.9), all at Fz",
        "Magic Formula, trail, half contact length and relaxation length at the actual vertical force; "
        "F_y(0) = 0 at every load, so no Hopf point moves",
        False),
    AssumptionInfo(
        Assumption.QUASI_STEADY_SPEED,
        "a change of speed enters only through V(t) in the equations",
        "V in (2.1)-(2.3) and (2.10)-(2.11) along a speed ramp",
        "along a ramp also the d'Alembert force -m_wheel dV/dt at the wheel centres and the road force that spins "
        "the wheels up, I2 dOmega/dt / R; nothing at constant speed",
        False),
    AssumptionInfo(
        Assumption.SEPARATE_LATERAL_SPRING,
        "the tyre's lateral stiffness k4 acts as a spring of its own beside the relaxation equation",
        "k4 R^2 gamma psi in (2.1)-(2.2), 2 k4 R^2 psi in (2.3), next to the slip equations (2.10)-(2.11)",
        "the lateral compliance is counted once, in the relaxation equation: sigma alpha' + V alpha = v_y is the "
        "stretched string whose carcass stiffness K/sigma (about 120 kN/m) is the tyre's lateral spring (at V = 0 "
        "it is exactly a spring of stiffness K/sigma); no k4 force",
        True),
    AssumptionInfo(
        Assumption.NO_KINGPIN_INCLINATION,
        "the kingpin is tilted by the caster angle only",
        "the lever arms of (2.1)-(2.3) about the kingpin: R gamma + t, l (gamma - f)",
        "the kingpin also leans inward at the top by the kingpin inclination; it passes l inboard of the wheel "
        "centre (hub offset), so the scrub radius at the road is l - R tan(inclination): the steered wheel rises "
        "(weight jacking) and its contact point moves along a different arc",
        True, True),
    AssumptionInfo(
        Assumption.ROLL_AXIS_AT_WHEEL_CENTRE,
        "the axle rolls about an axis at wheel-centre height",
        "R as the lever of the lateral forces about the roll axis in (2.3) and of the k4 deflection R psi",
        "roll axis at the given height above the wheel centres (the spring seats of a leaf-sprung axle): the "
        "contact points move (R + h) psi sideways, the lateral forces act at that lever, the axle's inertia about "
        "the raised axis is I3 + m h^2 and the roll couples with the lateral motion",
        True, True),
    AssumptionInfo(
        Assumption.RIGID_AXLE_MOUNTS,
        "the axle cannot move sideways against the frame",
        "no lateral degree of freedom in (2.1)-(2.11)",
        "a lateral degree of freedom of the axle on the leaf springs' lateral stiffness and damping: the contact "
        "points move with it (slip velocity y', and the k4 spring when it is counted)",
        True, True),
    AssumptionInfo(
        Assumption.PARALLEL_STEERING_ARMS,
        "the tie-rod arms are parallel (no Ackermann)",
        "k1 (theta1 - theta2) in (2.1)-(2.2)",
        "tie-rod arms angled inward (Ackermann); the tie-rod between their ends: the same k1 at straight running, "
        "unequal steer of the two wheels at large angles (nonlinear only with massless links; with the tie rod's "
        "mass the angled arms also turn its ball masses' velocities, a small linear change)",
        True, True),
    AssumptionInfo(
        Assumption.RIGID_STEERING_GEAR,
        "the drag link runs level from the left steering arm to a fixed frame point",
        "k2 theta2 + c2 theta2' in (2.2)",
        "the drag link, inclined in side view, ends on a Pitman arm on a steering gear with its own inertia, "
        "torsional stiffness and damping to the frame: the gear's compliance in series with k2, and roll steer "
        "(the axle's roll moves the steering arm along the inclined drag link)",
        True, True),
    AssumptionInfo(
        Assumption.NO_AXLE_ROLL_STEER,
        "the axle rolls about a horizontal axis: it does not yaw as it rolls",
        "psi in (2.1)-(2.3) and (2.10)-(2.11) is a rotation about x only",
        "the leaf springs' eyes and shackles slope the roll axis in side view: the axle yaws by the roll-steer "
        "coefficient (axle_roll_steer) per unit of roll, so tramp steers both wheels and turns their contact "
        "points; about the sloped axis the tyre forces, the trail moment and the rotor moments have the extra "
        "lever of the yaw component",
        True, True),
    AssumptionInfo(
        Assumption.NO_CAMBER_FORCE,
        "the tyre makes no force or moment from its camber",
        "F_y(alpha) of (2.4)-(2.9) and the trail moment t F_y: slip only",
        "tramp and caster steer camber the wheels; the Magic Formula carries its camber terms (MF 6.1, Pacejka's "
        "205/60R15 example tyre): camber stiffness F_z (p_Ky6 + p_Ky7 df_z) through the horizontal and vertical "
        "shifts, the cornering stiffness falling with |camber|, and the camber moment of the residual torque "
        "F_z R (q_Dz8 + q_Dz9 df_z) gamma",
        True, True),
    AssumptionInfo(
        Assumption.RIGID_VERTICAL_MOUNTS,
        "the axle cannot bounce against the frame",
        "no vertical degree of freedom in (2.1)-(2.11)",
        "a vertical degree of freedom of the axle on the leaf springs' vertical stiffness and damping: bounce changes "
        "both wheel loads (k5), whose load at the scrub radius and rolling resistance at the hub offset toe the wheels "
        "by l (sin gamma - f cos gamma) k5 per unit of bounce, and it steers the left wheel through the inclined drag "
        "link (bump steer)",
        True, True),
    AssumptionInfo(
        Assumption.MASSLESS_LINKS,
        "the tie rod and the drag link have no mass",
        "I1 theta'' in (2.1)-(2.2): the wheels' inertia about the kingpins only",
        "each rod is two point masses, half at each ball joint, on the steering arms' ends (and the Pitman arm's): "
        "the steering inertia grows by m r^2 / 2 per arm, steer couples with roll through the arm ends' masses; the "
        "whole axle keeps Table 1's I3",
        True, True),
)

ELEMENT_ASSUMPTIONS = tuple(info.assumption for info in ASSUMPTIONS if info.element)
PAPER_ASSUMPTIONS = tuple(info.assumption for info in ASSUMPTIONS if not info.element)
# the freedoms added by issue 18: the checks of the earlier elements keep them out (their switches on)
ISSUE_18 = frozenset({Assumption.NO_AXLE_ROLL_STEER, Assumption.NO_CAMBER_FORCE,
                      Assumption.RIGID_VERTICAL_MOUNTS, Assumption.MASSLESS_LINKS})

_BY_NAME = {info.name: info.assumption for info in ASSUMPTIONS}
ALL = frozenset(Assumption)


@dataclass(frozen=True)
class Fidelity:
    """Which assumptions of the reduced model are on.  All on: the reduced model; none: the full geometry."""

    assumed: frozenset[Assumption] = ALL

    @classmethod
    def reduced(cls) -> "Fidelity":
        return cls(ALL)

    @classmethod
    def full(cls) -> "Fidelity":
        return cls(frozenset())

    @classmethod
    def parse(cls, text: str | Iterable[str] | None) -> "Fidelity":
        """``"reduced"`` (all on), ``"full"`` (all off), or a comma list of assumption names to keep on."""
        if text is None:
            return cls.reduced()
        names = [s.strip() for s in (text.split(",") if isinstance(text, str) else text) if s.strip()]
        if names == ["reduced"]:
            return cls.reduced()
        if names in (["full"], ["none"], []):
            return cls.full()
        unknown = [n for n in names if n not in _BY_NAME]
        if unknown:
            raise ParameterError(f"unknown assumption '{unknown[0]}' (known: {', '.join(_BY_NAME)}; "
                                 f"or reduced, full)")
        return cls(frozenset(_BY_NAME[n] for n in names))

    def without(self, assumption: Assumption | str) -> "Fidelity":
        """The same fidelity with one assumption switched off."""
        a = assumption if isinstance(assumption, Assumption) else Fidelity.parse(assumption).single()
        return Fidelity(self.assumed - {a})

    def single(self) -> Assumption:
        if len(self.assumed) != 1:
            raise ValueError("not a single assumption")
        return next(iter(self.assumed))

    def __contains__(self, assumption: Assumption) -> bool:
        return assumption in self.assumed

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(info.name for info in ASSUMPTIONS if info.assumption in self.assumed)

    @property
    def label(self) -> str:
        if self.assumed == ALL:
            return "reduced"
        if not self.assumed:
            return "full"
        return ",".join(self.names)

