"""Generalized forces of the multibody axle: tyres, spinning wheels, tie-rod, drag link, alignment.

The kinematic tree (:mod:`mbs_shimmy.system`) carries the inertia and the joint spring-dampers (roll k3, c3;
kingpins c4).  Everything else acts through :meth:`AxleForces.evaluate`, the tree's force user function,
evaluated once per solver stage:

* the two tyre elements (:mod:`mbs_shimmy.tyre_element`);
* the wheels' spin: a wheel spinning at Omega = V/R about its axis s is exactly equivalent to the same wheel fixed
  to its knuckle plus the moment -I2 Omega (omega x s) (and -I2 Omega' s when the spin changes), because the wheel
  is axisymmetric: its inertia tensor does not change with the spin angle.  The spin itself is prescribed by
  rolling without longitudinal slip (paper, section 6).  Projected on the coordinates the moment is
  (+I2 Omega theta' g, -I2 Omega psi' g) on (psi, theta) with g = e_z s_y - e_y s_z (= cos gamma at straight
  running), i.e. -I2 V/R psi' in (2.1)-(2.2) and +I2 V/R theta' in (2.3);
* the tie-rod between the two steering arms and the drag link from the left arm to the frame: spring-dampers
  whose axial stiffness and damping are scaled so that about the kingpins they are exactly k1, c1 and k2, c2;
* the alignment: constant generalized forces equal and opposite to the static moments at straight running
  (the static wheel load with caster and kingpin offset, the rolling resistance), i.e. the tie-rod, drag-link
  and roll-spring preloads set so that the vehicle runs straight.  Their own geometric stiffness (preload x arm,
  ~10 N m/rad against k1 = 35.5 kN m/rad) is not modelled.

Generalized forces are virtual work: a force F at P on a knuckle gives x.((P - O) x F) on psi and
e.((P - K) x F) on its theta, e the kingpin axis through K; with the first-order kinematics (``small_angles``)
the lever arms are the constant straight-running ones.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

from reduced_model.model import Effects, ShimmyModel
from reduced_model.parameters import ShimmyParameters

from .dimensions import AxleDimensions
from .fidelity import Assumption, Fidelity
from .geometry import SIDES, AxleGeometry, cross, knuckle_frame
from .tyre_element import TyreElement


@dataclass(frozen=True)
class ElementFlags:
    """The fidelity switches the tyre elements read (see :mod:`mbs_shimmy.fidelity`)."""

    fixed_static_load_arms: bool
    slip_heading_only: bool
    load_tramp_only: bool
    k4_tramp_only: bool


@dataclass(frozen=True)
class Linkage:
    """Axial stiffness and damping of the tie-rod and drag link from k1, c1, k2, c2 and the arm geometry."""

    tie_rod_lever: float      # d(tie-rod length)/d(theta2 - theta1) at straight running, m/rad
    drag_link_lever: float    # d(drag-link length)/d(theta2), m/rad (sign included)
    k_tie_rod: float
    c_tie_rod: float
    k_drag_link: float
    c_drag_link: float

    @classmethod
    def build(cls, params: ShimmyParameters, g: AxleGeometry) -> "Linkage":
        e = g.kingpin_axis
        # Tie-rod along y: its length changes by (e x u)_y (theta2 - theta1), u the arm of either side.
        j_tr = cross(e, g.tie_rod_arm_vector)[1]
        # Drag link along x from the arm to the frame: its length changes by -(e x u_d)_x theta2.
        j_dl = -cross(e, g.drag_link_arm_vector)[0]
        return cls(j_tr, j_dl, params.k1 / j_tr ** 2, params.c1 / j_tr ** 2, params.k2 / j_dl ** 2,
                   params.c2 / j_dl ** 2)


class AxleForces:
    """Generalized forces (psi, theta1, theta2) and slip rates of the axle at one state; see the module doc.

    ``speed(t)`` and ``acceleration(t)`` give the speed schedule (m/s, m/s^2); ``pressure`` is one value or
    (right, left) in Pa.
    """

    def __init__(self, params: ShimmyParameters, effects: Effects, fidelity: Fidelity, dims: AxleDimensions,
                 pressure, speed: Callable[[float], float], acceleration: Callable[[float], float] | None = None):
        self.params, self.effects, self.fidelity, self.dims = params, effects, fidelity, dims
        self.linear = Assumption.SMALL_ANGLES in fidelity
        self.g_exact = AxleGeometry.build(params, dims, exact=True)
        self.g_lin = AxleGeometry.build(params, dims, exact=False)
        self.g = self.g_lin if self.linear else self.g_exact
        self.linkage = Linkage.build(params, self.g)
        self.flags = ElementFlags(
            fixed_static_load_arms=Assumption.FIXED_STATIC_LOAD_ARMS in fidelity,
            slip_heading_only=Assumption.SLIP_HEADING_ONLY in fidelity,
            load_tramp_only=Assumption.LOAD_TRAMP_ONLY in fidelity,
            k4_tramp_only=Assumption.LATERAL_STIFFNESS_TRAMP_ONLY in fidelity)
        # exact poses: for the exact kinematics, and for the static load's geometric stiffness
        self.need_exact = (not self.linear) or not self.flags.fixed_static_load_arms
        wheels = ShimmyModel(params, effects).tyres(pressure)   # raises ParameterError where meaningless
        load_dependent = Assumption.CONSTANT_LOAD not in fidelity
        self.tyres = tuple(TyreElement(s, params, effects, w, load_dependent, self.g, self.flags)
                           for s, w in zip(SIDES, wheels))
        self.quasi_steady = Assumption.QUASI_STEADY_SPEED in fidelity
        # The d'Alembert force of the decelerating frame acts on the wheel mass at the wheel centre when the
        # inertia is the distributed one (lumped, the mass sits on the kingpin axis and does no virtual work).
        self.wheel_mass = 0.0 if Assumption.UNCOUPLED_INERTIA in fidelity else dims.wheel_mass
        self.I2, self.R = params.I2, params.R
        g = self.g
        self.tie_rest = g.L - 2.0 * g.l
        self.tie_arm = g.tie_rod_arm_vector
        self.drag_arm = g.drag_link_arm
        self.drag_point = g.drag_link_frame_point()
        self.drag_length = g.drag_link_length
        self.speed = speed
        self.acceleration = acceleration
        self.steady = self.quasi_steady or acceleration is None
        self.alignment = (0.0, 0.0, 0.0)
        Q = self.evaluate(0.0, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0))
        self.alignment = (-float(Q[0]), -float(Q[1]), -float(Q[2]))

    # ------------------------------------------------------------------------------------------------------
    def evaluate(self, t: float, q, qd, alpha, states: list | None = None):
        """(Q_psi, Q_theta1, Q_theta2, alpha1_dot, alpha2_dot) at time t; q = (psi, theta1, theta2).

        ``states``, if a list, receives the two wheels' :class:`~mbs_shimmy.tyre_element.ContactState`.
        """
        psi, th1, th2 = q[0], q[1], q[2]
        psid, thd1, thd2 = qd[0], qd[1], qd[2]
        al1, al2 = alpha[0], alpha[1]
        V = self.speed(t)
        kg = self.I2 * V / self.R                     # I2 Omega
        flags = self.flags
        record = states is not None
        t1, t2 = self.tyres
        if self.need_exact:
            cpsi, spsi = math.cos(psi), math.sin(psi)
            gx = self.g_exact
            f1 = knuckle_frame(gx, -1.0, cpsi, spsi, th1)
            f2 = knuckle_frame(gx, 1.0, cpsi, spsi, th2)
        if self.linear:
            r1 = t1.linear(psi, th1, psid, thd1, al1, V, record)
            r2 = t2.linear(psi, th2, psid, thd2, al2, V, record)
            # spinning wheels, first order: g = 1
            Qp = r1[0] + r2[0] + kg * (thd1 + thd2)
            Q1 = r1[1] - kg * psid
            Q2 = r2[1] - kg * psid
            if not flags.fixed_static_load_arms:
                s1 = t1.static_load_moments(f1)
                s2 = t2.static_load_moments(f2)
                Qp += s1[0] + s2[0]
                Q1 += s1[1]
                Q2 += s2[1]
            # linkage, first order
            k = self.linkage
            j = k.tie_rod_lever
            T = k.k_tie_rod * j * (th2 - th1) + k.c_tie_rod * j * (thd2 - thd1)
            Q1 += T * j
            Q2 -= T * j
            jd = k.drag_link_lever
            Q2 -= (k.k_drag_link * jd * th2 + k.c_drag_link * jd * thd2) * jd
        else:
            r1 = t1.exact(f1, psid, thd1, al1, V, cpsi, spsi, record)
            r2 = t2.exact(f2, psid, thd2, al2, V, cpsi, spsi, record)
            gp, g1, g2 = self.rotor_moments(f1, f2, psid, thd1, thd2, V)
            Qp = r1[0] + r2[0] + gp
            Q1 = r1[1] + g1
            Q2 = r2[1] + g2
            Qp, Q1, Q2 = self._linkage_exact(Qp, Q1, Q2, psid, thd1, thd2, f1, f2)
        if not self.steady:
            acc = self.acceleration(t)
            if acc != 0.0:
                if self.linear:
                    Q1 += self._ramp_linear(-1.0, acc)
                    Q2 += self._ramp_linear(1.0, acc)
                else:
                    a1 = self._ramp_exact(-1.0, f1, acc)
                    a2 = self._ramp_exact(1.0, f2, acc)
                    Qp += a1[0] + a2[0]
                    Q1 += a1[1]
                    Q2 += a2[1]
        a = self.alignment
        if record:
            states.append(r1[3])
            states.append(r2[3])
        return Qp + a[0], Q1 + a[1], Q2 + a[2], r1[2], r2[2]

    # ------------------------------------------------------------------------------------------------------
    def rotor_moments(self, f1: tuple, f2: tuple, psid: float, thd1: float, thd2: float, speed: float):
        """(Q_psi, Q_theta1, Q_theta2) of the wheels' spin Omega = V/R, exact poses: -I2 Omega (omega x s) with
        omega = psi' x + theta' e gives +I2 Omega theta' g on psi and -I2 Omega psi' g on theta,
        g = e_z s_y - e_y s_z (pose tuple: e at 2..4, spin axis = rotated y at 6, 9, 12)."""
        kg = self.I2 * speed / self.R
        g1 = f1[4] * f1[9] - f1[3] * f1[12]
        g2 = f2[4] * f2[9] - f2[3] * f2[12]
        return kg * (thd1 * g1 + thd2 * g2), -kg * psid * g1, -kg * psid * g2

    def _linkage_exact(self, Qp, Q1, Q2, psid, thd1, thd2, f1, f2):
        """Tie-rod and drag link with the exact poses (generalized forces added to Qp, Q1, Q2).

        Arm vectors w = R_k u from the kingpin point; end velocities psi' x x (p - O) + theta' e x w; a force
        T n at the end gives T e.(w x n) on theta and T x.((p - O) x n) on psi."""
        k, R = self.linkage, self.R
        ux, _, uz = self.tie_arm
        _, _, ex1, ey1, ez1, a00, a01, a02, a10, a11, a12, a20, a21, a22 = f1
        Ky2, Kz2, ex2, ey2, ez2, b00, b01, b02, b10, b11, b12, b20, b21, b22 = f2
        w1x, w1y, w1z = a00 * ux + a02 * uz, a10 * ux + a12 * uz, a20 * ux + a22 * uz
        w2x, w2y, w2z = b00 * ux + b02 * uz, b10 * ux + b12 * uz, b20 * ux + b22 * uz
        p1y, p1z = f1[0] + w1y, f1[1] + w1z
        p2y, p2z = Ky2 + w2y, Kz2 + w2z
        # end velocities (x: only the kingpin rotation moves ends along x)
        v1x = thd1 * (ey1 * w1z - ez1 * w1y)
        v1y = -psid * (p1z - R) + thd1 * (ez1 * w1x - ex1 * w1z)
        v1z = psid * p1y + thd1 * (ex1 * w1y - ey1 * w1x)
        v2x = thd2 * (ey2 * w2z - ez2 * w2y)
        v2y = -psid * (p2z - R) + thd2 * (ez2 * w2x - ex2 * w2z)
        v2z = psid * p2y + thd2 * (ex2 * w2y - ey2 * w2x)
        dx, dy, dz = w2x - w1x, p2y - p1y, p2z - p1z
        length = math.sqrt(dx * dx + dy * dy + dz * dz)
        nx, ny, nz = dx / length, dy / length, dz / length
        T = (k.k_tie_rod * (length - self.tie_rest)
             + k.c_tie_rod * (nx * (v2x - v1x) + ny * (v2y - v1y) + nz * (v2z - v1z)))
        # +T n on end 1, -T n on end 2; no net moment about the roll axis (the force is along the line of ends)
        Q1 += T * (ex1 * (w1y * nz - w1z * ny) + ey1 * (w1z * nx - w1x * nz) + ez1 * (w1x * ny - w1y * nx))
        Q2 -= T * (ex2 * (w2y * nz - w2z * ny) + ey2 * (w2z * nx - w2x * nz) + ez2 * (w2x * ny - w2y * nx))
        # drag link: arm -r_d s (s = rotated y) from the left kingpin to the end p, then to the frame point D
        rd = self.drag_arm
        wx, wy, wz = -rd * b01, -rd * b11, -rd * b21
        py, pz = Ky2 + wy, Kz2 + wz
        vx = thd2 * (ey2 * wz - ez2 * wy)
        vy = -psid * (pz - R) + thd2 * (ez2 * wx - ex2 * wz)
        vz = psid * py + thd2 * (ex2 * wy - ey2 * wx)
        D = self.drag_point
        dx, dy, dz = D[0] - wx, D[1] - py, D[2] - pz
        length = math.sqrt(dx * dx + dy * dy + dz * dz)
        nx, ny, nz = dx / length, dy / length, dz / length
        T = k.k_drag_link * (length - self.drag_length) - k.c_drag_link * (nx * vx + ny * vy + nz * vz)
        Qp += T * (py * nz - (pz - R) * ny)
        Q2 += T * (ex2 * (wy * nz - wz * ny) + ey2 * (wz * nx - wx * nz) + ez2 * (wx * ny - wy * nx))
        return Qp, Q1, Q2

    # --- speed changes (assumption quasi_steady_speed off) ------------------------------------------------
    def _ramp_exact(self, side: float, f: tuple, acc: float) -> tuple[float, float]:
        """Wheel spin-up by the road: force -I2 Omega'/|P - C| along the heading at P with the reaction
        -I2 Omega' s on the knuckle, which together are that force moved to the wheel centre C; plus the
        d'Alembert force -m_w dV/dt at C.  Both act at C along the heading / x."""
        l, R = self.params.l, self.R
        sx, sy, sz = f[6], f[9], f[12]
        hl = side * l
        Cx, Cy, Cz = hl * sx, f[0] + hl * sy, f[1] + hl * sz
        cphi = math.sqrt(1.0 - sz * sz)
        depth = Cz / cphi
        fs = -self.I2 * (acc / R) / depth
        Fx, Fy = fs * sy / cphi - self.wheel_mass * acc, -fs * sx / cphi
        ex, ey, ez = f[2], f[3], f[4]
        rx, ry, rz = Cx, Cy - f[0], Cz - f[1]
        q_psi = -(Cz - R) * Fy
        q_theta = ex * (-rz * Fy) + ey * (rz * Fx) + ez * (rx * Fy - ry * Fx)
        return q_psi, q_theta

    def _ramp_linear(self, side: float, acc: float) -> float:
        """First-order form of :meth:`_ramp_exact`: both forces along x at lever -side*l about the kingpin."""
        fx = -self.I2 * acc / self.R ** 2 - self.wheel_mass * acc
        return -side * self.params.l * fx
