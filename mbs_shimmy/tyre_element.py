"""The user tyre element: one per wheel, contact from the wheel's pose, forces at the contact, slip-angle state.

Per wheel, from the pose of its knuckle (the wheel is carried by the knuckle; its spin is a rotor moment, see
:mod:`mbs_shimmy.forces`):

* contact point P where the wheel plane's line of steepest descent from the centre C meets the road z = 0
  (:func:`~mbs_shimmy.geometry.disc_contact`); the loaded radius is |P - C|;
* vertical force Fz = Fz_static + k5 (R - |P - C|) along the road normal (k5 from the reduced model's tyre,
  pressure effect ``vs``; Fz_static is Table 1's F_z, so at straight running the loaded radius is R), and the
  rolling resistance -f Fz along the wheel heading x_w, which reaches the knuckle at the wheel centre (the wheel
  rolls freely: its bearing carries no moment about the spin axis);
* lateral spring -k4 y along the wheel's lateral direction y_w, y = lateral displacement of P from its
  straight-running position (Table 1's k4), only with the assumption ``separate_lateral_spring``: otherwise the
  lateral compliance is the relaxation equation's carcass spring K/sigma alone (counted once);
* Magic-Formula lateral force F_y(alpha) of :mod:`reduced_model.tyre` (eqs. 2.4-2.9) along y_w, acting at the
  pneumatic trail t(alpha) behind P, i.e. with the moment -t F_y about the road normal; ``pt`` makes the trail
  slip-dependent (4.2-4.8); with ``no_camber_force`` off the Magic Formula's camber terms add a force and a moment
  at P from the wheel's camber (:mod:`mbs_shimmy.camber`);
* slip-angle state alpha (Pacejka's tan-slip, the Magic Formula's input) with the relaxation equation
  sigma alpha' + |v_x| alpha = v_y, v the road-relative velocity of the leading contact point P + a x_w
  (von Schlippe's straight-tangent approximation; Pacejka, Tire and Vehicle Dynamics, 3rd ed., 2012, sections 5.4
  and 7.2); a and sigma are the reduced model's (pressure effects ``hcl``, ``rl``).

The element is written twice over the same steps: :meth:`TyreElement.exact` from the exact pose, and
:meth:`TyreElement.linear` with every kinematic quantity to first order in the states and in the caster angle,
which is how the reduced model's tyre terms of (2.1)-(2.3) and (2.10)-(2.11) arise; which one runs is the
``small_angles`` switch.  Both are scalar arithmetic on purpose: they run at every solver stage.  The exact
element's steps are plain functions of floats and tuples (:func:`wheel_contact`, :func:`vertical_load`,
:func:`table_values`, :func:`slip_forces`, :func:`contact_forces`): :meth:`TyreElement.exact` calls them, and the
compiled solver stage of the full geometry (:mod:`mbs_shimmy.compiled_stage`) compiles the same functions.

Load dependence (assumption ``constant_load`` off): the Magic-Formula factors, the trail factors, a and sigma
follow the actual vertical force, from a table over the load (:mod:`mbs_shimmy.load_table`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from mbs_shimmy.camber import camber_terms
from mbs_shimmy.geometry import Vec
from mbs_shimmy.load_table import load_table
from mbs_shimmy.scalar_ops import MATH
from reduced_model import tyre
from reduced_model.model import Effects, WheelTyre
from axles.parameters import ShimmyParameters


@dataclass(frozen=True)
class ContactState:
    """What the element computed for one wheel at one state (for drawing and checks)."""

    point: Vec            # contact point P (vehicle frame)
    force: Vec            # total force of the road on the wheel at P (N); the trail moment is not included
    vertical_force: float
    lateral_force: float  # Magic-Formula F_y
    slip_rate: float


def table_values(v, static: tuple, pt: bool, hcl: int, rl: bool) -> tuple[float, ...]:
    """(B, D, E, Bt, Dt, Et0, a, sigma) from the :attr:`~mbs_shimmy.load_table.LoadTable.layout` values ``v`` at a load, the rest from the
    static wheel's ``static`` (same order)."""
    B, D, E = v[0], v[1], v[2]
    if pt:
        Bt, Dt, Et0 = v[3], v[4], v[5]
        i = 6
    else:
        Bt, Dt, Et0 = static[3], static[4], static[5]
        i = 3
    a = v[i] if hcl else static[6]
    sigma = v[i + hcl] if rl else static[7]
    return B, D, E, Bt, Dt, Et0, a, sigma


def wheel_contact(hl: float, K, s, sqrt) -> tuple[float, ...]:
    """(C_x, C_y, C_z, P_x, P_y, |P - C|, cos(camber)): wheel centre C = K + hl s on the spin axis s, and the
    contact point P (:func:`~mbs_shimmy.geometry.disc_contact`, inlined) with the loaded radius |P - C|; ``sqrt``
    from :mod:`mbs_shimmy.scalar_ops`."""
    Kx, Ky, Kz = K[0], K[1], K[2]
    sx, sy, sz = s
    Cx, Cy, Cz = Kx + hl * sx, Ky + hl * sy, Kz + hl * sz
    cphi2 = 1.0 - sz * sz
    cphi = sqrt(cphi2)
    depth = Cz / cphi
    k = Cz / cphi2
    return Cx, Cy, Cz, Cx + k * sz * sx, Cy + k * sz * sy, depth, cphi


def vertical_load(el: tuple, contact: tuple, Oy: float, Oz: float, h: float, cpsi: float,
                  spsi: float) -> tuple[float, float, float]:
    """(F_z, F_z - F_z,static, P0_y) of the exact element (``el`` = :attr:`TyreElement.constants`, ``contact`` of
    :func:`wheel_contact`); P0_y is the contact point's y of the same wheel with theta = 0 (for ``load_tramp_only``
    and ``k4_tramp_only``, else 0)."""
    side, R, L, k5, Fs, load_tramp, k4_tramp = el[0], el[1], el[3], el[4], el[7], el[10], el[11]
    depth = contact[5]
    P0y = 0.0
    if load_tramp or k4_tramp:
        # the same wheel with theta = 0: centre O + Rx(psi) (0, side L/2, -h), axis (0, cos, sin)
        hw = side * 0.5 * L
        C0z = Oz + hw * spsi - h * cpsi
        P0y = Oy + hw * cpsi + h * spsi + C0z * spsi / cpsi
        if load_tramp:
            depth = C0z / cpsi
    dFz = k5 * (R - depth)
    return Fs + dFz, dFz, P0y


def slip_forces(tc: tuple, camber: tuple, values: tuple, alpha: float, load: float, sz: float,
                load_dependent: bool, ops: tuple, braked: bool, bc: tuple) -> tuple[float, float, float, float]:
    """(F_y, M_z, F_y without camber, F_x) at slip alpha and vertical load: the Magic Formula and the trail moment
    -t F_y of :mod:`reduced_model.tyre`, with the camber terms (:func:`~mbs_shimmy.camber.camber_terms`, camber
    asin(s_z)) when ``tc`` says so; ``tc`` = :attr:`TyreElement.slip_constants`, ``values`` of :func:`table_values`,
    ``ops`` the elementary functions (:mod:`mbs_shimmy.scalar_ops`).  ``braked``: MF 6.1's combined slip of the
    constants ``bc`` (:attr:`~reduced_model.tyre.CombinedSlip.constants`: F_x, the weighted F_y and the combined
    aligning moment with the trail at alpha_t,eq, :func:`~reduced_model.tyre.combined_forces`); F_x 0 free rolling.
    A lifted wheel (load <= 0) has no grip only where the properties follow the load: with ``constant_load`` the
    slip force is the reduced model's, whatever the load."""
    sin, cos, atan, sqrt, asin, choose = ops
    C, Ct, q_ez4, t0, pt, with_camber = tc
    B, D, E, Bt, Dt, Et0 = values[0], values[1], values[2], values[3], values[4], values[5]
    Fy = tyre.mf_force(B, C, D, E, alpha, sin, atan)
    t = tyre.mf_trail(Bt, Ct, Dt, Et0, q_ez4, alpha, cos, atan) if pt else t0
    mz = -t * Fy          # the trail moment about the road normal (on the slip force alone)
    total = Fy
    dFy, mzr = 0.0, 0.0
    if with_camber:
        # camber (ISO: top of the wheel to the right positive) = asin(s_z) for both wheels
        dFy, mzr = camber_terms(camber, B, C, D, E, alpha, load, asin(sz), Fy, ops)
        total, mz = Fy + dFy, mz + mzr
    Fx = 0.0
    if braked:
        alpha_t = tyre.trail_slip(bc, alpha, sqrt, choose)
        t_eq = tyre.mf_trail(Bt, Ct, Dt, Et0, q_ez4, alpha_t, cos, atan) if pt else t0
        Fx, total, mz = tyre.combined_forces(bc, alpha, Fy, dFy, mzr, t_eq, cos, atan)
    if load_dependent:
        lifted = load <= 0.0
        return (choose(lifted, 0.0, total), choose(lifted, 0.0, mz), choose(lifted, 0.0, Fy),
                choose(lifted, 0.0, Fx))
    return total, mz, Fy, Fx


def contact_forces(el: tuple, contact: tuple, pose: tuple, Oy: float, Oz: float, ux: float, uz: float, Fz: float,
                   dFz: float, P0y: float, Fy: float, mz: float, a: float, sigma: float, alpha: float,
                   speed: float) -> tuple[float, ...]:
    """(Q_psi, Q_theta, alpha_dot, Q_y, Q_z, lateral force) of the exact element from the forces at the contact
    (arguments as :meth:`TyreElement.exact` and the functions above)."""
    side, l, L, k4, f = el[0], el[2], el[3], el[5], el[6]
    fixed_arms, heading_only, k4_tramp, separate = el[8], el[9], el[11], el[12]
    Cx, Cy, Cz, Px, Py, _, cphi = contact
    K, vK, e, s, w = pose
    Kx, Ky, Kz = K[0], K[1], K[2]
    ex, ey, ez = e
    sx, sy, sz = s
    hl = side * l
    xwx, xwy = sy / cphi, -sx / cphi              # heading x_w (horizontal)
    ywx, ywy = sx / cphi, sy / cphi               # lateral y_w (horizontal)
    if not separate:
        lat = Fy          # the lateral compliance is the relaxation equation's carcass spring (K/sigma)
    elif k4_tramp:
        lat = Fy - k4 * (P0y - side * 0.5 * L) * ywy
    else:
        lat = Fy - k4 * (Px * ywx + (Py - side * 0.5 * L) * ywy)
    # The static load acts through the actual lever arms (its geometric stiffness included) or, as in
    # (2.1)-(2.3), through the straight-running ones, where it is a constant balanced by the alignment.
    vert = dFz if fixed_arms else Fz
    # The wheel rolls freely on its bearing, which carries no moment about the spin axis: the rolling
    # resistance reaches the knuckle as the same force at the wheel centre C (at P it would brake the knuckle
    # by f Fz |P - C| about s).  The lateral and vertical forces act at P.
    Frx, Fry = -f * vert * xwx, -f * vert * xwy
    Fx, Fy_lat = lat * ywx, lat * ywy
    Fyv = Fry + Fy_lat
    # generalized forces: psi about u through O (x and z components of the moments about O, the trail moment's
    # -t F_y about z included); theta about e through K (P_z = 0)
    # (no test of uz = 0 here: the twin traces this with uz a symbol; a zero uz adds an exact 0)
    q_psi = (ux * ((Py - Oy) * vert + Oz * Fy_lat - (Cz - Oz) * Fry)
             + uz * (Px * Fy_lat - (Py - Oy) * Fx + Cx * Fry - (Cy - Oy) * Frx + mz))
    rx, ry, rz = Px - Kx, Py - Ky, -Kz
    cx, cy, cz = hl * sx, hl * sy, hl * sz       # C - K
    q_theta = (ex * (ry * vert - rz * Fy_lat - cz * Fry) + ey * (rz * Fx - rx * vert + cz * Frx)
               + ez * (rx * Fy_lat - ry * Fx + cx * Fry - cy * Frx) + mz * ez)
    # slip: road-relative velocity of the leading contact point P + a x_w
    wz = w[2]          # only the yaw component of the wheel's angular velocity turns the contact line
    lx = speed - a * wz * xwy
    ly = a * wz * xwx
    if not heading_only:
        # carrier velocity at P as a point of the knuckle: v_K + omega x (P - K)
        lx += vK[0] + w[1] * rz - w[2] * ry
        ly += vK[1] + w[2] * rx - w[0] * rz
    vx = lx * xwx + ly * xwy
    vy = lx * ywx + ly * ywy
    alpha_d = (vy - abs(vx) * alpha) / sigma
    return q_psi, q_theta, alpha_d, Fyv, vert, lat


def brake_forces(contact: tuple, pose: tuple, Oy: float, Oz: float, ux: float, uz: float,
                 Fx: float) -> tuple[float, float, float]:
    """(Q_psi, Q_theta, Q_y) of a brake force ``Fx`` (N, forward positive, so braking is negative) acting along the
    wheel's heading x_w at its contact point P on the knuckle: the brake caliper is on the knuckle, so the brake
    torque F_x |P - C| about the spin axis is the knuckle's (the road force does not pass to the wheel centre, as
    the free-rolling wheel's rolling resistance does).  Virtual work as in :func:`contact_forces`: u.((P - O) x F)
    about the roll axis u through O = (0, Oy, Oz), e.((P - K) x F) about the kingpin e through K; ``contact`` of
    :func:`wheel_contact`."""
    K, _, e, s, _ = pose
    Px, Py, cphi = contact[3], contact[4], contact[6]
    Fxx, Fxy = Fx * s[1] / cphi, -Fx * s[0] / cphi         # F along x_w (horizontal)
    q_psi = ux * Oz * Fxy + uz * (Px * Fxy - (Py - Oy) * Fxx)
    rx, ry, rz = Px - K[0], Py - K[1], -K[2]
    q_theta = -e[0] * rz * Fxy + e[1] * rz * Fxx + e[2] * (rx * Fxy - ry * Fxx)
    return q_psi, q_theta, Fxy


# the first-order element's lateral() runs at every stage of the reduced fidelity: no attribute look-ups
_mf_force, _sin, _atan = tyre.mf_force, math.sin, math.atan
BRAKING_SIZE = 19      # floats of :attr:`reduced_model.tyre.CombinedSlip.constants`


class TyreElement:
    """One wheel's tyre: pose -> contact forces, their generalized forces and the slip-angle rate.

    ``side``: -1 right (wheel 1), +1 left (wheel 2).  Geometry constants come from the axle geometry in use
    (exact caster or linearised, see :class:`~mbs_shimmy.geometry.AxleGeometry`).  Not to be changed after
    construction: the compiled stage copies :attr:`constants`, :attr:`slip_constants` and the load table once.
    """

    def __init__(self, side: float, params: ShimmyParameters, effects: Effects, wheel: WheelTyre,
                 load_dependent: bool, geometry, flags, camber=None):
        self.side = side
        self.camber = camber      # :class:`~mbs_shimmy.camber.CamberTerms`, or None: no camber terms
        self.flags = flags
        # the switches as plain attributes: read at every stage
        self.fixed_arms = flags.fixed_static_load_arms
        self.heading_only = flags.slip_heading_only
        self.load_tramp = flags.load_tramp_only
        self.k4_tramp = flags.k4_tramp_only
        self.separate = flags.separate_lateral_spring
        self.params = params
        self.effects = effects
        self.wheel = wheel
        self.k4 = params.k4
        self.k5 = wheel.k5
        self.f = params.f
        self.static_load = params.Fz
        self.R, self.L, self.l = params.R, params.L, params.l
        self.gamma = geometry.gamma
        self.ky = side * (0.5 * params.L - params.l)
        self.load_dependent = load_dependent
        self.table = load_table(params, effects, wheel) if load_dependent else None
        # a lifted wheel's properties: those at 1 % of the static load (no grip; its a and sigma still count)
        self.lifted = self.table.direct(0.01 * self.static_load) if self.table is not None else None
        mf, tf = wheel.force, wheel.trail
        self.a, self.sigma = wheel.a, wheel.sigma
        # (B, D, E, Bt, Dt, Et0, a, sigma) of the static wheel: the properties without load dependence
        self.static = (mf.B, mf.D, mf.E) + ((tf.Bt, tf.Dt, tf.Et0) if tf is not None else (math.nan,) * 3) + (
            wheel.a, wheel.sigma)
        self.pt, self.hcl, self.rl = effects.pt, int(effects.hcl), effects.rl
        self.t0 = params.t0
        # the arguments of the plain functions above (see :func:`vertical_load`, :func:`contact_forces`)
        self.constants = (side, self.R, self.l, self.L, self.k5, self.k4, self.f, self.static_load, self.fixed_arms,
                          self.heading_only, self.load_tramp, self.k4_tramp, self.separate)
        self.C, self.Ct, self.q_ez4 = mf.C, (tf.Ct if tf is not None else math.nan), (
            tf.q_ez4 if tf is not None else math.nan)
        self.slip_constants = (self.C, self.Ct, self.q_ez4, self.t0, self.pt, camber is not None)
        self.camber_coefficients = camber.coefficients if camber is not None else (0.0,) * 10
        # under braking: MF 6.1's combined slip at the static load (free rolling: not braked, constants unused)
        self.combined = wheel.combined
        self.braked = wheel.combined is not None
        self.braking_constants = wheel.combined.constants if self.braked else (0.0,) * BRAKING_SIZE

    def brake_force(self, alpha: float) -> float:
        """F_x = G_xa(alpha) F_x0 of the braking wheel (N, ISO: braking negative); 0 free rolling."""
        if self.combined is None:
            return 0.0
        return self.combined.forces(0.0, alpha, math.cos, math.atan)[0]

    def properties(self, load: float) -> tuple[float, ...]:
        """(B, D, E, Bt, Dt, Et0, a, sigma) at this vertical load (the static wheel's with ``constant_load``)."""
        if self.table is None:
            return self.static
        if load <= 0.0:                        # lifted wheel: the properties at 1 % of the load (no grip)
            return self.lifted
        return table_values(self.table.at(load), self.static, self.pt, self.hcl, self.rl)

    def lateral(self, alpha: float, load: float, braked: bool = False) -> tuple[float, float, float, float, float]:
        """(F_y, M_z, a, sigma, F_x) at slip alpha and vertical load, without camber (the first-order element's):
        M_z the trail moment -t F_y, or under braking MF 6.1's combined F_y, M_z and F_x (:func:`slip_forces`)."""
        if self.table is None:      # constant_load: the reduced model's slip force, whatever the load
            v = self.static
        else:
            v = self.properties(load)
            if load <= 0.0:         # lifted wheel: no grip
                return 0.0, 0.0, v[6], v[7], 0.0
        if braked and self.braked:
            Fy, mz, _, Fx = slip_forces(self.slip_constants[:5] + (False,), self.camber_coefficients, v, alpha,
                                        load, 0.0, False, MATH, True, self.braking_constants)
            return Fy, mz, v[6], tyre.braked_relaxation_length(self.braking_constants, v[7]), Fx
        Fy = _mf_force(v[0], self.C, v[1], v[2], alpha, _sin, _atan)
        t = tyre.mf_trail(v[3], self.Ct, v[4], v[5], self.q_ez4, alpha, math.cos, _atan) if self.pt else self.t0
        return Fy, -t * Fy, v[6], v[7], 0.0

    # --- exact kinematics ----------------------------------------------------------------------------------
    def exact(self, pose: tuple, Oy: float, Oz: float, h: float, alpha: float, speed: float,
              cpsi: float, spsi: float, ux: float = 1.0, uz: float = 0.0, record: bool = False,
              braked: bool = True):
        """(Q_psi, Q_theta, alpha_dot, Q_y, Q_z[, ContactState]) from the knuckle's pose as Exudyn gives it.

        ``pose`` = (K, v_K, e, s, omega): kingpin point and its velocity, kingpin axis, spin axis and angular
        velocity of the knuckle (vehicle frame); the roll axis runs along u = (ux, 0, uz) (x without roll steer)
        through O = (0, Oy, Oz), h above the wheel centres at straight running; Q_y, Q_z are the forces on the axle's
        lateral travel and bounce.  The steps are the module's plain functions, which the compiled stage shares."""
        el, s = self.constants, pose[3]
        contact = wheel_contact(self.side * self.l, pose[0], s, math.sqrt)
        Fz, dFz, P0y = vertical_load(el, contact, Oy, Oz, h, cpsi, spsi)
        values = self.properties(Fz)
        braked = braked and self.braked
        Fy, mz, _, Fx = slip_forces(self.slip_constants, self.camber_coefficients, values, alpha, Fz, s[2],
                                    self.table is not None, MATH, braked, self.braking_constants)
        sigma = tyre.braked_relaxation_length(self.braking_constants, values[7]) if braked else values[7]
        q_psi, q_theta, alpha_d, Fyv, vert, lat = contact_forces(el, contact, pose, Oy, Oz, ux, uz, Fz, dFz, P0y,
                                                                 Fy, mz, values[6], sigma, alpha, speed)
        if braked:
            b_psi, b_theta, b_y = brake_forces(contact, pose, Oy, Oz, ux, uz, Fx)
            q_psi, q_theta, Fyv = q_psi + b_psi, q_theta + b_theta, Fyv + b_y
        if record:
            cphi = contact[6]
            xwx, xwy, ywx, ywy = s[1] / cphi, -s[0] / cphi, s[0] / cphi, s[1] / cphi
            total = ((Fx - self.f * Fz) * xwx + lat * ywx, (Fx - self.f * Fz) * xwy + lat * ywy, Fz)
            return (q_psi, q_theta, alpha_d, Fyv, vert,
                    ContactState((contact[3], contact[4], 0.0), total, Fz, Fy, alpha_d))
        return q_psi, q_theta, alpha_d, Fyv, vert

    # --- first-order kinematics (the reduced model's) --------------------------------------------------------
    def linear(self, psi: float, theta: float, psi_d: float, theta_d: float, alpha: float, speed: float,
               record: bool = False, braked: bool = True):
        """(Q_psi, Q_theta, alpha_dot[, ContactState]) with the kinematics to first order in the states and in
        gamma (sin gamma -> gamma, cos gamma -> 1).

        At straight running P0 - O = (0, s L/2, -R) and P0 - K = (0, s l, -R); the lever arms are the constant
        Jacobian columns x x (P0 - O) = (0, R, s L/2) and e x (P0 - K) = (-s l, -gamma R, -gamma s l) with
        e = (-gamma, 0, 1).  The spin axis is y + psi z + theta e x y = (-theta, 1, psi - gamma theta), the wheel
        centre height R + s (L/2 psi - gamma l theta), the contact point's lateral shift R (psi - gamma theta).
        """
        side, R, L, l, gam = self.side, self.R, self.L, self.l, self.gamma
        sx = -theta
        sz = psi - gam * theta
        lift = 0.5 * L * psi if self.load_tramp else 0.5 * L * psi - gam * l * theta
        dFz = -self.k5 * side * lift      # the wheel centre rises by side*lift: the deflection falls by as much
        Fz = self.static_load + dFz
        Fy, mz, a, sigma, Fb = self.lateral(alpha, Fz, braked)
        # under braking the brake force acts along x at the straight-running arm, as the rolling resistance in
        # (2.1)-(2.2) (fixed_static_load_arms; without it AxleForces adds its moments at the actual pose instead)
        if not self.fixed_arms:
            Fb = 0.0
        y4 = R * psi if self.k4_tramp else R * sz
        lat = Fy - self.k4 * y4 if self.separate else Fy
        # only load changes: the static load times constant lever arms is balanced by the alignment
        Fx = Fb - self.f * dFz
        q_psi = R * lat + side * 0.5 * L * dFz
        q_theta = -side * l * Fx - gam * R * lat - gam * side * l * dFz + mz
        vy = speed * sx + a * theta_d
        if not self.heading_only:
            vy += R * psi_d - gam * R * theta_d
        alpha_d = (vy - speed * alpha) / sigma
        if record:
            P = (-side * l * theta, side * 0.5 * L + R * sz, 0.0)
            return q_psi, q_theta, alpha_d, ContactState(P, (-self.f * Fz, lat, Fz), Fz, Fy, alpha_d)
        return q_psi, q_theta, alpha_d

    def static_load_moments(self, pose: tuple, Oz: float) -> tuple[float, float]:
        """(Q_psi, Q_theta) of the static load F_z and its rolling resistance at the exact contact point
        (``pose`` as in :meth:`exact`; roll axis through (0, 0, Oz))."""
        K, _, e, s, _ = pose
        sx, sy, sz = s
        hl = self.side * self.l
        _, _, Cz, Px, Py, _, cphi = wheel_contact(hl, K, s, math.sqrt)
        Fs = self.static_load
        # the rolling resistance at the wheel centre (free-rolling wheel, as in :meth:`exact`)
        Fx, Fyv = -self.f * Fs * sy / cphi, self.f * Fs * sx / cphi
        rx, ry, rz = Px - K[0], Py - K[1], -K[2]
        cx, cy, cz = hl * sx, hl * sy, hl * sz
        ex, ey, ez = e
        return (Py * Fs - (Cz - Oz) * Fyv,
                ex * (ry * Fs - cz * Fyv) + ey * (cz * Fx - rx * Fs) + ez * (cx * Fyv - cy * Fx))
