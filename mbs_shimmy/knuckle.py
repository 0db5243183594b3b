"""One knuckle of the exact kinematics, from Exudyn's outputs: its pose, its wheel's rotor moment and spin-up.

Plain functions of floats and tuples with :mod:`math`: :class:`mbs_shimmy.forces.AxleForces` calls them, and the
compiled solver stage (:mod:`mbs_shimmy.compiled_stage`) compiles the same functions.
"""

from __future__ import annotations

from mbs_shimmy.tyre_element import wheel_contact


def knuckle_pose(Rm, K, spin: tuple, Oy: float, Oz: float, yd: float, zd: float, wx: float, wz: float,
                 thd: float) -> tuple:
    """(K, v_K, e, s, omega) of one knuckle (:meth:`~mbs_shimmy.forces.AxleForces.knuckle_poses`) from Exudyn's
    outputs: the rotation matrix ``Rm`` (9 values, row by row) and kingpin point ``K`` of its marker, the spin
    axis ``spin`` in the joint frame, the roll axis's point O = (0, Oy, Oz) and the rates (lateral y', bounce z',
    psi' u = (wx, 0, wz), the knuckle's theta')."""
    a, b, c = spin
    e = (Rm[2], Rm[5], Rm[8])
    ry, rz = K[1] - Oy, K[2] - Oz
    return ((K[0], K[1], K[2]), (-wz * ry, yd + wz * K[0] - wx * rz, zd + wx * ry), e,
            (Rm[0] * a + Rm[1] * b + Rm[2] * c, Rm[3] * a + Rm[4] * b + Rm[5] * c, Rm[6] * a + Rm[7] * b + Rm[8] * c),
            (wx + thd * e[0], thd * e[1], wz + thd * e[2]))


def rotor_moment(kg: float, ux: float, uz: float, pose: tuple) -> tuple[float, float]:
    """(Q_psi, Q_theta) of one wheel's spin: the moment -I2 Omega (omega x s) (``kg`` = I2 Omega), its component
    along the roll axis u = (ux, 0, uz) on psi and along the kingpin axis e on theta."""
    e, s, w = pose[2], pose[3], pose[4]
    Mx = -kg * (w[1] * s[2] - w[2] * s[1])
    My = -kg * (w[2] * s[0] - w[0] * s[2])
    Mz = -kg * (w[0] * s[1] - w[1] * s[0])
    return ux * Mx + uz * Mz, e[0] * Mx + e[1] * My + e[2] * Mz


def ramp_moments(rc: tuple, side: float, pose: tuple, Oy: float, Oz: float, ux: float, uz: float,
                 acc: float, sqrt) -> tuple[float, float]:
    """(Q_psi, Q_theta) of one wheel's spin-up by the road: force -I2 Omega'/|P - C| along the heading at P with
    the reaction -I2 Omega' s on the knuckle, which together are that force moved to the wheel centre C; plus the
    d'Alembert force -m_w dV/dt at C.  Both act at C along the heading / x.  ``rc`` = (l, I2, R, m_w);
    ``sqrt`` from :mod:`mbs_shimmy.scalar_ops`."""
    l, I2, R, wheel_mass = rc
    K, e, s = pose[0], pose[2], pose[3]
    sx, sy, sz = s
    Cx, Cy, Cz, _, _, depth, cphi = wheel_contact(side * l, K, s, sqrt)
    fs = -I2 * (acc / R) / depth
    Fx, Fy = fs * sy / cphi - wheel_mass * acc, -fs * sx / cphi
    ex, ey, ez = e
    rx, ry, rz = Cx - K[0], Cy - K[1], Cz - K[2]
    # F has no vertical component; about the roll axis u = (ux, 0, uz) through O = (0, Oy, Oz)
    q_psi = ux * (-(Cz - Oz) * Fy) + uz * (Cx * Fy - (Cy - Oy) * Fx)
    q_theta = ex * (-rz * Fy) + ey * (rz * Fx) + ez * (rx * Fy - ry * Fx)
    return q_psi, q_theta
