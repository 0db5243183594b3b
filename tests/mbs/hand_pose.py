"""An independent wheel pose for hand derivations (no code of the model): the axle rolled by psi about x through
O = (0, 0, R + h), the knuckle steered by theta about the kingpin e through K = (0, s (L/2 - l), R) (caster gamma,
inclination kpi); the wheel centre C = K + R_k (0, s l, 0), spin axis s = R_k (0, 1, 0), R_k the rotation by theta
about e; the contact point the wheel plane's lowest point P = C + rho d, d = (-z + (z.s) s) / |...|, rho = C_z / |d_z|
(the loaded radius); the heading s x z, unit."""

import math
from dataclasses import dataclass

import numpy as np


def rot(axis, angle):
    a = np.asarray(axis, dtype=float)
    K = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + math.sin(angle) * K + (1 - math.cos(angle)) * K @ K


@dataclass(frozen=True)
class WheelPose:
    O: np.ndarray           # the roll axis' point
    e: np.ndarray           # the kingpin's direction
    K: np.ndarray           # the kingpin's point
    C: np.ndarray           # the wheel centre
    s: np.ndarray           # the spin axis
    contact: np.ndarray     # the contact point P
    rho: float              # the loaded radius
    heading: np.ndarray     # s x z, unit


def wheel_pose(P, side: float, theta: float, psi: float, kpi: float, h: float = 0.0) -> WheelPose:
    O = np.array([0.0, 0.0, P.R + h])
    Rx = rot([1.0, 0.0, 0.0], psi)
    e = np.array([-math.tan(P.gamma), -side * math.tan(kpi), 1.0])
    e = Rx @ (e / np.linalg.norm(e))
    K = O + Rx @ (np.array([0.0, side * (0.5 * P.L - P.l), P.R]) - O)
    Rk = rot(e, theta) @ Rx
    C = K + Rk @ np.array([0.0, side * P.l, 0.0])
    s = Rk @ np.array([0.0, 1.0, 0.0])
    d = -np.array([0.0, 0.0, 1.0]) + s[2] * s
    d /= np.linalg.norm(d)
    rho = C[2] / -d[2]
    heading = np.cross(s, [0.0, 0.0, 1.0])
    return WheelPose(O, e, K, C, s, C + rho * d, float(rho), heading / np.linalg.norm(heading))
