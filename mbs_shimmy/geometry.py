"""Geometry of the multibody axle: constant vectors, exact forward kinematics and its first-order form.

Frame: the vehicle frame, moving with the speed V along x; origin on the road below the axle centre, x forward, y
left, z up (the paper's o-xyz, section 2).  Generalized coordinates of the kinematic tree: ``q = (psi, theta1,
theta2)``: axle roll about the x-axis through O = (0, 0, R) (wheel-centre height), then each knuckle about its
kingpin, which lies in the wheel's x-z plane at lateral distance l inboard of the wheel centre and is tilted
rearward at the top by the caster angle gamma (Table 1; Figure 1 of the paper).  Wheel 1 is the right wheel
(side s = -1), wheel 2 the left (s = +1), as in the reduced model.

Everything here is plain Python floats on 3-tuples: these functions run inside the Exudyn user functions, where
numpy's per-call overhead on 3-vectors would cost more than the arithmetic.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

from reduced_model.parameters import ShimmyParameters

from .dimensions import AxleDimensions

Vec = tuple[float, float, float]
SIDES = (-1.0, 1.0)   # wheel 1 (right), wheel 2 (left)


def add(a: Vec, b: Vec) -> Vec:
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


def scale(k: float, a: Vec) -> Vec:
    return (k * a[0], k * a[1], k * a[2])


def dot(a: Vec, b: Vec) -> float:
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def cross(a: Vec, b: Vec) -> Vec:
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


@dataclass(frozen=True)
class AxleGeometry:
    """Constant vectors of the axle (SI, vehicle frame at straight running).

    ``exact`` selects the caster terms: sin(gamma), cos(gamma) (exact) or gamma, 1 (the reduced model's
    linearisation).  Body vectors of the knuckles are given in the axle frame at theta = 0 relative to the
    kingpin point K.
    """

    R: float
    L: float
    l: float
    gamma: float
    exact: bool
    tie_rod_arm: float
    drag_link_arm: float
    drag_link_length: float

    @classmethod
    def build(cls, params: ShimmyParameters, dims: AxleDimensions, exact: bool) -> "AxleGeometry":
        return cls(R=params.R, L=params.L, l=params.l, gamma=params.gamma, exact=exact,
                   tie_rod_arm=dims.tie_rod_arm, drag_link_arm=dims.drag_link_arm,
                   drag_link_length=dims.drag_link_length)

    @cached_property
    def sin_gamma(self) -> float:
        return math.sin(self.gamma) if self.exact else self.gamma

    @cached_property
    def cos_gamma(self) -> float:
        return math.cos(self.gamma) if self.exact else 1.0

    @property
    def origin(self) -> Vec:
        """O: the roll axis passes through it along x."""
        return (0.0, 0.0, self.R)

    @cached_property
    def kingpin_axis(self) -> Vec:
        """Kingpin direction in the axle frame: tilted rearward at the top by the caster angle."""
        return (-self.sin_gamma, 0.0, self.cos_gamma)

    def kingpin_point(self, side: float) -> Vec:
        """K relative to O (axle frame): at wheel-centre height, l inboard of the wheel centre plane."""
        return (0.0, side * (0.5 * self.L - self.l), 0.0)

    def wheel_centre(self, side: float) -> Vec:
        """Wheel centre relative to K; it lies on the spin axis (y) through K."""
        return (0.0, side * self.l, 0.0)

    @cached_property
    def tie_rod_arm_vector(self) -> Vec:
        """Steering arm to the tie-rod joint (both knuckles): perpendicular to the kingpin, pointing rearward."""
        return scale(-self.tie_rod_arm, (self.cos_gamma, 0.0, self.sin_gamma))

    @property
    def drag_link_arm_vector(self) -> Vec:
        """Left steering arm to the drag link, pointing inboard (-y)."""
        return (0.0, -self.drag_link_arm, 0.0)

    def drag_link_frame_point(self) -> Vec:
        """The steering-gear end of the drag link, fixed to the frame (vehicle frame, absolute)."""
        end = add(add(self.origin, self.kingpin_point(1.0)), self.drag_link_arm_vector)
        return add(end, (self.drag_link_length, 0.0, 0.0))

    def contact_point(self, side: float) -> Vec:
        """Contact point at straight running (absolute)."""
        return (0.0, side * 0.5 * self.L, 0.0)


@dataclass(frozen=True)
class KnucklePose:
    """Exact pose of one knuckle (with its non-spinning wheel) in the vehicle frame."""

    rotation: tuple[Vec, Vec, Vec]   # rows of the rotation matrix, knuckle (axle frame at theta = 0) -> vehicle
    kingpin_point: Vec               # K (absolute)
    kingpin_axis: Vec                # e (absolute)

    def vector(self, r: Vec) -> Vec:
        m = self.rotation
        return (dot(m[0], r), dot(m[1], r), dot(m[2], r))

    def point(self, r: Vec) -> Vec:
        """Absolute position of the body point r (relative to K, axle frame at theta = 0)."""
        return add(self.kingpin_point, self.vector(r))

    @property
    def spin_axis(self) -> Vec:
        m = self.rotation
        return (m[0][1], m[1][1], m[2][1])


def knuckle_frame(g: AxleGeometry, side: float, cpsi: float, spsi: float, theta: float) -> tuple:
    """Exact pose of a knuckle as a flat tuple (Ky, Kz, ex, ey, ez, R00, R01, ..., R22).

    K = (0, Ky, Kz) is the kingpin point, e the kingpin axis and R the knuckle's rotation (rows), all in the
    vehicle frame: the axle rotation Rx(psi) times the rotation by theta about the kingpin axis (Rodrigues).
    Flat floats because it runs at every solver stage; :func:`knuckle_pose` wraps it.
    """
    ex, _, ez = g.kingpin_axis
    c, s = math.cos(theta), math.sin(theta)
    v = 1.0 - c
    a00, a01, a02 = c + v * ex * ex, -s * ez, v * ex * ez
    a10, a11, a12 = s * ez, c, -s * ex
    a20, a21, a22 = v * ex * ez, s * ex, c + v * ez * ez
    ky = side * (0.5 * g.L - g.l)
    return (cpsi * ky, g.R + spsi * ky, ex, -spsi * ez, cpsi * ez,
            a00, a01, a02,
            cpsi * a10 - spsi * a20, cpsi * a11 - spsi * a21, cpsi * a12 - spsi * a22,
            spsi * a10 + cpsi * a20, spsi * a11 + cpsi * a21, spsi * a12 + cpsi * a22)


def knuckle_pose(g: AxleGeometry, side: float, cpsi: float, spsi: float, theta: float) -> KnucklePose:
    """Exact pose of a knuckle (see :func:`knuckle_frame`)."""
    f = knuckle_frame(g, side, cpsi, spsi, theta)
    return KnucklePose((f[5:8], f[8:11], f[11:14]), (0.0, f[0], f[1]), f[2:5])


@dataclass(frozen=True)
class Contact:
    """Where a wheel disc of the given pose meets the flat road z = 0."""

    point: Vec          # P: the road point on the wheel plane's line of steepest descent from the centre
    depth: float        # |P - C|: the loaded radius along the wheel plane
    heading: Vec        # x_w: wheel forward direction in the road plane
    lateral: Vec        # y_w: wheel lateral direction in the road plane


def disc_contact(centre: Vec, spin_axis: Vec) -> Contact:
    """Contact point of a disc with spin axis ``spin_axis`` (unit) and centre ``centre`` on the road z = 0.

    The line from the centre downwards in the wheel plane, d = (-z + (z.s) s) / |...|, meets the road at
    P = C + (C_z / cos(camber)) d; its length is the loaded radius (Pacejka, Tire and Vehicle Dynamics, 3rd ed.,
    2012, section 10.1, contact-point definition of the Magic-Formula tyre).
    """
    sx, sy, sz = spin_axis
    cphi2 = 1.0 - sz * sz
    cphi = math.sqrt(cphi2)
    depth = centre[2] / cphi
    k = centre[2] / cphi2
    point = (centre[0] + k * sz * sx, centre[1] + k * sz * sy, 0.0)
    return Contact(point, depth, (sy / cphi, -sx / cphi, 0.0), (sx / cphi, sy / cphi, 0.0))


def axle_rotation(psi: float) -> tuple[Vec, Vec, Vec]:
    c, s = math.cos(psi), math.sin(psi)
    return ((1.0, 0.0, 0.0), (0.0, c, -s), (0.0, s, c))


def quaternion_xyzw(m: tuple[Vec, Vec, Vec]) -> tuple[float, float, float, float]:
    """Unit quaternion (x, y, z, w) of a rotation matrix given by rows (Shepperd's method)."""
    tr = m[0][0] + m[1][1] + m[2][2]
    if tr > 0.0:
        s = math.sqrt(tr + 1.0) * 2.0
        return ((m[2][1] - m[1][2]) / s, (m[0][2] - m[2][0]) / s, (m[1][0] - m[0][1]) / s, 0.25 * s)
    if m[0][0] > m[1][1] and m[0][0] > m[2][2]:
        s = math.sqrt(1.0 + m[0][0] - m[1][1] - m[2][2]) * 2.0
        return (0.25 * s, (m[0][1] + m[1][0]) / s, (m[0][2] + m[2][0]) / s, (m[2][1] - m[1][2]) / s)
    if m[1][1] > m[2][2]:
        s = math.sqrt(1.0 + m[1][1] - m[0][0] - m[2][2]) * 2.0
        return ((m[0][1] + m[1][0]) / s, 0.25 * s, (m[1][2] + m[2][1]) / s, (m[0][2] - m[2][0]) / s)
    s = math.sqrt(1.0 + m[2][2] - m[0][0] - m[1][1]) * 2.0
    return ((m[0][2] + m[2][0]) / s, (m[1][2] + m[2][1]) / s, 0.25 * s, (m[1][0] - m[0][1]) / s)


def matmul(a: tuple[Vec, Vec, Vec], b: tuple[Vec, Vec, Vec]) -> tuple[Vec, Vec, Vec]:
    cols = ((b[0][0], b[1][0], b[2][0]), (b[0][1], b[1][1], b[2][1]), (b[0][2], b[1][2], b[2][2]))
    return tuple(tuple(dot(row, col) for col in cols) for row in a)  # type: ignore[return-value]
