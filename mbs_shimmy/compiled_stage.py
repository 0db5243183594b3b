"""The full geometry's force user function compiled: both tyre elements, rotor moments and speed ramp in one call.

A solver stage of the exact kinematics (:meth:`mbs_shimmy.forces.AxleForces.evaluate`) is scalar arithmetic on a
few dozen floats; in Python it costs about 13 us a stage besides the Exudyn calls, most of it the interpreter's.
Here numba compiles the *same* functions the Python path calls (:func:`~reduced_model.tyre.mf_force`,
:func:`~reduced_model.tyre.mf_trail`, :func:`~mbs_shimmy.camber.camber_terms`, the element's steps in
:mod:`mbs_shimmy.tyre_element`, the knuckle pose, rotor moment and ramp of :mod:`mbs_shimmy.knuckle`;
``register_jitable`` leaves them plain Python functions for their other callers) into one entry point
(:data:`STAGE`) with few arguments: numba's call overhead grows with the number of arguments (about 0.7 us for 20
floats), and compiling the small functions one by one was slower than Python.  What the entry point adds is glue
only: reading the constants array, the load table's cubic interpolation on an array (the Python path's
:meth:`~mbs_shimmy.load_table.LoadTable.at` on lists, same weights
:func:`~mbs_shimmy.load_table.lagrange_weights`), and the sums of
:meth:`~mbs_shimmy.forces.AxleForces.evaluate`.  No fastmath: results equal the Python path's to the last bit
(``tests/mbs/test_mbs_compiled_stage.py``).

Where the compiled stage cannot follow the Python one it returns ``None`` and the caller evaluates that stage in
Python: a positive load outside the load table (:attr:`~mbs_shimmy.load_table.LoadTable.RANGE`: below 1e-6 or
beyond 10 times the static load), where the properties come from the reduced model's formulas directly.  A lifted
wheel's properties are constants (those at 1 % of the static load) and stay compiled.  The first-order element
(``small_angles``) stays in Python.
Under braking the stage carries each wheel's MF 6.1 combined slip (F_x at the contact point, the weighted F_y, the
combined aligning moment: :func:`~reduced_model.tyre.combined_forces`) as the Python path does.

Numba's cache (``cache=True``, next to this file in ``__pycache__``) is checked against this file only; the
functions it compiles live in other files.  :func:`_build` therefore closes the entry point over a hash of all
those sources, which numba's cache index includes, so that a changed formula is compiled anew.
"""

from __future__ import annotations

import hashlib
import math

import numba
import numpy as np
from numba.extending import register_jitable

from mbs_shimmy import camber, knuckle, load_table, scalar_ops, tyre_element
from reduced_model import tyre

_SHARED = (tyre.mf_force, tyre.mf_trail, tyre.mf_weight, tyre.combined_weights, tyre.trail_slip,
           tyre.combined_forces, tyre.braked_relaxation_length, camber.camber_terms, load_table.lagrange_weights,
           tyre_element.table_values, tyre_element.wheel_contact, tyre_element.vertical_load,
           tyre_element.slip_forces, tyre_element.contact_forces, tyre_element.brake_forces, knuckle.knuckle_pose,
           knuckle.rotor_moment, knuckle.ramp_moments, scalar_ops.choose)
for _f in _SHARED:
    register_jitable(_f)
_SOURCES = (tyre, camber, load_table, tyre_element, knuckle, scalar_ops)

# --- layout of the constants array ---------------------------------------------------------------------------
# axle: coordinate indices (psi, theta1, theta2, lateral, bounce; -1 if absent), Oz at rest, roll height h,
# roll axis (ux, uz), I2, R, l, wheel mass, the two spin axes in the joint frames
I_PSI, I_TH1, I_TH2, I_LAT, I_VERT, OZ, H, UX, UZ, I2, RADIUS, ARM, WHEEL_MASS = range(13)
SPIN = (13, 16)
# per wheel, from its start: TyreElement.constants (13), static (8), slip_constants (6), camber coefficients
# (10), load table: load dependent, log of the first node, node spacing, nodes, pt, hcl, rl, columns, a lifted
# wheel's a and sigma (10), braking: braked (1 or 0), then CombinedSlip.constants (tyre_element.BRAKING_SIZE)
EL, STATIC, SLIP, CAMBER, TABLE, BRAKE = 0, 13, 21, 27, 37, 47
LIFTED = 8          # a lifted wheel's a and sigma, from the start of the load table's constants
WHEEL_SIZE = BRAKE + 1 + tyre_element.BRAKING_SIZE
WHEELS = (19, 19 + WHEEL_SIZE)  # where each wheel's constants start
ALIGNMENT = WHEELS[1] + WHEEL_SIZE


def constants(forces) -> tuple[np.ndarray, np.ndarray]:
    """(constants, tables) of this axle for :data:`STAGE`: the array laid out as above (the alignment at the
    end) and both wheels' load tables, shape (2, nodes, columns)."""
    f = forces
    c = [float(f.i_psi), float(f.i_th1), float(f.i_th2), float(f.i_lat), float(f.i_vert), f.Oz, f.roll_height,
         f.ux, f.uz, f.I2, f.R, f.params.l, f.wheel_mass]
    for spin in f.spin_local:
        c += [float(v) for v in spin]
    tables = []
    for element in f.tyres:
        t = element.table
        c += [float(v) for v in element.constants]
        c += [float(v) for v in element.static]
        c += [float(v) for v in element.slip_constants]
        c += [float(v) for v in element.camber_coefficients]
        if t is None:
            c += [0.0, 0.0, 1.0, 4.0, 0.0, 0.0, 0.0, 3.0, 0.0, 0.0]
            tables.append(np.zeros((4, 3)))
        else:
            c += [1.0, t.s0, t.ds, float(t.n), float(element.pt), float(element.hcl), float(element.rl),
                  float(len(t.layout)), element.lifted[6], element.lifted[7]]
            tables.append(t.array)
        c += [float(element.braked)] + [float(v) for v in element.braking_constants]
    assert len(c) == ALIGNMENT
    c += [float(v) for v in f.alignment]
    return np.array(c), np.ascontiguousarray(np.stack(tables))


def table_row(table, c, t: int, Fz):
    """(ok, the load table's :attr:`~mbs_shimmy.load_table.LoadTable.layout` values at the load Fz, D and D_t
    times the load) by the cubic interpolation of :meth:`~mbs_shimmy.load_table.LoadTable.at` on an array (same
    grid test and weights, :func:`~mbs_shimmy.load_table.lagrange_weights`).  ok False where a positive load is
    outside the table; the values are then those at the table's nearest end, finite and to be discarded, as they
    are for a lifted wheel (Fz <= 0, ok: :func:`wheel_terms` takes its constants).  The compiled stage's lookup;
    the twin (:mod:`mbs_shimmy.twin`) has its own on traced values."""
    ok = Fz > 0.0
    x = 1.0
    if ok:
        x = (math.log(Fz) - c[t + 1]) / c[t + 2]
    ok = ok and x >= 1.0 and x < c[t + 3] - 2.0    # LoadTable.at's grid test, k = int(x) - 1 in [0, n - 4]
    if not ok:
        x = min(max(x, 1.0), c[t + 3] - 2.5)
    k = int(x) - 1
    w0, w1, w2, w3 = load_table.lagrange_weights(x - (k + 1.0))
    v = np.empty(table.shape[1])
    for j in range(table.shape[1]):
        v[j] = table[k, j] * w0 + table[k + 1, j] * w1 + table[k + 2, j] * w2 + table[k + 3, j] * w3
    v[1] *= Fz                                    # D and D_t are tabulated divided by the load
    if c[t + 4] != 0.0:
        v[4] *= Fz
    return ok or Fz <= 0.0, v


register_jitable(table_row)


def wheel_terms(c, b: int, table, pose, Oy, Oz, h, cpsi, spsi, ux, uz, alpha, speed, ops, lookup):
    """(ok, Q_psi, Q_theta, alpha_dot, Q_y, Q_z) of the wheel whose constants start at c[b]: the steps of
    :meth:`~mbs_shimmy.tyre_element.TyreElement.exact` with the load table read by ``lookup`` (as
    :func:`table_row`); ok False where a positive load is outside the table.  Generic over ``ops``
    (:mod:`mbs_shimmy.scalar_ops`) for the twin; ``c`` and ``b`` are plain numbers in every caller."""
    e = b + EL
    el = (c[e], c[e + 1], c[e + 2], c[e + 3], c[e + 4], c[e + 5], c[e + 6], c[e + 7], c[e + 8] != 0.0,
          c[e + 9] != 0.0, c[e + 10] != 0.0, c[e + 11] != 0.0, c[e + 12] != 0.0)
    s = b + STATIC
    static = (c[s], c[s + 1], c[s + 2], c[s + 3], c[s + 4], c[s + 5], c[s + 6], c[s + 7])
    s = b + SLIP
    tc = (c[s], c[s + 1], c[s + 2], c[s + 3], c[s + 4] != 0.0, c[s + 5] != 0.0)
    s = b + CAMBER
    cam = (c[s], c[s + 1], c[s + 2], c[s + 3], c[s + 4], c[s + 5], c[s + 6], c[s + 7], c[s + 8], c[s + 9])
    contact = tyre_element.wheel_contact(el[0] * el[2], pose[0], pose[3], ops[3])
    Fz, dFz, P0y = tyre_element.vertical_load(el, contact, Oy, Oz, h, cpsi, spsi)
    t = b + TABLE
    values = static
    ok = True
    if c[t] != 0.0:
        ok, v = lookup(table, c, t, Fz)
        values = tyre_element.table_values(v, static, c[t + 4] != 0.0, int(c[t + 5]), c[t + 6] != 0.0)
        # a lifted wheel (TyreElement.properties): no grip (slip_forces), a and sigma those at 1 % of the load
        lifted, choose = Fz <= 0.0, ops[5]
        values = (values[0], values[1], values[2], values[3], values[4], values[5],
                  choose(lifted, c[t + LIFTED], values[6]), choose(lifted, c[t + LIFTED + 1], values[7]))
    s = b + BRAKE + 1
    braked = c[s - 1] != 0.0
    bc = (c[s], c[s + 1], c[s + 2], c[s + 3], c[s + 4], c[s + 5], c[s + 6], c[s + 7], c[s + 8], c[s + 9], c[s + 10],
          c[s + 11], c[s + 12], c[s + 13], c[s + 14], c[s + 15], c[s + 16], c[s + 17], c[s + 18])
    Fy, mz, _, Fx = tyre_element.slip_forces(tc, cam, values, alpha, Fz, pose[3][2], c[t] != 0.0, ops, braked, bc)
    sigma = values[7]
    if braked:
        sigma = tyre.braked_relaxation_length(bc, sigma)
    r = tyre_element.contact_forces(el, contact, pose, Oy, Oz, ux, uz, Fz, dFz, P0y, Fy, mz, values[6], sigma,
                                    alpha, speed)
    q_psi, q_theta, Q_y = r[0], r[1], r[3]
    if braked:       # the brake force at the contact point, on the knuckle (TyreElement.exact)
        bp, bt, by = tyre_element.brake_forces(contact, pose, Oy, Oz, ux, uz, Fx)
        q_psi, q_theta, Q_y = q_psi + bp, q_theta + bt, Q_y + by
    return ok, q_psi, q_theta, r[2], Q_y, r[4]


register_jitable(wheel_terms)


def stage_terms(c, tables, R1, K1, R2, K2, q, qd, speed, acc, ops, lookup):
    """(ok, Q_psi, Q_theta1, Q_theta2, Q_y, Q_z, alpha1', alpha2') of :meth:`AxleForces.evaluate` less the
    alignment, from both knuckle markers' rotation matrices (9 values, row by row) and positions, the tree state
    (q, q') and the speed and acceleration (0 with a steady speed).  Generic over ``ops`` and ``lookup`` (as
    :func:`wheel_terms`): the compiled entry point (:data:`STAGE`) and the twin (:mod:`mbs_shimmy.twin`) call it."""
    sin, cos, atan, sqrt, asin, choose = ops
    ip, i1, i2, ilat, ivert = int(c[I_PSI]), int(c[I_TH1]), int(c[I_TH2]), int(c[I_LAT]), int(c[I_VERT])
    m = len(q) - 2
    psi, psid = q[ip], qd[ip]
    Oy, yd = 0.0, 0.0
    if ilat >= 0:
        Oy, yd = q[ilat], qd[ilat]
    Oz, zd = c[OZ], 0.0
    if ivert >= 0:
        Oz, zd = c[OZ] + q[ivert], qd[ivert]
    ux, uz, h = c[UX], c[UZ], c[H]
    wx, wz = psid * ux, psid * uz
    a = SPIN[0]
    p1 = knuckle.knuckle_pose(R1, K1, (c[a], c[a + 1], c[a + 2]), Oy, Oz, yd, zd, wx, wz, qd[i1])
    a = SPIN[1]
    p2 = knuckle.knuckle_pose(R2, K2, (c[a], c[a + 1], c[a + 2]), Oy, Oz, yd, zd, wx, wz, qd[i2])
    cpsi, spsi = cos(psi), sin(psi)
    r1 = wheel_terms(c, WHEELS[0], tables[0], p1, Oy, Oz, h, cpsi, spsi, ux, uz, qd[m], speed, ops, lookup)
    r2 = wheel_terms(c, WHEELS[1], tables[1], p2, Oy, Oz, h, cpsi, spsi, ux, uz, qd[m + 1], speed, ops, lookup)
    kg = c[I2] * speed / c[RADIUS]
    g1, b1 = knuckle.rotor_moment(kg, ux, uz, p1)
    g2, b2 = knuckle.rotor_moment(kg, ux, uz, p2)
    Qp, Q1, Q2 = r1[1] + r2[1] + (0.0 + g1 + g2), r1[2] + b1, r2[2] + b2
    if acc != 0.0:
        rc = (c[ARM], c[I2], c[RADIUS], c[WHEEL_MASS])
        a1 = knuckle.ramp_moments(rc, -1.0, p1, Oy, Oz, ux, uz, acc, sqrt)
        a2 = knuckle.ramp_moments(rc, 1.0, p2, Oy, Oz, ux, uz, acc, sqrt)
        Qp += a1[0] + a2[0]
        Q1 += a1[1]
        Q2 += a2[1]
    return choose(r1[0], r2[0], False), Qp, Q1, Q2, r1[4] + r2[4], r1[5] + r2[5], r1[3], r2[3]


register_jitable(stage_terms)


def _build(stamp: str):
    """The entry point, closed over ``stamp`` (the sources' hash) so that numba's cache index depends on it."""
    def stage(c, tables, R1, K1, R2, K2, q, qd, speed, acc):
        """The generalized forces and slip rates of :meth:`AxleForces.evaluate` (a new array), or None (the Python
        path must evaluate this stage), from both knuckle markers' Exudyn outputs (rotation matrix, position),
        the tree state (q, q') as tuples, the speed and the acceleration (0 with a steady speed)."""
        if len(stamp) == 0:          # never: it makes the stamp part of the compiled function (module doc)
            return None
        ops = (math.sin, math.cos, math.atan, math.sqrt, math.asin, scalar_ops.choose)
        ok, Qp, Q1, Q2, Qy, Qz, ad1, ad2 = stage_terms(c, tables, R1, K1, R2, K2, q, qd, speed, acc, ops, table_row)
        if not ok:
            return None
        m = len(q) - 2
        ip, i1, i2, ilat, ivert = int(c[I_PSI]), int(c[I_TH1]), int(c[I_TH2]), int(c[I_LAT]), int(c[I_VERT])
        out = c[ALIGNMENT:ALIGNMENT + m + 2].copy()
        out[ip] += Qp
        out[i1] += Q1
        out[i2] += Q2
        if ilat >= 0:
            out[ilat] += Qy
        if ivert >= 0:
            out[ivert] += Qz
        out[m] = ad1
        out[m + 1] = ad2
        return out
    return numba.njit(cache=True)(stage)


def sources_stamp() -> str:
    """Hash of the sources the compiled stage is built from."""
    digest = hashlib.sha256()
    for module in _SOURCES:
        with open(module.__file__, "rb") as fh:
            digest.update(fh.read())
    return digest.hexdigest()


STAGE = _build(sources_stamp())
