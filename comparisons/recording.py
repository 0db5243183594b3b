"""Rerun recordings (.rrd) of simulations: 3D scene, every state, speed, detected mode and mode switches.

One recording per trajectory, on the timeline ``sim_time`` (simulated time, integer nanoseconds).  Entities:

* ``/scene/<body>`` for each body of :data:`comparisons.scene.BODY_NAMES`: a time-varying Transform3D (pose,
  world frame x forward, y left, z up, m); the shapes are static children (``/scene/<body>/shape`` ...) and move
  with it.  ``/scene/tie_rod`` and ``/scene/drag_link``: line strips between their end points.
  ``/scene/tyre_forces``: the tyre lateral forces as arrows at their points of action, drawn
  :data:`FORCE_ARROW_M_PER_N` m long per N.
* ``/states/<state>_<unit>``: every state of the reduced model's state vector, angles in degrees and rates in
  degrees per second (the project's interface units; the simulation is SI inside): e.g. ``/states/theta1_deg``,
  ``/states/psi_dot_deg_per_s``.  ``/tyre_forces/right_N`` and ``/tyre_forces/left_N``: the forces, N.
* ``/speed_kmh``: the speed.
* ``/mode``: the detected mode as a state lane (``rr.StateChange``, one row per change, shown by a
  StateTimelineView); ``/events``: one ``rr.TextLog`` per mode switch at its time; a warning at the end if the
  simulation did not complete.
* ``/info``: a static text document with the title, the model, the integrator and the units.

The stored default blueprint opens the 3D view beside the time series, the speed, the mode lane and the events.
The file is written under a temporary name in the target folder, read back, and renamed only when complete:
a failure, a full disk or an interrupt never leaves a truncated recording under the final name.
"""

from __future__ import annotations

import enum
import numbers
import os
import uuid
from dataclasses import dataclass
from typing import Sequence

import numpy as np

from reduced_model.model import STATE_NAMES, STATE_UNITS, ShimmyModel
from reduced_model.trajectory import Trajectory

from .files import atomic_path, run_writer
from .scene import BODY_NAMES, SIDES, AxleGeometry, ScenePoses, quaternion_about, trajectory_poses

APP_ID = "shimmy"
TIMELINE = "sim_time"
FORCE_ARROW_M_PER_N = 1e-4      # a 5 kN force is drawn 0.5 m long
_UNIT_SUFFIX = {"rad": ("deg", np.degrees), "rad/s": ("deg_per_s", np.degrees)}
STATE_ENTITIES = {name: f"/states/{name}_{_UNIT_SUFFIX[unit][0]}" for name, unit in zip(STATE_NAMES, STATE_UNITS)}
SPEED_ENTITY = "/speed_kmh"
MODE_ENTITY = "/mode"
EVENTS_ENTITY = "/events"
FORCE_ENTITIES = {side: f"/tyre_forces/{side}_N" for side in SIDES}
SCENE_ENTITIES = tuple(f"/scene/{name}" for name in BODY_NAMES) + ("/scene/tie_rod", "/scene/drag_link",
                                                                    "/scene/tyre_forces")
_MODE_COLOURS = (0x4C72B0FF, 0xDD8452FF, 0x55A868FF, 0xC44E52FF, 0x8172B3FF, 0x937860FF, 0xDA8BC3FF)


class RecordingError(OSError):
    """The recording cannot be written where asked; the message says why in one line."""


@dataclass(frozen=True)
class ModeSwitch:
    time: float       # s
    before: str
    after: str


@dataclass(frozen=True)
class RecordingSummary:
    path: str
    recording_id: str
    samples: int
    mode_changes: int
    switches: int


def time_ns(t) -> np.ndarray:
    """Simulated time as integer nanoseconds (rounded: float durations would be truncated by Rerun)."""
    return np.round(np.asarray(t, dtype=float) * 1e9).astype(np.int64)


def mode_label(mode) -> str:
    """A mode as text: enums by value (or name), anything else by str()."""
    if isinstance(mode, enum.Enum):
        return mode.value if isinstance(mode.value, str) else mode.name
    return str(mode)


def _is_pair(item) -> bool:
    return (isinstance(item, (tuple, list)) and len(item) == 2 and isinstance(item[0], numbers.Real)
            and not isinstance(item[0], bool))


def mode_segments(modes, t: np.ndarray) -> list[tuple[float, str]]:
    """(start time s, label) per segment, from one label per sample (length N; str or enum) or from
    (start time s, label) pairs."""
    if modes is None:
        return []
    modes = list(modes)
    if modes and all(_is_pair(m) for m in modes):
        segments = [(float(start), mode_label(label)) for start, label in modes]
        times = [s for s, _ in segments]
        if any(b < a for a, b in zip(times, times[1:])):
            raise ValueError("mode segments must be in time order")
        _check_times(times, t, "mode segment")
        return [seg for i, seg in enumerate(segments) if i == 0 or seg[1] != segments[i - 1][1]]
    if len(modes) != len(t):
        raise ValueError(f"modes must be one label per sample ({len(t)}) or (time_s, label) pairs, "
                         f"got {len(modes)} labels")
    labels = [mode_label(m) for m in modes]
    return [(float(t[i]), labels[i]) for i in range(len(labels)) if i == 0 or labels[i] != labels[i - 1]]


def _check_times(times, t: np.ndarray, what: str) -> None:
    for x in times:
        if not (np.isfinite(x) and t[0] - 1e-12 <= x <= t[-1] + 1e-12):
            raise ValueError(f"{what} at {x} s lies outside the trajectory's {t[0]:g}-{t[-1]:g} s")


def mode_switches(switches, t: np.ndarray) -> list[ModeSwitch]:
    """(time s, from, to) triples, or objects with ``time``, ``before`` and ``after`` (labels str or enum)."""
    out = []
    for s in switches or ():
        if all(hasattr(s, a) for a in ("time", "before", "after")):
            out.append(ModeSwitch(float(s.time), mode_label(s.before), mode_label(s.after)))
        else:
            out.append(ModeSwitch(float(s[0]), mode_label(s[1]), mode_label(s[2])))
    _check_times([s.time for s in out], t, "mode switch")
    return out


def default_blueprint():
    import rerun.blueprint as rrb
    angles = [STATE_ENTITIES[n] for n in ("theta1", "theta2", "psi")]
    slips = [STATE_ENTITIES[n] for n in ("alpha1", "alpha2")]
    rates = [STATE_ENTITIES[n] for n in ("theta1_dot", "theta2_dot", "psi_dot")]
    return rrb.Blueprint(
        rrb.Horizontal(
            rrb.Spatial3DView(origin="/scene", name="front axle"),
            rrb.Vertical(
                rrb.Tabs(
                    rrb.TimeSeriesView(origin="/states", contents=angles, name="yaw and tramp angles [deg]"),
                    rrb.TimeSeriesView(origin="/states", contents=slips, name="slip angles [deg]"),
                    rrb.TimeSeriesView(origin="/states", contents=rates, name="angular rates [deg/s]"),
                    rrb.TimeSeriesView(origin="/tyre_forces", name="tyre lateral forces [N]"),
                ),
                rrb.TimeSeriesView(origin=SPEED_ENTITY, name="speed [km/h]"),
                rrb.StateTimelineView(origin=MODE_ENTITY, name="mode"),
                rrb.TextLogView(origin=EVENTS_ENTITY, name="mode switches"),
                row_shares=[4, 2, 1, 2],
            ),
            column_shares=[1, 1],
        ),
        rrb.TimePanel(timeline=TIMELINE, expanded=True),
        collapse_panels=True,
    )


def write_recording(path: str, trajectory: Trajectory, modes=None, switches: Sequence = (), title: str = "", *,
                    model: ShimmyModel | None = None, pressure=None, geometry: AxleGeometry | None = None,
                    recording_id: str | None = None) -> RecordingSummary:
    """Write one .rrd recording of ``trajectory`` to ``path`` atomically.

    ``modes``: None, one label per sample, or (start time s, label) pairs (labels str or enum).  ``switches``:
    (time s, from, to) triples or objects with ``time``, ``before``, ``after`` (such as :class:`ModeSwitch`).  The 3D poses come from ``trajectory.extra["poses"]`` when present
    (multibody model), else from the reduced model's angles, for which ``pressure`` (Pa; or
    ``extra["pressure"]``) and ``model`` (default: the section 3 model) give the tyre forces.
    ``recording_id``: default a fresh UUID, so that recordings opened together never merge.
    Raises :class:`RecordingError` when the file cannot be written, ValueError on inconsistent input.
    """
    final = os.path.abspath(path)
    folder = os.path.dirname(final)
    if os.path.isdir(final):
        raise RecordingError(f"cannot write the recording {path}: a directory is in the way")
    if not os.path.isdir(folder):
        raise RecordingError(f"cannot write the recording {path}: the folder {folder} does not exist")
    # Everything that can fail on the input fails here, before a byte is written.
    t = np.asarray(trajectory.t, dtype=float)
    if len(t) < 2 or np.any(np.diff(t) <= 0.0):
        raise ValueError("the trajectory needs at least two samples at increasing times")
    poses = trajectory_poses(trajectory, model, pressure, geometry)
    segments = mode_segments(modes, t)
    events = mode_switches(switches, t)
    geometry = geometry or AxleGeometry.from_params((model or ShimmyModel()).params)
    recording_id = recording_id or str(uuid.uuid4())
    try:
        with atomic_path(final) as tmp:
            run_writer(_write, tmp, trajectory, poses, segments, events, title, geometry, recording_id)
            _check_written(tmp, len(t), path)
    except RecordingError:
        raise
    except OSError as exc:
        raise RecordingError(f"cannot write the recording {path}: {exc.strerror or exc}") from None
    return RecordingSummary(path=final, recording_id=recording_id, samples=len(t), mode_changes=len(segments),
                            switches=len(events))


def _check_written(tmp: str, n: int, path: str) -> None:
    """Read the file back: a full disk, a killed writer or ``RERUN=off`` leave a file that fails here."""
    from rerun.chunk import RrdReader
    hint = " (RERUN=off is set in the environment)" if os.environ.get("RERUN", "").lower() == "off" else ""
    first = STATE_ENTITIES[STATE_NAMES[0]]
    try:
        RrdReader(tmp).store()   # parses the whole file, footer included
        rows = sum(chunk.to_record_batch().num_rows
                   for chunk in RrdReader(tmp).stream().filter(content=first, is_static=False))
    except Exception as exc:  # the reader raises assorted types on a truncated file
        raise RecordingError(f"cannot write the recording {path}: it came out unreadable{hint} ({exc})") from None
    if rows != n:
        raise RecordingError(f"cannot write the recording {path}: it came out incomplete, {first} has {rows} "
                             f"rows, not {n}{hint}")


def _write(tmp: str, trajectory: Trajectory, poses: ScenePoses, segments, events, title: str,
           geometry: AxleGeometry, recording_id: str) -> None:
    import rerun as rr

    rec = rr.RecordingStream(APP_ID, recording_id=recording_id, send_properties=False)
    rec.set_log_time_enabled(False)     # no wall-clock column: the file depends on the data only
    rec.set_log_tick_enabled(False)
    try:
        rec.save(tmp, default_blueprint=default_blueprint())
        if title:
            rec.send_recording_name(title)
        _log_static(rec, trajectory, title, geometry)
        ns = time_ns(trajectory.t)
        index = [rr.TimeColumn(TIMELINE, duration=ns.astype("timedelta64[ns]"))]
        _log_scene(rec, index, poses)
        _log_series(rec, index, trajectory, poses)
        _log_modes(rec, segments, events, trajectory)
    finally:
        rec.flush()
        rec.disconnect()    # writes the footer; without it the reader rejects the file
        del rec
        rr.bindings.flush_and_cleanup_orphaned_recordings()


def _log_static(rec, trajectory: Trajectory, title: str, g: AxleGeometry) -> None:
    import rerun as rr
    units = ", ".join(f"{name}: {path}" for name, path in STATE_ENTITIES.items())
    status = trajectory.status.value + (f" ({trajectory.message})" if trajectory.message else "")
    rec.log("/info", rr.TextDocument(
        f"# {title or 'shimmy simulation'}\n\n"
        f"* model: {trajectory.model}; integrator: {trajectory.integrator}; status: {status}\n"
        f"* timeline `{TIMELINE}`: simulated time; {len(trajectory.t)} samples, "
        f"{trajectory.t[0]:g}-{trajectory.t[-1]:g} s\n"
        f"* states (degrees, degrees per second): {units}\n"
        f"* scene: x forward, y left, z up, m; the frame travels with the axle; true angles (not exaggerated); "
        f"tyre force arrows {FORCE_ARROW_M_PER_N * 1e3:g} m per kN\n", media_type="text/markdown"), static=True)
    rec.log("/scene", rr.ViewCoordinates.FLU, static=True)
    rec.log("/scene/road", rr.Boxes3D(half_sizes=[[1.5, 1.3, 0.002]], centers=[[0.0, 0.0, -0.002]],
                                      colors=[0xBBBBBBFF]), static=True)
    rec.log("/scene/axle/shape", rr.Boxes3D(half_sizes=[[0.5 * g.axle_section, g.kingpin_y,
                                                         0.5 * g.axle_section]], colors=[0x5F6B7AFF]),
            static=True)
    spin_axis = quaternion_about([1.0, 0.0, 0.0], -0.5 * np.pi)   # cylinder +z onto the wheel's +y
    kingpin_tilt = quaternion_about([0.0, 1.0, 0.0], -g.gamma)    # cylinder +z onto the kingpin axis
    for side in SIDES:
        inboard = 1.0 if side == "right" else -1.0
        rec.log(f"/scene/knuckle_{side}/shape",
                rr.Cylinders3D(lengths=[g.kingpin_length], radii=[g.kingpin_radius], quaternions=[kingpin_tilt],
                               colors=[0xC0392BFF]), static=True)
        strips = [[[0.0, 0.0, 0.0], g.tie_rod_point]]
        if side == "left":
            strips.append([[0.0, 0.0, 0.0], g.drag_link_point])
        rec.log(f"/scene/knuckle_{side}/arms", rr.LineStrips3D(strips, radii=[0.015], colors=[0xC0392BFF]),
                static=True)
        rec.log(f"/scene/wheel_{side}/tyre", rr.Cylinders3D(lengths=[g.tyre_width], radii=[g.R],
                                                            quaternions=[spin_axis], colors=[0x2B2B2BFF]),
                static=True)
        # Spokes on the outer face, so that the spin shows.
        y = -inboard * (0.5 * g.tyre_width + 0.005)
        spokes = [[[g.R * np.cos(a), y, g.R * np.sin(a)], [-g.R * np.cos(a), y, -g.R * np.sin(a)]]
                  for a in np.linspace(0.0, np.pi, 3, endpoint=False)]
        rec.log(f"/scene/wheel_{side}/spokes", rr.LineStrips3D(spokes, radii=[0.012], colors=[0xF1C40FFF]),
                static=True)
    for path, colour in (("/scene/tie_rod", 0x2E86C1FF), ("/scene/drag_link", 0x17A589FF)):
        rec.log(path, rr.LineStrips3D.from_fields(radii=[0.02], colors=[colour]), static=True)
    rec.log("/scene/tyre_forces", rr.Arrows3D.from_fields(colors=[0xE74C3CFF], radii=[0.015]), static=True)
    for name, path in STATE_ENTITIES.items():
        rec.log(path, rr.SeriesLines(names=[path.rsplit("/", 1)[1]]), static=True)
    for side, path in FORCE_ENTITIES.items():
        rec.log(path, rr.SeriesLines(names=[f"F_y {side} [N]"]), static=True)
    rec.log(SPEED_ENTITY, rr.SeriesLines(names=["speed [km/h]"]), static=True)


def _log_scene(rec, index, poses: ScenePoses) -> None:
    import rerun as rr
    n = poses.n
    for name in BODY_NAMES:
        pose = poses.bodies[name]
        rec.send_columns(f"/scene/{name}", indexes=index,
                         columns=rr.Transform3D.columns(translation=pose.position.astype(np.float32),
                                                        quaternion=pose.quaternion.astype(np.float32)))
    for name, ends in poses.links.items():
        rec.send_columns(f"/scene/{name}", indexes=index,
                         columns=rr.LineStrips3D.columns(strips=ends.astype(np.float32)).partition([1] * n))
    rec.send_columns("/scene/tyre_forces", indexes=index,
                     columns=rr.Arrows3D.columns(
                         origins=poses.force_points.reshape(-1, 3).astype(np.float32),
                         vectors=(FORCE_ARROW_M_PER_N * poses.force_vectors).reshape(-1, 3).astype(np.float32),
                     ).partition([2] * n))


def _log_series(rec, index, trajectory: Trajectory, poses: ScenePoses) -> None:
    import rerun as rr
    for k, (name, unit) in enumerate(zip(STATE_NAMES, STATE_UNITS)):
        convert = _UNIT_SUFFIX[unit][1]
        rec.send_columns(STATE_ENTITIES[name], indexes=index,
                         columns=rr.Scalars.columns(scalars=convert(trajectory.x[:, k])))
    forces = poses.lateral_forces()
    for k, side in enumerate(SIDES):
        rec.send_columns(FORCE_ENTITIES[side], indexes=index, columns=rr.Scalars.columns(scalars=forces[:, k]))
    rec.send_columns(SPEED_ENTITY, indexes=index,
                     columns=rr.Scalars.columns(scalars=np.asarray(trajectory.speed, dtype=float) * 3.6))


def _log_modes(rec, segments, events: list[ModeSwitch], trajectory: Trajectory) -> None:
    import rerun as rr
    if segments:
        labels = list(dict.fromkeys(label for _, label in segments))
        colours = np.array([_MODE_COLOURS[i % len(_MODE_COLOURS)] for i in range(len(labels))], dtype=np.uint32)
        rec.log(MODE_ENTITY, rr.StateConfiguration(values=labels, labels=labels, colors=colours), static=True)
        rec.send_columns(MODE_ENTITY,
                         indexes=[rr.TimeColumn(TIMELINE, duration=time_ns([s for s, _ in segments])
                                                .astype("timedelta64[ns]"))],
                         columns=rr.StateChange.columns(state=[label for _, label in segments]))
    texts = [f"mode switch at {e.time:.4f} s: {e.before} -> {e.after}" for e in events]
    times = [e.time for e in events]
    levels = ["INFO"] * len(events)
    if not trajectory.complete:
        texts.append(f"simulation ended early: {trajectory.status.value}"
                     + (f": {trajectory.message}" if trajectory.message else ""))
        times.append(float(trajectory.t[-1]))
        levels.append("WARN")
    if texts:
        order = np.argsort(times, kind="stable")
        rec.send_columns(EVENTS_ENTITY,
                         indexes=[rr.TimeColumn(TIMELINE, duration=time_ns(np.asarray(times)[order])
                                                .astype("timedelta64[ns]"))],
                         columns=rr.TextLog.columns(text=[texts[i] for i in order],
                                                    level=[levels[i] for i in order]))
