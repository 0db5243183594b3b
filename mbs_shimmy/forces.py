"""Generalized forces of the multibody axle that Exudyn has no element for: tyres, spinning wheels, alignment.

The Exudyn system (:mod:`mbs_shimmy.system`) carries the inertia, the joint spring-dampers (roll k3, c3; kingpins
c4; lateral mounts; steering gear) and the linkage connectors (tie-rod, drag link).  What stays in Python acts
through :meth:`AxleForces.evaluate`, the kinematic tree's force user function, evaluated once per solver stage,
because Exudyn has no element for it:

* the two tyre elements (:mod:`mbs_shimmy.tyre_element`): contact point of a cambered disc on the road, the
  Magic Formula with the pressure effects, and the slip angle's relaxation equation (Exudyn has no tyre);
* the wheels' spin: a wheel spinning at Omega = V/R about its axis s is exactly equivalent to the same wheel fixed
  to its knuckle plus the moment -I2 Omega (omega x s) (and -I2 Omega' s when the spin changes), because the wheel
  is axisymmetric.  The spin is prescribed by rolling (paper, section 6) and follows the speed schedule; a spinning
  link would need a second coordinate per wheel and a step small enough for its rotation;
* the alignment: constant generalized forces equal and opposite to the static moments at straight running
  (the static wheel load with caster, kingpin inclination and offsets, the rolling resistance), i.e. the tie-rod,
  drag-link and roll-spring preloads set so that the vehicle runs straight.

Poses come from Exudyn: each knuckle's kingpin point K, its velocity, rotation and angular velocity are read from
``MarkerKinematicTreeRigid`` markers at the stage's state (:attr:`AxleForces.system`).  From them: the spin axis
s = R_k s_0 and the wheel centre C = K + (side l) s, the kingpin axis e (the joint frame's z).  Generalized forces
are virtual work on the tree's joints: a force F at P on a knuckle gives u.((P - O) x F) on psi (roll axis u
through O: x, or sloped in side view with the roll steer), e.((P - K) x F) on its theta, y.F on the lateral travel
and z.F on the bounce.  With the first-order kinematics
(``small_angles``) the lever arms are the constant straight-running ones (:meth:`TyreElement.linear`).

With the exact kinematics a stage runs compiled (:mod:`mbs_shimmy.compiled_stage`: numba compiles the same functions
the Python path of :meth:`AxleForces.evaluate` calls, those of :mod:`mbs_shimmy.tyre_element`,
:mod:`mbs_shimmy.knuckle`, :mod:`mbs_shimmy.camber` and :mod:`reduced_model.tyre`), one call per stage for both
wheels; the first-order kinematics stay in Python.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

from mbs_shimmy import engine  # noqa: F401  (before exudyn: chooses Exudyn's compiled module)

# isort: split
import exudyn as exu

from mbs_shimmy.camber import CamberTerms
from axles.dimensions import AxleDimensions
from mbs_shimmy.fidelity import ELEMENT_ASSUMPTIONS, Assumption, Fidelity
from mbs_shimmy.geometry import SIDES, AxleGeometry
from mbs_shimmy.knuckle import knuckle_pose, ramp_moments, rotor_moment
from mbs_shimmy.tyre_element import TyreElement, brake_forces, wheel_contact
from reduced_model.model import Effects, ShimmyModel
from axles.parameters import ParameterError, ShimmyParameters
from axles.braking import FREE_ROLLING, Braking
from axles.pressures import TyrePressures

_POS, _VEL = exu.OutputVariableType.Position, exu.OutputVariableType.Velocity
_ROT, _OMEGA = exu.OutputVariableType.RotationMatrix, exu.OutputVariableType.AngularVelocity


@dataclass(frozen=True)
class ElementFlags:
    """The fidelity switches the tyre elements read (see :mod:`mbs_shimmy.fidelity`)."""

    fixed_static_load_arms: bool
    slip_heading_only: bool
    load_tramp_only: bool
    k4_tramp_only: bool
    separate_lateral_spring: bool


def layout_of(fidelity: Fidelity, dims: AxleDimensions):
    """The tree's coordinates (:class:`mbs_shimmy.system.Layout`) for these switches and dimensions."""
    from mbs_shimmy.layout import Layout
    lateral = Assumption.RIGID_AXLE_MOUNTS not in fidelity and dims.axle_mount_lateral_compliance > 0.0
    gear = Assumption.RIGID_STEERING_GEAR not in fidelity and dims.steering_gear_compliance > 0.0
    vertical = Assumption.RIGID_VERTICAL_MOUNTS not in fidelity and dims.axle_mount_vertical_compliance > 0.0
    return Layout(lateral, gear, vertical)


class AxleForces:
    """Generalized forces on the tree's coordinates and slip rates of the axle at one state; see the module doc.

    ``speed(t)`` and ``acceleration(t)`` give the speed schedule (m/s, m/s^2); ``pressures`` are the tyres'
    (:class:`~axles.pressures.TyrePressures`).  :meth:`attach` connects it to the assembled Exudyn system whose markers it reads.
    """

    def __init__(self, params: ShimmyParameters, effects: Effects, fidelity: Fidelity, dims: AxleDimensions,
                 pressures: TyrePressures, speed: Callable[[float], float],
                 acceleration: Callable[[float], float] | None = None, braking: Braking = FREE_ROLLING):
        self.params, self.effects, self.fidelity, self.dims = params, effects, fidelity, dims
        self.linear = Assumption.SMALL_ANGLES in fidelity
        if self.linear:
            dropped = [a.value for a in ELEMENT_ASSUMPTIONS if a not in fidelity]
            if dropped:
                raise ParameterError(f"small_angles (the paper's first-order kinematics) has no first-order form of "
                                     f"{', '.join(dropped)}: keep them on with small_angles")
        self.layout = layout_of(fidelity, dims)
        self.g_exact = AxleGeometry.build(params, dims, exact=True, fidelity=fidelity)
        self.g_lin = AxleGeometry.build(params, dims, exact=False, fidelity=fidelity)
        self.g = self.g_lin if self.linear else self.g_exact
        self.flags = ElementFlags(
            fixed_static_load_arms=Assumption.FIXED_STATIC_LOAD_ARMS in fidelity,
            slip_heading_only=Assumption.SLIP_HEADING_ONLY in fidelity,
            load_tramp_only=Assumption.LOAD_TRAMP_ONLY in fidelity,
            k4_tramp_only=Assumption.LATERAL_STIFFNESS_TRAMP_ONLY in fidelity,
            separate_lateral_spring=Assumption.SEPARATE_LATERAL_SPRING in fidelity)
        # exact poses: for the exact kinematics, and for the static load's geometric stiffness
        self.need_exact = (not self.linear) or not self.flags.fixed_static_load_arms
        # raises ParameterError where meaningless; under braking each wheel carries its combined slip
        wheels = ShimmyModel(params, effects).tyres(pressures, braking)
        self.braking = braking
        load_dependent = Assumption.CONSTANT_LOAD not in fidelity
        camber = None
        if Assumption.NO_CAMBER_FORCE not in fidelity:
            camber = CamberTerms.of(dims, params)
            camber = None if camber.neutral else camber
        self.tyres = tuple(TyreElement(s, params, effects, w, load_dependent, self.g, self.flags, camber)
                           for s, w in zip(SIDES, wheels))
        self.quasi_steady = Assumption.QUASI_STEADY_SPEED in fidelity
        # The d'Alembert force of the decelerating frame acts on the wheel mass at the wheel centre when the
        # inertia is the distributed one (lumped, the mass sits on the kingpin axis and does no virtual work).
        self.wheel_mass = 0.0 if Assumption.UNCOUPLED_INERTIA in fidelity else dims.wheel_mass
        self.I2, self.R = params.I2, params.R
        self.ramp_constants = (params.l, params.I2, params.R, self.wheel_mass)
        self.speed = speed
        self.acceleration = acceleration
        self.steady = self.quasi_steady or acceleration is None
        L = self.layout
        self.n_mech = L.n_mech
        self.i_lat = L.index("y_axle") if L.lateral else -1
        self.i_vert = L.index("z_axle") if L.vertical else -1
        self.i_psi, self.i_th1, self.i_th2 = L.index("psi"), L.index("theta1"), L.index("theta2")
        self.roll_height = self.g_exact.roll_height
        self.Oz = self.g_exact.origin[2]
        # the roll axis u = (ux, 0, uz): x without roll steer, sloped in side view with it
        self.ux, _, self.uz = self.g_exact.roll_axis
        self.alignment = [0.0] * (L.n_mech + 2)
        self.system = None
        self.markers = ()
        # the exact kinematics' stage compiled (mbs_shimmy.compiled_stage), set by attach
        self.stage = None
        # spin axis (y of the axle frame) in each knuckle's joint frame: s = R_link s_local
        rows = [self.g_exact.joint_rotation(side) for side in SIDES]
        self.spin_local = tuple((r[1][0], r[1][1], r[1][2]) for r in rows)

    def attach(self, system) -> None:
        """Read poses from this assembled system; set the alignment at straight running (zero state)."""
        self.system = system
        self.stage = None          # the alignment from the Python path; the compiled stage reads it
        mbs = system.mbs
        self.get = mbs.GetMarkerOutput
        if system.markers is not None:
            self.markers = system.markers.knuckles
        sd = mbs.systemData
        q0, v0 = sd.GetODE2Coordinates(), sd.GetODE2Coordinates_t()
        n = len(q0)
        sd.SetODE2Coordinates([0.0] * n)
        sd.SetODE2Coordinates_t([0.0] * n)
        # the alignment trims the free-rolling axle to run straight: braking then deflects it (the compiled stage,
        # braking included, is attached after it)
        Q = self.evaluate(0.0, [0.0] * n, [0.0] * n, free_rolling=True)
        self.alignment = [-float(v) for v in Q[:self.n_mech]] + [0.0, 0.0]
        sd.SetODE2Coordinates(q0)
        sd.SetODE2Coordinates_t(v0)
        if not self.linear and len(self.markers) == 2:
            from mbs_shimmy import compiled_stage  # numba's import only where a compiled stage is used
            self.stage_constants, self.stage_tables = compiled_stage.constants(self)
            self.stage = compiled_stage.STAGE

    def knuckle_poses(self, q, qd) -> tuple:
        """(K, v_K, e, s, omega) of both knuckles at the tree state (q, q') written in Exudyn's current
        configuration: K and the knuckle's rotation (hence e and s) are Exudyn's marker outputs; the velocities are
        J q' with the same joint axes and points (roll axis u through O, kingpin e through K, lateral travel y),
        omega = psi' u + theta' e and v_K = y' y + z' z + psi' u x (K - O) - the columns that also project the
        forces (u = x without roll steer; O moves with the lateral travel y and the bounce z).
        (Exudyn's Velocity and AngularVelocity outputs give the same, ``tests/test_mbs_model.py``, at 10 us a call
        against 4-7 us for a pose: they would double the cost of a stage.)"""
        out = []
        get = self.get
        psid = qd[self.i_psi]
        Oy, yd = (q[self.i_lat], qd[self.i_lat]) if self.i_lat >= 0 else (0.0, 0.0)
        Oz, zd = (self.Oz + q[self.i_vert], qd[self.i_vert]) if self.i_vert >= 0 else (self.Oz, 0.0)
        wx, wz = psid * self.ux, psid * self.uz      # the axle's angular velocity psi' u
        for m, spin, thd in zip(self.markers, self.spin_local, (qd[self.i_th1], qd[self.i_th2])):
            out.append(knuckle_pose(get(m, _ROT).tolist(), get(m, _POS).tolist(), spin, Oy, Oz, yd, zd, wx, wz, thd))
        return tuple(out)

    # ------------------------------------------------------------------------------------------------------
    def evaluate(self, t: float, q, qd, states: list | None = None, python: bool = False,
                 free_rolling: bool = False):
        """Generalized forces on the tree's coordinates, then (alpha1', alpha2'), at time t and tree state
        (q, q'); the slip angles are the last two velocities.  ``states``, if a list, receives the two wheels'
        :class:`~mbs_shimmy.tyre_element.ContactState`.

        The exact kinematics run compiled (:meth:`compiled`) unless ``python``; the Python path below calls the
        functions the compiled stage is built from, and serves the first-order kinematics, ``states``, loads
        outside the load table and ``free_rolling`` (without the braking, for the alignment)."""
        if self.stage is not None and states is None and not python and not free_rolling:
            out = self.compiled(t, q, qd)
            if out is not None:
                return out
        ip, i1, i2 = self.i_psi, self.i_th1, self.i_th2
        psi, th1, th2 = q[ip], q[i1], q[i2]
        psid, thd1, thd2 = qd[ip], qd[i1], qd[i2]
        m = self.n_mech
        al1, al2 = qd[m], qd[m + 1]
        V = self.speed(t)
        kg = self.I2 * V / self.R                     # I2 Omega
        record = states is not None
        t1, t2 = self.tyres
        out = list(self.alignment)
        if self.need_exact:
            p1, p2 = self.knuckle_poses(q, qd)
        if self.linear:
            braked = not free_rolling
            r1 = t1.linear(psi, th1, psid, thd1, al1, V, record, braked)
            r2 = t2.linear(psi, th2, psid, thd2, al2, V, record, braked)
            # spinning wheels, first order: g = 1
            Qp = r1[0] + r2[0] + kg * (thd1 + thd2)
            Q1 = r1[1] - kg * psid
            Q2 = r2[1] - kg * psid
            Qy = 0.0
            if not self.flags.fixed_static_load_arms:
                s1 = t1.static_load_moments(p1, self.Oz)
                s2 = t2.static_load_moments(p2, self.Oz)
                Qp += s1[0] + s2[0]
                Q1 += s1[1]
                Q2 += s2[1]
                if braked and self.braking.active:      # the brake forces at the actual contact points too
                    c1 = wheel_contact(-self.params.l, p1[0], p1[3], math.sqrt)
                    c2 = wheel_contact(self.params.l, p2[0], p2[3], math.sqrt)
                    b1 = brake_forces(c1, p1, 0.0, self.Oz, self.ux, self.uz, t1.brake_force(al1))
                    b2 = brake_forces(c2, p2, 0.0, self.Oz, self.ux, self.uz, t2.brake_force(al2))
                    Qp += b1[0] + b2[0]
                    Q1 += b1[1]
                    Q2 += b2[1]
        else:
            cpsi, spsi = math.cos(psi), math.sin(psi)
            Oy = q[self.i_lat] if self.i_lat >= 0 else 0.0
            Oz = self.Oz + q[self.i_vert] if self.i_vert >= 0 else self.Oz
            r1 = t1.exact(p1, Oy, Oz, self.roll_height, al1, V, cpsi, spsi, self.ux, self.uz, record, not free_rolling)
            r2 = t2.exact(p2, Oy, Oz, self.roll_height, al2, V, cpsi, spsi, self.ux, self.uz, record, not free_rolling)
            gp, g1, g2 = self.rotor_moments(p1, p2, V)
            Qp, Q1, Q2 = r1[0] + r2[0] + gp, r1[1] + g1, r2[1] + g2
            Qy = r1[3] + r2[3]
            Qz = r1[4] + r2[4]
        if not self.steady:
            acc = self.acceleration(t)
            if acc != 0.0:
                if self.linear:
                    Q1 += self._ramp_linear(-1.0, acc)
                    Q2 += self._ramp_linear(1.0, acc)
                else:
                    a1 = self._ramp_exact(-1.0, p1, Oy, Oz, acc)
                    a2 = self._ramp_exact(1.0, p2, Oy, Oz, acc)
                    Qp += a1[0] + a2[0]
                    Q1 += a1[1]
                    Q2 += a2[1]
        if record:
            states.append(r1[-1])
            states.append(r2[-1])
        out[ip] += Qp
        out[i1] += Q1
        out[i2] += Q2
        if self.i_lat >= 0:
            out[self.i_lat] += Qy
        if self.i_vert >= 0:
            out[self.i_vert] += Qz          # the tyres' vertical forces (nothing else applied has a z component)
        out[m] = r1[2]
        out[m + 1] = r2[2]
        return out

    def compiled(self, t: float, q, qd) -> list | None:
        """:meth:`evaluate` by the compiled stage (:mod:`mbs_shimmy.compiled_stage`), or None where it cannot
        (a load outside the load table) or there is none (first-order kinematics, no system attached)."""
        if self.stage is None:
            return None
        get = self.get
        m1, m2 = self.markers
        out = self.stage(self.stage_constants, self.stage_tables, get(m1, _ROT), get(m1, _POS), get(m2, _ROT),
                         get(m2, _POS), tuple(q), tuple(qd), self.speed(t),
                         0.0 if self.steady else self.acceleration(t))
        return None if out is None else out.tolist()

    def rotor_moments(self, p1: tuple, p2: tuple, speed: float) -> tuple[float, float, float]:
        """(Q_psi, Q_theta1, Q_theta2) of the wheels' spin Omega = V/R (:func:`rotor_moment`; poses as
        :meth:`knuckle_poses`)."""
        kg = self.I2 * speed / self.R
        a1, b1 = rotor_moment(kg, self.ux, self.uz, p1)
        a2, b2 = rotor_moment(kg, self.ux, self.uz, p2)
        return 0.0 + a1 + a2, b1, b2

    # --- speed changes (assumption quasi_steady_speed off) ------------------------------------------------
    def _ramp_exact(self, side: float, pose: tuple, Oy: float, Oz: float, acc: float) -> tuple[float, float]:
        return ramp_moments(self.ramp_constants, side, pose, Oy, Oz, self.ux, self.uz, acc, math.sqrt)

    def _ramp_linear(self, side: float, acc: float) -> float:
        """First-order form of :func:`ramp_moments`: both forces along x at lever -side*l about the kingpin."""
        fx = -self.I2 * acc / self.R ** 2 - self.wheel_mass * acc
        return -side * self.params.l * fx
