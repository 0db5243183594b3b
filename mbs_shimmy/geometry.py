"""Geometry of the multibody axle: the constant vectors at straight running that the Exudyn tree is built from.

Frame: the vehicle frame, moving with the speed V along x; origin on the road below the axle centre, x forward, y
left, z up (the paper's o-xyz, section 2).  The axle rolls about an x-axis h above the wheel centres (h = 0 in the
paper), each knuckle turns about its kingpin, which passes at wheel-centre height l inboard of the wheel centre and
is tilted rearward at the top by the caster angle gamma (Table 1; Figure 1 of the paper) and inward by the kingpin
inclination.  Wheel 1 is the right wheel (side s = -1), wheel 2 the left (s = +1), as in the reduced model.  The
poses at any state are Exudyn's (:mod:`mbs_shimmy.system`); this module only gives the straight-running vectors
the tree and its markers are built from, and the disc-road contact.

Everything here is plain Python floats on 3-tuples: these functions run inside the Exudyn user functions, where
numpy's per-call overhead on 3-vectors would cost more than the arithmetic.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from axles.dimensions import AxleDimensions
from mbs_shimmy.fidelity import Assumption, Fidelity
from axles.parameters import ShimmyParameters

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


def unit(a: Vec) -> Vec:
    return scale(1.0 / math.sqrt(dot(a, a)), a)


def perpendicular(d: Vec, e: Vec) -> Vec:
    """The unit vector of d's component perpendicular to the unit vector e."""
    return unit(add(d, scale(-dot(d, e), e)))


@dataclass(frozen=True)
class AxleGeometry:
    """Constant vectors of the axle at straight running (SI, vehicle frame; what the Exudyn tree is built from).

    ``exact`` selects the caster terms: sin(gamma), cos(gamma) (exact) or gamma, 1 (the reduced model's
    linearisation).  The fidelity switches of the new geometry set their element to its neutral value here
    (kingpin inclination 0, roll axis at wheel-centre height, parallel arms, level drag link to the frame).
    Vectors of a knuckle are given in the axle frame at theta = 0 relative to its kingpin point K.
    Nothing here moves: the poses at any state are Exudyn's (:mod:`mbs_shimmy.system`).
    """

    R: float
    L: float
    l: float
    gamma: float
    exact: bool
    tie_rod_arm: float
    drag_link_arm: float
    drag_link_length: float
    kingpin_inclination: float = 0.0
    steering_arm_angle: float = 0.0
    roll_height: float = 0.0           # roll axis above the wheel centres
    drag_link_inclination: float = 0.0
    pitman_arm: float = 0.0            # 0: the drag link ends on a frame point (rigid gear)
    roll_steer: float = 0.0            # axle yaw per unit of roll: the roll axis slopes by atan(roll_steer)

    @classmethod
    def build(cls, params: ShimmyParameters, dims: AxleDimensions, exact: bool,
              fidelity: Fidelity | None = None) -> "AxleGeometry":
        on = (lambda a: fidelity is None or a in fidelity)
        gear = not on(Assumption.RIGID_STEERING_GEAR)
        return cls(R=params.R, L=params.L, l=params.l, gamma=params.gamma, exact=exact,
                   tie_rod_arm=dims.tie_rod_arm, drag_link_arm=dims.drag_link_arm,
                   drag_link_length=dims.drag_link_length,
                   kingpin_inclination=0.0 if on(Assumption.NO_KINGPIN_INCLINATION) else dims.kingpin_inclination,
                   steering_arm_angle=0.0 if on(Assumption.PARALLEL_STEERING_ARMS) else dims.steering_arm_angle,
                   roll_height=0.0 if on(Assumption.ROLL_AXIS_AT_WHEEL_CENTRE) else dims.roll_axis_above_wheel_centre,
                   drag_link_inclination=dims.drag_link_inclination if gear else 0.0,
                   pitman_arm=dims.pitman_arm if gear else 0.0,
                   roll_steer=0.0 if on(Assumption.NO_AXLE_ROLL_STEER) else dims.axle_roll_steer)

    @cached_property
    def sin_gamma(self) -> float:
        return math.sin(self.gamma) if self.exact else self.gamma

    @cached_property
    def cos_gamma(self) -> float:
        return math.cos(self.gamma) if self.exact else 1.0

    @property
    def origin(self) -> Vec:
        """O: the roll axis passes through it along x."""
        return (0.0, 0.0, self.R + self.roll_height)

    @cached_property
    def roll_axis(self) -> Vec:
        """u: the axle's roll axis through O, sloped up at the front by atan(roll_steer) in side view, so that a
        roll psi about it is a roll psi cos(beta) about x and a yaw psi sin(beta) about z (exactly (1, 0, 0)
        without roll steer)."""
        if self.roll_steer == 0.0:
            return (1.0, 0.0, 0.0)
        return unit((1.0, 0.0, self.roll_steer))

    @cached_property
    def roll_joint_rotation(self) -> tuple[Vec, Vec, Vec]:
        """Rows of the roll joint's frame -> vehicle frame: its x-axis is :attr:`roll_axis` (Ry(-beta))."""
        ux, _, uz = self.roll_axis
        return ((ux, 0.0, -uz), (0.0, 1.0, 0.0), (uz, 0.0, ux))

    def kingpin_axis_of(self, side: float) -> Vec:
        """Kingpin direction (axle frame): tilted rearward at the top by the caster angle and inward by the
        kingpin inclination (both as seen in side and front view)."""
        if not self.exact:
            return (-self.sin_gamma, 0.0, self.cos_gamma)
        return unit((-math.tan(self.gamma), -side * math.tan(self.kingpin_inclination), 1.0))

    @cached_property
    def kingpin_axis(self) -> Vec:
        """Kingpin direction of the left wheel (both, without kingpin inclination)."""
        return self.kingpin_axis_of(1.0)

    def joint_rotation(self, side: float) -> tuple[Vec, Vec, Vec]:
        """Rows of the rotation joint frame -> axle frame whose z-axis is the kingpin axis (for no inclination
        exactly Ry(-gamma))."""
        e = self.kingpin_axis_of(side)
        t1 = perpendicular((1.0, 0.0, 0.0), e)
        t2 = cross(e, t1)
        return ((t1[0], t2[0], e[0]), (t1[1], t2[1], e[1]), (t1[2], t2[2], e[2]))

    def kingpin_point(self, side: float) -> Vec:
        """K relative to the wheel-centre line (0, 0, R): at wheel-centre height, l inboard of the wheel centre
        (the hub offset; the scrub radius at the road is l - R tan(inclination))."""
        return (0.0, side * (0.5 * self.L - self.l), 0.0)

    @property
    def scrub_radius(self) -> float:
        return self.l - self.R * math.tan(self.kingpin_inclination)

    def wheel_centre(self, side: float) -> Vec:
        """Wheel centre relative to K; it lies on the spin axis (y) through K."""
        return (0.0, side * self.l, 0.0)

    def tie_rod_arm_vector_of(self, side: float) -> Vec:
        """Steering arm to the tie-rod joint: rearward, turned inward by the steering-arm angle (Ackermann),
        perpendicular to the kingpin."""
        if not self.exact:
            return scale(-self.tie_rod_arm, (self.cos_gamma, 0.0, self.sin_gamma))
        b = self.steering_arm_angle
        d = (-math.cos(b), -side * math.sin(b), 0.0)
        return scale(self.tie_rod_arm, perpendicular(d, self.kingpin_axis_of(side)))

    @cached_property
    def tie_rod_arm_vector(self) -> Vec:
        return self.tie_rod_arm_vector_of(1.0)

    @cached_property
    def drag_link_arm_vector(self) -> Vec:
        """Left steering arm to the drag link, pointing inboard, perpendicular to the kingpin."""
        if not self.exact:
            return (0.0, -self.drag_link_arm, 0.0)
        return scale(self.drag_link_arm, perpendicular((0.0, -1.0, 0.0), self.kingpin_axis_of(1.0)))

    def absolute(self, side: float, r: Vec) -> Vec:
        """Absolute position at straight running of the knuckle point r (relative to K)."""
        return add(add((0.0, 0.0, self.R), self.kingpin_point(side)), r)

    def drag_link_frame_point(self) -> Vec:
        """The gear end of the drag link at straight running (absolute): the Pitman-arm ball, or the fixed frame
        point of the rigid gear; the drag link rises towards it by its inclination."""
        end = self.absolute(1.0, self.drag_link_arm_vector)
        c, s = math.cos(self.drag_link_inclination), math.sin(self.drag_link_inclination)
        return add(end, (self.drag_link_length * c, 0.0, self.drag_link_length * s))

    def gear_shaft_point(self) -> Vec:
        """The steering gear's output shaft (axis y), the Pitman arm hanging down from it to the ball."""
        return add(self.drag_link_frame_point(), (0.0, 0.0, self.pitman_arm))

    def contact_point(self, side: float) -> Vec:
        """Contact point at straight running (absolute)."""
        return (0.0, side * 0.5 * self.L, 0.0)


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


def quaternions_xyzw(m: np.ndarray) -> np.ndarray:
    """Unit quaternions (x, y, z, w), shape (N, 4), of rotation matrices m, shape (N, 3, 3) (Shepperd's method:
    each matrix by the largest of its trace and diagonal, so that the square root never nears zero)."""
    m = np.asarray(m, dtype=float)
    m00, m11, m22 = m[:, 0, 0], m[:, 1, 1], m[:, 2, 2]
    tr = m00 + m11 + m22
    with np.errstate(invalid="ignore", divide="ignore"):   # the branches not taken
        s0 = np.sqrt(tr + 1.0) * 2.0
        s1 = np.sqrt(1.0 + m00 - m11 - m22) * 2.0
        s2 = np.sqrt(1.0 + m11 - m00 - m22) * 2.0
        s3 = np.sqrt(1.0 + m22 - m00 - m11) * 2.0
        a, b, c = m[:, 2, 1] - m[:, 1, 2], m[:, 0, 2] - m[:, 2, 0], m[:, 1, 0] - m[:, 0, 1]
        d, e, f = m[:, 0, 1] + m[:, 1, 0], m[:, 0, 2] + m[:, 2, 0], m[:, 1, 2] + m[:, 2, 1]
        forms = (np.stack([a / s0, b / s0, c / s0, 0.25 * s0], axis=1),
                 np.stack([0.25 * s1, d / s1, e / s1, a / s1], axis=1),
                 np.stack([d / s2, 0.25 * s2, f / s2, b / s2], axis=1),
                 np.stack([e / s3, f / s3, 0.25 * s3, c / s3], axis=1))
    first = tr > 0.0
    second = ~first & (m00 > m11) & (m00 > m22)
    third = ~first & ~second & (m11 > m22)
    pick = np.where(first, 0, np.where(second, 1, np.where(third, 2, 3)))
    return np.stack(forms)[pick, np.arange(len(m))]