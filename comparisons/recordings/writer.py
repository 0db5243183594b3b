"""Rerun recordings (.rrd) of simulations: 3D scene, every state, speed, detected mode and mode switches.

:func:`write_recording` writes one run; :func:`write_comparison` writes several runs of one experiment side by
side (both 3D axles next to each other, each state of every run overlaid in one plot, the difference of their
amplitudes, one mode lane per run).
Timeline ``sim_time`` (simulated time, integer nanoseconds).  Entities of a one-run recording (a side-by-side
recording appends ``/<run>`` to each, see :mod:`comparisons.recordings.layout`):

* ``/scene/<body>`` for each body of :data:`comparisons.recordings.scene.BODY_NAMES`: a time-varying Transform3D (pose,
  world frame x forward, y left, z up, m); the shapes are static children (``/scene/<body>/shape`` ...) and move
  with it.  ``/scene/tie_rod`` and ``/scene/drag_link``: line strips between their end points.
  ``/scene/tyre_forces``: the tyre lateral forces as arrows at their points of action, drawn
  :data:`FORCE_ARROW_M_PER_N` m long per N.  Logged at :data:`SCENE_RATE_HZ`.
* ``/states/<state>_<unit>``: every state of the reduced model's state vector, angles in degrees and rates in
  degrees per second (the project's interface units; the simulation is SI inside): e.g. ``/states/theta1_deg``,
  ``/states/psi_dot_deg_per_s``.  ``/tyre_forces/right_N`` and ``/tyre_forces/left_N``: the forces, N.
  ``/speed_kmh``: the speed.  Each series keeps, per :data:`SERIES_BIN_S` of simulated time, its lowest and
  highest sample (:func:`comparisons.recordings.decimation.envelope_indices`): every swing's extreme is kept exactly at a
  fifth of the size of 1 kHz data, and the series are drawn with min/max aggregation, so the viewer shows the
  envelope at any zoom instead of averaging an oscillation away.  Each state has its own fixed colour.  The
  stored blueprint shows these waveforms in a window of :data:`~comparisons.recordings.layout.WAVE_WINDOW_S`
  around the time cursor.
* ``/envelopes/<state>_<unit>/upper`` and ``.../lower`` (``/envelopes/tyre_forces/<side>_N/...`` for the forces):
  the per-cycle envelopes, a line through the highest sample of each swing and one through the lowest
  (:func:`comparisons.recordings.decimation.cycle_envelopes`), shown over the whole run: a 60 s run of a 5 Hz
  oscillation reads as two lines, not as a filled band.
* Side by side only, ``/difference/<state>_<unit>/<run>``: that run's amplitude (half the distance between its
  envelopes) minus the first run's, on a :data:`DIFFERENCE_RATE_HZ` grid where both ran.
* ``/mode``: the detected mode as a state lane (``rr.StateChange``, one row per change); ``/events``: one
  ``rr.TextLog`` per mode switch at its time; a warning at the end if the simulation did not complete.
* ``/info``: a static Markdown document (title, model, integrator, units, what the views show), shown in a
  text view of the stored blueprint.

The file is written under a temporary name in the target folder, read back, and renamed only when complete:
a failure, a full disk or an interrupt never leaves a truncated recording under the final name.
"""

from __future__ import annotations

import enum
import numbers
import os
import uuid
from dataclasses import dataclass, field
from typing import Sequence

import numpy as np

from axles.axle import interface_text
from axles.units import kmh
from comparisons.files import atomic_path, run_writer
from comparisons.recordings.decimation import uniform_indices
from comparisons.recordings.layout import (
    ENVELOPE_BOUNDS,
    FORCE_COLOURS,
    INFO_ENTITY,
    RUN_COLOURS,
    RUN_WIDTHS,
    SPEED_COLOUR,
    STATE_COLOURS,
    STATE_UNIT_LABELS,
    TIMELINE,
    UNIT_SUFFIX,
    WAVE_WINDOW_S,
    RunPaths,
    colour_name,
    comparison_blueprint,
    mode_colour,
    series_leaves,
    single_blueprint,
)
from comparisons.recordings.timeseries import (  # noqa: F401 (time_ns, series_indices: part of this module's API)
    DIFFERENCE_RATE_HZ,
    SERIES_BIN_S,
    log_differences,
    log_envelopes,
    log_series,
    series_indices,
    series_style,
    time_index,
    time_ns,
)
from comparisons.recordings.scene import BODY_NAMES, SIDES, AxleGeometry, ScenePoses, rotation_about, trajectory_poses
from reduced_model.model import STATE_NAMES, STATE_UNITS, ShimmyModel
from reduced_model.trajectory import Trajectory

APP_ID = "shimmy"
FORCE_ARROW_M_PER_N = 1e-4      # a 5 kN force is drawn 0.5 m long
SCENE_RATE_HZ = 100.0           # poses: 10 per cycle of a 10 Hz shimmy, enough to scrub and to play back
_ROOT = RunPaths()
STATE_ENTITIES = {name: _ROOT.state(name) for name in STATE_NAMES}
SPEED_ENTITY = _ROOT.speed
MODE_ENTITY = _ROOT.mode
EVENTS_ENTITY = _ROOT.events
FORCE_ENTITIES = {side: _ROOT.force(side) for side in SIDES}
SCENE_ENTITIES = tuple(f"/scene/{name}" for name in BODY_NAMES) + ("/scene/tie_rod", "/scene/drag_link",
                                                                    "/scene/tyre_forces")
MODEL_TITLES = {"reduced": "reduced model (3 DOF, paper)", "mbs": "multibody model (Exudyn)"}


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
    bytes: int = 0


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




@dataclass(frozen=True)
class _Run:
    """One run checked and converted, ready to log."""

    key: str                 # "" in a one-run recording, else the run's sub-path (the model name)
    title: str
    trajectory: Trajectory
    poses: ScenePoses
    segments: list
    events: list
    geometry: AxleGeometry
    colour: int | None = None   # the run's colour in side-by-side plots; None: one colour per state
    width: float = RUN_WIDTHS[0]

    @property
    def paths(self) -> RunPaths:
        return RunPaths(self.key)

    def series(self) -> dict:
        """entity -> values (interface units) of every plotted waveform."""
        values = self.enveloped()
        out = {self.paths.state(name): values[name] for name in STATE_NAMES}
        out.update({self.paths.force(side): values[f"F_y {side}"] for side in SIDES})
        out[self.paths.speed] = kmh(np.asarray(self.trajectory.speed, dtype=float))
        return out

    def enveloped(self) -> dict:
        """series key (state name or "F_y <side>") -> values (interface units) of every series that gets
        envelopes: all but the speed."""
        tr, forces = self.trajectory, self.poses.lateral_forces()
        out = {name: UNIT_SUFFIX[unit][2](tr.x[:, k]) for k, (name, unit) in enumerate(zip(STATE_NAMES, STATE_UNITS))}
        out.update({f"F_y {side}": forces[:, k] for k, side in enumerate(SIDES)})
        return out


def scene_indices(t: np.ndarray) -> np.ndarray:
    """The samples whose poses go into a recording."""
    return uniform_indices(t, SCENE_RATE_HZ)


def _prepare(trajectory: Trajectory, modes, switches, model, pressures, geometry, key="", title="",
             colour=None, width=RUN_WIDTHS[0]) -> _Run:
    """Everything that can fail on the input fails here, before a byte is written."""
    t = np.asarray(trajectory.t, dtype=float)
    if len(t) < 2 or np.any(np.diff(t) <= 0.0):
        raise ValueError("the trajectory needs at least two samples at increasing times")
    poses = trajectory_poses(trajectory, model, pressures, geometry)
    geometry = geometry or AxleGeometry.from_params((model or ShimmyModel()).params)
    return _Run(key=key, title=title or MODEL_TITLES.get(trajectory.model, trajectory.model),
                trajectory=trajectory, poses=poses, segments=mode_segments(modes, t),
                events=mode_switches(switches, t), geometry=geometry, colour=colour, width=width)


def write_recording(path: str, trajectory: Trajectory, modes=None, switches: Sequence = (), title: str = "", *,
                    model: ShimmyModel | None = None, pressures=None, geometry: AxleGeometry | None = None,
                    recording_id: str | None = None) -> RecordingSummary:
    """Write one .rrd recording of ``trajectory`` to ``path`` atomically.

    ``modes``: None, one label per sample, or (start time s, label) pairs (labels str or enum).  ``switches``:
    (time s, from, to) triples or objects with ``time``, ``before``, ``after`` (such as :class:`ModeSwitch`).
    The 3D poses come from ``trajectory.extra["poses"]`` when present (multibody model), else from the reduced
    model's angles, for which ``pressures`` (:class:`~axles.pressures.TyrePressures`; or ``extra["pressures"]``) and ``model`` (default: the section 3
    model) give the tyre forces.  ``recording_id``: default a fresh UUID, so that recordings opened together
    never merge.  Raises :class:`RecordingError` when the file cannot be written, ValueError on inconsistent
    input.
    """
    _check_target(path)
    run = _prepare(trajectory, modes, switches, model, pressures, geometry)
    return _write_file(path, [run], title, single_blueprint(_span([run])), recording_id)


@dataclass(frozen=True)
class ComparedRun:
    """One model's run of an experiment, for :func:`write_comparison`."""

    trajectory: Trajectory
    modes: object = None                    # as for write_recording
    switches: Sequence = field(default=())
    title: str = ""                         # default: the model's name


def write_comparison(path: str, runs: Sequence[ComparedRun], title: str = "", *, model: ShimmyModel | None = None,
                     pressures=None, geometry: AxleGeometry | None = None,
                     recording_id: str | None = None) -> RecordingSummary:
    """Write several runs of one experiment (e.g. the reduced model and the MBS) into one recording, side by
    side: their 3D axles in views next to each other, each state of every run overlaid in one plot (one colour
    per run), one mode lane per run.  The runs share the timeline; each is keyed by its ``trajectory.model``,
    which must differ between runs.  The first run is the reference: the others are drawn wide and translucent
    over it, and each one's amplitude minus the reference's is a series of its own (``/difference/...``).  Same
    errors and atomic write as :func:`write_recording`."""
    _check_target(path)
    keys = [r.trajectory.model for r in runs]
    if not runs or len(set(keys)) != len(keys):
        raise ValueError(f"write_comparison needs runs of different models, got {keys}")
    prepared = [_prepare(r.trajectory, r.modes, r.switches, model, pressures, geometry, key=r.trajectory.model,
                         title=r.title, colour=RUN_COLOURS[k % len(RUN_COLOURS)],
                         width=RUN_WIDTHS[k % len(RUN_WIDTHS)]) for k, r in enumerate(runs)]
    blueprint = comparison_blueprint([(r.key, r.title) for r in prepared], _span(prepared))
    return _write_file(path, prepared, title, blueprint, recording_id)


def _span(runs: list[_Run]) -> tuple[float, float]:
    return (min(float(r.trajectory.t[0]) for r in runs), max(float(r.trajectory.t[-1]) for r in runs))


def _check_target(path: str) -> None:
    final = os.path.abspath(path)
    folder = os.path.dirname(final)
    if os.path.isdir(final):
        raise RecordingError(f"cannot write the recording {path}: a directory is in the way")
    if not os.path.isdir(folder):
        raise RecordingError(f"cannot write the recording {path}: the folder {folder} does not exist")


def _write_file(path: str, runs: list[_Run], title: str, blueprint, recording_id: str | None) -> RecordingSummary:
    final = os.path.abspath(path)
    recording_id = recording_id or str(uuid.uuid4())
    first = runs[0]
    entity = first.paths.state(STATE_NAMES[0])
    expected = len(series_indices(first.trajectory.t, first.series()[entity]))
    try:
        with atomic_path(final) as tmp:
            run_writer(write_runs, tmp, runs, title, blueprint, recording_id)
            _check_written(tmp, entity, expected, path)
            size = os.path.getsize(tmp)
    except RecordingError:
        raise
    except OSError as exc:
        raise RecordingError(f"cannot write the recording {path}: {exc.strerror or exc}") from None
    return RecordingSummary(path=final, recording_id=recording_id, samples=len(first.trajectory.t),
                            mode_changes=len(first.segments), switches=len(first.events), bytes=size)


def _check_written(tmp: str, entity: str, rows_expected: int, path: str) -> None:
    """Read the file back: a full disk, a killed writer or ``RERUN=off`` leave a file that fails here."""
    from rerun.chunk import RrdReader
    hint = " (RERUN=off is set in the environment)" if os.environ.get("RERUN", "").lower() == "off" else ""
    try:
        RrdReader(tmp).store()   # parses the whole file, footer included
        rows = sum(chunk.to_record_batch().num_rows
                   for chunk in RrdReader(tmp).stream().filter(content=entity, is_static=False))
    except Exception as exc:  # the reader raises assorted types on a truncated file
        raise RecordingError(f"cannot write the recording {path}: it came out unreadable{hint} ({exc})") from None
    if rows != rows_expected:
        raise RecordingError(f"cannot write the recording {path}: it came out incomplete, {entity} has {rows} "
                             f"rows, not {rows_expected}{hint}")


def write_runs(tmp: str, runs: list[_Run], title: str, blueprint, recording_id: str) -> None:
    import rerun as rr

    rec = rr.RecordingStream(APP_ID, recording_id=recording_id, send_properties=False)
    rec.set_log_time_enabled(False)     # no wall-clock column: the file depends on the data only
    rec.set_log_tick_enabled(False)
    rec.save(tmp, default_blueprint=blueprint)
    try:
        with rec:   # leaving the block flushes and writes the footer, also when logging failed
            if title:
                rec.send_recording_name(title)
            rec.log(INFO_ENTITY, rr.TextDocument(info_text(runs, title), media_type="text/markdown"), static=True)
            for run in runs:
                _log_static(rec, run)
                _log_scene(rec, run)
                log_series(rec, run)
                log_envelopes(rec, run)
                _log_modes(rec, run)
            log_differences(rec, runs)
    finally:
        del rec     # the SDK releases a recording's threads and buffers when its last reference goes


def info_text(runs: list[_Run], title: str) -> str:
    """The Markdown of ``/info``."""
    lines = [f"# {title or 'shimmy simulation'}", ""]
    for run in runs:
        tr = run.trajectory
        status = tr.status.value + (f" ({interface_text(tr.message)})" if tr.message else "")
        lines += [f"**{run.title}**: integrator {tr.integrator}; status {status}; {len(tr.t)} samples, "
                  f"{tr.t[0]:g}-{tr.t[-1]:g} s; speed {kmh(np.min(tr.speed)):.1f}-{kmh(np.max(tr.speed)):.1f} "
                  f"km/h.", ""]
    lines += [
        "* **Plots**: angles in degrees, rates in degrees per second, forces in N, speed in km/h, against "
        f"simulated time `{TIMELINE}`. The envelope views show, over the whole run, a line through every swing's "
        "maximum (upper envelope) and one through every minimum (lower envelope); the waveform views show the "
        f"signal itself in {WAVE_WINDOW_S:g} s around the time cursor (play or scrub to move it). The waveform "
        f"keeps its lowest and highest sample of every {SERIES_BIN_S * 1e3:g} ms and is drawn with min/max "
        "aggregation, so zoomed out it shows its true peaks, never an average. Legends are off: each view's name "
        "says which colour is which.",
        "* **3D**: x forward, y left, z up, m; the frame travels with the axle; true angles (not exaggerated); "
        f"red arrows: tyre lateral forces, {FORCE_ARROW_M_PER_N * 1e3:g} m per kN; poses at "
        f"{SCENE_RATE_HZ:g} per second.",
        "* **Mode lane**: the mode detected by `reduced_model.modes.ModeClassifier` (straight, yaw, tramp); "
        "the events list each switch.",
    ]
    if len(runs) > 1:
        names = ", ".join(f"{run.title}: {colour_name(run.colour)} ({_hex(run.colour)}"
                          f"{', wide and translucent' if k else ''})" for k, run in enumerate(runs))
        lines.append(f"* **Colours** in the plots: {names}. No run hides another: where the lines coincide, the "
                     "narrow one shows inside the wide one.")
        lines.append(f"* **Difference**: each run's amplitude (half the distance between its envelopes) minus "
                     f"{runs[0].title}'s, on a {DIFFERENCE_RATE_HZ:g} Hz grid where both ran.")
    return "\n".join(lines) + "\n"


def _hex(colour: int | None) -> str:
    return "-" if colour is None else f"#{colour >> 8:06X}"


def _log_static(rec, run: _Run) -> None:
    import rerun as rr
    g, paths = run.geometry, run.paths
    scene = paths.scene
    rec.log(scene, rr.ViewCoordinates.FLU, static=True)
    rec.log(f"{scene}/road", rr.Boxes3D(half_sizes=[[1.5, 1.3, 0.002]], centers=[[0.0, 0.0, -0.002]],
                                        colors=[0xBBBBBBFF]), static=True)
    rec.log(f"{scene}/axle/shape", rr.Boxes3D(half_sizes=[[0.5 * g.axle_section, g.kingpin_y,
                                                           0.5 * g.axle_section]], colors=[0x5F6B7AFF]),
            static=True)
    spin_axis = rotation_about([1.0, 0.0, 0.0], -0.5 * np.pi).as_quat()   # cylinder +z onto the wheel's +y
    kingpin_tilt = rotation_about([0.0, 1.0, 0.0], -g.gamma).as_quat()    # cylinder +z onto the kingpin axis
    for side in SIDES:
        inboard = 1.0 if side == "right" else -1.0
        rec.log(f"{scene}/knuckle_{side}/shape",
                rr.Cylinders3D(lengths=[g.kingpin_length], radii=[g.kingpin_radius], quaternions=[kingpin_tilt],
                               colors=[0xC0392BFF]), static=True)
        strips = [[[0.0, 0.0, 0.0], g.tie_rod_point]]
        if side == "left":
            strips.append([[0.0, 0.0, 0.0], g.drag_link_point])
        rec.log(f"{scene}/knuckle_{side}/arms", rr.LineStrips3D(strips, radii=[0.015], colors=[0xC0392BFF]),
                static=True)
        rec.log(f"{scene}/wheel_{side}/tyre", rr.Cylinders3D(lengths=[g.tyre_width], radii=[g.R],
                                                             quaternions=[spin_axis], colors=[0x2B2B2BFF]),
                static=True)
        # Spokes on the outer face, so that the spin shows.
        y = -inboard * (0.5 * g.tyre_width + 0.005)
        spokes = [[[g.R * np.cos(a), y, g.R * np.sin(a)], [-g.R * np.cos(a), y, -g.R * np.sin(a)]]
                  for a in np.linspace(0.0, np.pi, 3, endpoint=False)]
        rec.log(f"{scene}/wheel_{side}/spokes", rr.LineStrips3D(spokes, radii=[0.012], colors=[0xF1C40FFF]),
                static=True)
    for name, colour in (("tie_rod", 0x2E86C1FF), ("drag_link", 0x17A589FF)):
        rec.log(f"{scene}/{name}", rr.LineStrips3D.from_fields(radii=[0.02], colors=[colour]), static=True)
    rec.log(f"{scene}/tyre_forces", rr.Arrows3D.from_fields(colors=[0xE74C3CFF], radii=[0.015]), static=True)
    # Series styles: a name with its unit, a fixed colour, and min/max aggregation (module docstring).
    short = run.title.split(" (")[0]
    for name in STATE_NAMES:
        label = f"{name} [{STATE_UNIT_LABELS[name]}]" if run.colour is None else short
        series_style(rec, paths.state(name), label, run.colour or STATE_COLOURS[name], run.width)
    for side in SIDES:
        label = f"F_y {side} [N]" if run.colour is None else f"F_y {side}, {short}"
        series_style(rec, paths.force(side), label, run.colour or FORCE_COLOURS[side], run.width)
    for key, leaf in series_leaves().items():
        colour = run.colour or (STATE_COLOURS.get(key) or FORCE_COLOURS[key.split()[-1]])
        for bound in ENVELOPE_BOUNDS:
            series_style(rec, paths.envelope(leaf, bound), f"{key} {bound}" + (f", {short}" if run.colour else ""),
                          colour, run.width)
    series_style(rec, paths.speed, "speed [km/h]" if run.colour is None else short, run.colour or SPEED_COLOUR,
                  run.width)


def _log_scene(rec, run: _Run) -> None:
    import rerun as rr
    idx = scene_indices(run.trajectory.t)
    index = time_index(rr, run.trajectory.t[idx])
    n, scene, poses = len(idx), run.paths.scene, run.poses
    for name in BODY_NAMES:
        pose = poses.bodies[name]
        rec.send_columns(f"{scene}/{name}", indexes=index,
                         columns=rr.Transform3D.columns(translation=pose.position[idx].astype(np.float32),
                                                        quaternion=pose.quaternion[idx].astype(np.float32)))
    for name, ends in poses.links.items():
        rec.send_columns(f"{scene}/{name}", indexes=index,
                         columns=rr.LineStrips3D.columns(strips=ends[idx].astype(np.float32)).partition([1] * n))
    rec.send_columns(f"{scene}/tyre_forces", indexes=index,
                     columns=rr.Arrows3D.columns(
                         origins=poses.force_points[idx].reshape(-1, 3).astype(np.float32),
                         vectors=(FORCE_ARROW_M_PER_N * poses.force_vectors[idx]).reshape(-1, 3).astype(np.float32),
                     ).partition([2] * n))


def _log_modes(rec, run: _Run) -> None:
    import rerun as rr
    paths, segments, events, trajectory = run.paths, run.segments, run.events, run.trajectory
    if segments:
        labels = list(dict.fromkeys(label for _, label in segments))
        colours = np.array([mode_colour(label, i) for i, label in enumerate(labels)], dtype=np.uint32)
        rec.log(paths.mode, rr.StateConfiguration(values=labels, labels=labels, colors=colours), static=True)
        rec.send_columns(paths.mode, indexes=time_index(rr, np.array([s for s, _ in segments])),
                         columns=rr.StateChange.columns(state=[label for _, label in segments]))
    texts = [f"mode switch at {e.time:.4f} s: {e.before} -> {e.after}" for e in events]
    times = [e.time for e in events]
    levels = ["INFO"] * len(events)
    if not trajectory.complete:
        texts.append(f"simulation ended early: {trajectory.status.value}"
                     + (f": {interface_text(trajectory.message)}" if trajectory.message else ""))
        times.append(float(trajectory.t[-1]))
        levels.append("WARN")
    if texts:
        order = np.argsort(times, kind="stable")
        rec.send_columns(paths.events, indexes=time_index(rr, np.asarray(times)[order]),
                         columns=rr.TextLog.columns(text=[texts[i] for i in order],
                                                    level=[levels[i] for i in order]))
