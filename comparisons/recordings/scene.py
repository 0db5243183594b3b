"""The front axle as a 3D scene for display: geometry of the shapes and body poses over time.

World frame as in the paper (figure 1): x forward (driving direction), y to the left, z up; metres.  The frame
travels with the axle (the road moves under it).  Right wheel (index 1 in the paper) at y = -L/2, left wheel
(index 2, with the drag link) at y = +L/2.

Body frames (the multibody model's, ``mbs_shimmy.geometry``, so that one set of shapes fits both models):

* ``axle``: origin O on the roll axis at wheel-centre height R, axes parallel to the world at rest; the tramp
  angle psi rotates it about x.
* ``knuckle_right`` / ``knuckle_left``: origin at the kingpin point K (wheel-centre height, the offset l inboard
  of the wheel centre plane), axes those of the axle at zero steer; the yaw angle theta rotates it about the
  kingpin axis e = (-sin gamma, 0, cos gamma) (tilted rearward at the top by the caster angle).
* ``wheel_right`` / ``wheel_left``: origin at the wheel centre, y along the spin axis; the spin angle about y is
  the integral of V/R.

Pose layouts accepted in ``Trajectory.extra`` (N samples, world frame, m, N; quaternions (x, y, z, w), body to
world):

* ``extra["poses"]`` as written by :meth:`ScenePoses.to_dict`::

    {"axle": {"position": (N, 3), "quaternion": (N, 4)}, ... one entry per name in BODY_NAMES,
     "tie_rod": (N, 2, 3), "drag_link": (N, 2, 3),                   # end points
     "tyre_forces": {"points": (N, 2, 3), "vectors": (N, 2, 3)}}     # right, left

* the multibody model's ``pose_record`` layout, in ``extra["poses"]`` or directly in ``extra``::

    {"bodies": {name: {"position": (N, 3), "quaternion_xyzw": (N, 4)}},
     "links": {"tie_rod": (N, 2, 3), "drag_link": (N, 2, 3)},
     "contact": {"right" | "left": {"point": (N, 3), "force": (N, 3)}}}

  (its contact force is the tyre's whole force on the wheel, vertical load included).

The reduced model has no positions, only angles; :func:`reduced_model_poses` turns them into poses with exact
rotations (the model itself linearises them), and the tyre lateral force and trail come from
:mod:`reduced_model.tyre` through :meth:`ShimmyModel.tyres`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.spatial.transform import Rotation

from reduced_model.model import ShimmyModel
from axles.parameters import YANG2024, ShimmyParameters
from reduced_model.trajectory import Trajectory

BODY_NAMES = ("axle", "knuckle_right", "knuckle_left", "wheel_right", "wheel_left")
LINK_NAMES = ("tie_rod", "drag_link")
SIDES = ("right", "left")
_SIDE_SIGN = {"right": -1.0, "left": 1.0}   # sign of y


# --- rotations: scipy.spatial.transform.Rotation, quaternions (x, y, z, w) as Rerun wants them ------------------

def rotation_about(axis, angle) -> Rotation:
    """Rotation by ``angle`` (rad, scalar or (N,)) about the unit ``axis`` (3,)."""
    axis = np.asarray(axis, dtype=float)
    axis = axis / np.linalg.norm(axis)
    return Rotation.from_rotvec(np.multiply.outer(np.asarray(angle, dtype=float), axis))


def rotate(q: np.ndarray, v) -> np.ndarray:
    """Rotate vector(s) v by quaternion(s) q, xyzw (one of either, or N of both)."""
    return Rotation.from_quat(q).apply(v)


# --- geometry --------------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class AxleGeometry:
    """Dimensions of the displayed shapes (m).  R, L, l and gamma are the model's; the arm lengths are the
    multibody model's defaults (``axles.dimensions``), so both scenes look alike; the rest only draws."""

    R: float
    L: float
    l: float
    gamma: float
    tie_rod_arm: float = 0.2        # steering arm to the tie-rod joint, perpendicular to the kingpin, rearward
    drag_link_arm: float = 0.2      # left steering arm to the drag link, inboard
    drag_link_length: float = 0.8   # drag link, forward to the steering gear on the frame
    tyre_width: float = 0.28
    axle_section: float = 0.10
    kingpin_length: float = 0.36
    kingpin_radius: float = 0.035

    @classmethod
    def from_params(cls, params: ShimmyParameters = YANG2024) -> "AxleGeometry":
        return cls(R=params.R, L=params.L, l=params.l, gamma=params.gamma)

    @property
    def kingpin_y(self) -> float:
        """|y| of the kingpins: the wheel centre plane lies the offset l outboard of them."""
        return 0.5 * self.L - self.l

    @property
    def kingpin_axis(self) -> np.ndarray:
        """e in the knuckle (= axle at zero steer) frame: tilted rearward at the top by the caster angle."""
        return np.array([-np.sin(self.gamma), 0.0, np.cos(self.gamma)])

    @property
    def tie_rod_point(self) -> np.ndarray:
        """Tie-rod joint relative to K, knuckle frame (both sides)."""
        return -self.tie_rod_arm * np.array([np.cos(self.gamma), 0.0, np.sin(self.gamma)])

    @property
    def drag_link_point(self) -> np.ndarray:
        """Drag-link joint on the left knuckle relative to K, knuckle frame."""
        return np.array([0.0, -self.drag_link_arm, 0.0])

    @property
    def drag_link_frame_point(self) -> np.ndarray:
        """The steering-gear end of the drag link, fixed to the frame (world)."""
        return np.array([self.drag_link_length, self.kingpin_y - self.drag_link_arm, self.R])


# --- poses -----------------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class BodyPose:
    position: np.ndarray     # (N, 3), m, world
    quaternion: np.ndarray   # (N, 4), xyzw, body to world


@dataclass(frozen=True)
class ScenePoses:
    """Everything the 3D scene needs per sample."""

    bodies: dict            # name -> BodyPose, for every name in BODY_NAMES
    links: dict             # name -> (N, 2, 3) end points, for every name in LINK_NAMES
    force_points: np.ndarray   # (N, 2, 3): where the tyre lateral forces act (right, left)
    force_vectors: np.ndarray  # (N, 2, 3): the forces, N

    @property
    def n(self) -> int:
        return len(self.force_points)

    def lateral_forces(self) -> np.ndarray:
        """(N, 2) signed lateral force of the right and left tyre, N: the force vector along the wheel's
        lateral axis (the paper's F_y1, F_y2)."""
        return np.stack([np.einsum("ij,ij->i", self.force_vectors[:, k],
                                   wheel_lateral_axis(self.bodies[f"wheel_{side}"].quaternion))
                         for k, side in enumerate(SIDES)], axis=1)

    def to_dict(self) -> dict:
        out = {name: {"position": p.position, "quaternion": p.quaternion} for name, p in self.bodies.items()}
        out.update({name: self.links[name] for name in LINK_NAMES})
        out["tyre_forces"] = {"points": self.force_points, "vectors": self.force_vectors}
        return out

    @classmethod
    def from_dict(cls, poses: dict, n: int) -> "ScenePoses":
        """Read and check the pose dictionary (module docstring) for ``n`` samples."""
        def array(value, shape, what):
            a = np.asarray(value, dtype=float)
            if a.shape != shape:
                raise ValueError(f"poses: {what} must have shape {shape}, got {a.shape}")
            if not np.all(np.isfinite(a)):
                raise ValueError(f"poses: {what} holds non-finite values")
            return a

        if "bodies" in poses:   # the multibody model's pose_record layout
            poses = _from_pose_record(poses)
        missing = [k for k in (*BODY_NAMES, *LINK_NAMES, "tyre_forces") if k not in poses]
        if missing:
            raise ValueError(f"poses: missing {', '.join(missing)}")
        bodies = {}
        for name in BODY_NAMES:
            entry = poses[name]
            pos, quat = (entry["position"], entry["quaternion"]) if isinstance(entry, dict) else entry
            bodies[name] = BodyPose(array(pos, (n, 3), f"{name} position"),
                                    array(quat, (n, 4), f"{name} quaternion"))
        links = {name: array(poses[name], (n, 2, 3), name) for name in LINK_NAMES}
        forces = poses["tyre_forces"]
        return cls(bodies=bodies, links=links,
                   force_points=array(forces["points"], (n, 2, 3), "tyre force points"),
                   force_vectors=array(forces["vectors"], (n, 2, 3), "tyre force vectors"))


def _from_pose_record(record: dict) -> dict:
    """The multibody model's layout (module docstring) in this module's layout."""
    try:
        out = {name: {"position": b["position"], "quaternion": b.get("quaternion_xyzw", b.get("quaternion"))}
               for name, b in record["bodies"].items()}
        out.update({name: record["links"][name] for name in LINK_NAMES if name in record["links"]})
        contact = record["contact"]
        out["tyre_forces"] = {"points": np.stack([np.asarray(contact[s]["point"]) for s in SIDES], axis=1),
                              "vectors": np.stack([np.asarray(contact[s]["force"]) for s in SIDES], axis=1)}
    except (KeyError, TypeError, ValueError) as exc:
        raise ValueError(f"poses: the multibody pose record is malformed ({exc!r})") from None
    return out


def wheel_lateral_axis(quaternion: np.ndarray) -> np.ndarray:
    """The wheel's spin axis (its y) laid flat on the road and normalised: the direction of +F_y."""
    axis = rotate(quaternion, [0.0, 1.0, 0.0])
    axis[..., 2] = 0.0
    return axis / np.linalg.norm(axis, axis=-1, keepdims=True)


def spin_angle(t: np.ndarray, speed: np.ndarray, R: float) -> np.ndarray:
    """Wheel spin angle (rad) by the trapezoidal rule on V/R, zero at the first sample."""
    rate = np.asarray(speed, dtype=float) / R
    steps = 0.5 * (rate[1:] + rate[:-1]) * np.diff(t)
    return np.concatenate([[0.0], np.cumsum(steps)])


def reduced_model_poses(trajectory: Trajectory, model: ShimmyModel, pressures,
                        geometry: AxleGeometry | None = None) -> ScenePoses:
    """Body poses from the reduced model's angles theta1 (right), theta2 (left), psi, and the tyre forces
    from its slip angles at the tyres' ``pressures``."""
    g = geometry or AxleGeometry.from_params(model.params)
    n = len(trajectory.t)
    theta = {"right": trajectory.state("theta1"), "left": trajectory.state("theta2")}
    alpha = {"right": trajectory.state("alpha1"), "left": trajectory.state("alpha2")}
    psi = trajectory.state("psi")
    phi = spin_angle(trajectory.t, trajectory.speed, g.R)

    axle_pos = np.tile([0.0, 0.0, g.R], (n, 1))
    axle_r = rotation_about([1.0, 0.0, 0.0], psi)
    bodies = {"axle": BodyPose(axle_pos, axle_r.as_quat())}
    knuckles = {}
    wheel_tyres = dict(zip(SIDES, model.tyres(pressures)))
    points = np.zeros((n, 2, 3))
    vectors = np.zeros((n, 2, 3))
    for k, side in enumerate(SIDES):
        s = _SIDE_SIGN[side]
        kr = axle_r * rotation_about(g.kingpin_axis, theta[side])   # apply the steer first, then the tramp
        kp = axle_pos + axle_r.apply([0.0, s * g.kingpin_y, 0.0])
        wq = (kr * rotation_about([0.0, 1.0, 0.0], phi)).as_quat()
        wp = kp + kr.apply([0.0, s * g.l, 0.0])
        kq = kr.as_quat()
        knuckles[side] = BodyPose(kp, kq)
        bodies[f"knuckle_{side}"] = knuckles[side]
        bodies[f"wheel_{side}"] = BodyPose(wp, wq)
        # The lateral force acts on the ground a pneumatic trail behind the contact centre, across the wheel's
        # heading; +F_y along the wheel's lateral axis (the sign of eqs. 2.1-2.3).
        lateral = wheel_lateral_axis(wq)
        heading = np.cross(lateral, [0.0, 0.0, 1.0])
        wt = wheel_tyres[side]
        fy = np.asarray(wt.force.force(alpha[side]), dtype=float)
        trail = np.broadcast_to(np.asarray(wt.trail_at(alpha[side]), dtype=float), (n,))
        contact = wp.copy()
        contact[:, 2] = 0.0
        points[:, k] = contact - trail[:, None] * heading
        vectors[:, k] = fy[:, None] * lateral
    left = knuckles["left"]
    links = {
        "tie_rod": np.stack([knuckles[side].position + rotate(knuckles[side].quaternion, g.tie_rod_point)
                             for side in SIDES], axis=1),
        "drag_link": np.stack([left.position + rotate(left.quaternion, g.drag_link_point),
                               np.tile(g.drag_link_frame_point, (n, 1))], axis=1),
    }
    return ScenePoses(bodies=bodies, links=links, force_points=points, force_vectors=vectors)


def trajectory_poses(trajectory: Trajectory, model: ShimmyModel | None = None, pressures=None,
                     geometry: AxleGeometry | None = None) -> ScenePoses:
    """The poses stored with the trajectory (multibody model: ``extra["poses"]`` or the pose record in ``extra``)
    or else computed from the reduced model's angles, which needs the ``pressures`` (argument or
    ``extra["pressures"]``, Pa)."""
    extra = trajectory.extra or {}
    stored = extra.get("poses", extra if "bodies" in extra else None)
    if stored is not None:
        return ScenePoses.from_dict(stored, len(trajectory.t))
    if pressures is None:
        pressures = extra.get("pressures")
    if pressures is None:
        raise ValueError("the trajectory has no stored poses: the tyre pressures are needed to compute the tyre "
                         "forces (pass pressures=TyrePressures)")
    return reduced_model_poses(trajectory, model or ShimmyModel(), pressures, geometry)
