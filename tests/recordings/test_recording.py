"""Rerun recordings read back with rerun's RrdReader, the 3D scene poses, and the atomic write."""

import enum
import os

import numpy as np
import pyarrow as pa
import pytest
from rerun.chunk import RrdReader
from rrd_helpers import blueprint_views, rows
from scipy.integrate import solve_ivp

from axles.units import from_kmh, kmh
from comparisons.recordings import writer as recording
from comparisons.recordings.scene import (
    BODY_NAMES,
    AxleGeometry,
    ScenePoses,
    reduced_model_poses,
    rotate,
    wheel_lateral_axis,
)
from comparisons.recordings.writer import (
    EVENTS_ENTITY,
    FORCE_ENTITIES,
    MODE_ENTITY,
    SCENE_ENTITIES,
    SPEED_ENTITY,
    STATE_ENTITIES,
    RecordingError,
    time_ns,
    write_recording,
)
from reduced_model.model import STATE_NAMES, ShimmyModel
from reduced_model.trajectory import SimulationStatus, Trajectory
from axles.pressures import TyrePressures

PRESSURE = TyrePressures.uniform(1.5e5)
SPEED = from_kmh(60.0)
SWITCHES = [(0.61234, "straight", "yaw"), (1.40007, "yaw", "tramp")]  # deliberately between samples


def simulate(n=801, seconds=2.0, status=SimulationStatus.COMPLETE):
    model = ShimmyModel()
    x0 = np.zeros(8)
    x0[0] = 0.01
    t = np.linspace(0.0, seconds, n)
    sol = solve_ivp(lambda _, x: model.rhs(x, SPEED, PRESSURE), (0.0, seconds), x0, t_eval=t, rtol=1e-9,
                    atol=1e-12)
    assert sol.success
    return Trajectory(t=sol.t, x=sol.y.T, speed=np.full(n, SPEED), model="reduced",
                      integrator="scipy RK45 rtol=1e-9 atol=1e-12", status=status,
                      message="" if status is SimulationStatus.COMPLETE else "step size too small at 2 s")


def labels_for(t):
    return np.where(t < SWITCHES[0][0], "straight", np.where(t < SWITCHES[1][0], "yaw", "tramp")).tolist()


@pytest.fixture(scope="module")
def trajectory():
    return simulate()


@pytest.fixture(scope="module")
def rrd(trajectory, tmp_path_factory):
    path = tmp_path_factory.mktemp("rec") / "run.rrd"
    summary = write_recording(str(path), trajectory, labels_for(trajectory.t), SWITCHES, "test run",
                              pressures=PRESSURE)
    assert summary.samples == len(trajectory.t) and summary.switches == 2 and summary.mode_changes == 3
    return str(path)


def times(table):
    return table.column("sim_time").cast(pa.int64()).to_numpy()


def scalars(table):
    values = table.column("Scalars:scalars").to_pylist()
    assert all(len(v) == 1 for v in values)
    return np.array([v[0] for v in values])


def test_entities_and_sample_counts(rrd, trajectory):
    """Series keep their min/max samples, the scene its 100-per-second poses; times are the trajectory's own."""
    t = trajectory.t
    series = dict(zip(STATE_ENTITIES.values(), np.degrees(trajectory.x.T)))
    series[SPEED_ENTITY] = kmh(trajectory.speed)
    for entity, values in series.items():
        table = rows(rrd, entity)
        kept = recording.series_indices(t, values)
        assert len(kept) < len(t)      # decimated ...
        np.testing.assert_array_equal(times(table), time_ns(t[kept]))
    for entity in (*FORCE_ENTITIES.values(), *SCENE_ENTITIES):
        assert rows(rrd, entity).num_rows > 0, entity
    for entity in SCENE_ENTITIES:
        np.testing.assert_array_equal(times(rows(rrd, entity)), time_ns(t[recording.scene_indices(t)]))
    assert len(recording.scene_indices(t)) == 201   # 2 s at 100 per second, and the last sample
    summary = RrdReader(rrd).store().summary()
    for body in BODY_NAMES:   # every body has static shapes as children
        assert f"/scene/{body}/" in summary
    assert "log_time" not in summary  # reproducible: no wall clock column


def test_state_values_equal_the_trajectory(rrd, trajectory):
    t = trajectory.t
    for k, name in enumerate(STATE_NAMES):
        values = np.degrees(trajectory.x[:, k])
        kept = recording.series_indices(t, values)
        np.testing.assert_array_equal(scalars(rows(rrd, STATE_ENTITIES[name])), values[kept])
        # ... but every 10 ms bin's extremes are there: the recorded envelope is the trajectory's.
        assert scalars(rows(rrd, STATE_ENTITIES[name])).max() == values.max()
    speed = kmh(trajectory.speed)
    np.testing.assert_array_equal(scalars(rows(rrd, SPEED_ENTITY)), speed[recording.series_indices(t, speed)])
    assert STATE_ENTITIES["theta1"] == "/states/theta1_deg"
    assert STATE_ENTITIES["psi_dot"] == "/states/psi_dot_deg_per_s"


def test_series_styles_distinct_colours_and_minmax(rrd):
    """Every series is drawn with min/max aggregation and a colour of its own (the viewer's defaults average
    the samples of a pixel and draw theta1 and theta2 in near-identical greens)."""
    colours = {}
    for name, entity in STATE_ENTITIES.items():
        static = [c.to_record_batch() for c in RrdReader(rrd).stream().filter(content=entity, is_static=True)]
        cols = {n: b.column(n).to_pylist()[0] for b in static for n in b.schema.names}
        assert cols["SeriesLines:aggregation_policy"] == [5]      # AggregationPolicy.MinMax
        colours[name] = cols["SeriesLines:colors"][0]
        assert cols["SeriesLines:names"][0].startswith(name + " [")
    assert len(set(colours.values())) == len(colours)


def test_scene_and_forces_equal_the_poses(rrd, trajectory):
    poses = reduced_model_poses(trajectory, ShimmyModel(), PRESSURE)
    k = recording.scene_indices(trajectory.t)
    for body in BODY_NAMES:
        table = rows(rrd, f"/scene/{body}")
        np.testing.assert_array_equal(np.array(table.column("Transform3D:translation").to_pylist()).reshape(-1, 3),
                                      poses.bodies[body].position[k].astype(np.float32))
        np.testing.assert_array_equal(np.array(table.column("Transform3D:quaternion").to_pylist()).reshape(-1, 4),
                                      poses.bodies[body].quaternion[k].astype(np.float32))
    strips = np.array(rows(rrd, "/scene/tie_rod").column("LineStrips3D:strips").to_pylist())
    np.testing.assert_array_equal(strips[:, 0], poses.links["tie_rod"][k].astype(np.float32))
    arrows = rows(rrd, "/scene/tyre_forces")
    origins = np.array(arrows.column("Arrows3D:origins").to_pylist())
    assert origins.shape == (len(k), 2, 3)
    np.testing.assert_array_equal(origins, poses.force_points[k].astype(np.float32))
    # The force scalars are the tyre model's F_y at the recorded slip angles.
    w_right, w_left = ShimmyModel().tyres(PRESSURE)
    for entity, wheel, state in ((FORCE_ENTITIES["right"], w_right, "alpha1"),
                                 (FORCE_ENTITIES["left"], w_left, "alpha2")):
        table = rows(rrd, entity)
        at = np.searchsorted(time_ns(trajectory.t), times(table))
        np.testing.assert_allclose(scalars(table), wheel.force.force(trajectory.state(state)[at]), rtol=1e-12,
                                   atol=1e-9)


def test_mode_lane_and_switch_events(rrd, trajectory):
    lane = rows(rrd, MODE_ENTITY)
    assert [v[0] for v in lane.column("StateChange:state").to_pylist()] == ["straight", "yaw", "tramp"]
    t = trajectory.t
    first_of = [0, int(np.argmax(t >= SWITCHES[0][0])), int(np.argmax(t >= SWITCHES[1][0]))]
    np.testing.assert_array_equal(times(lane), time_ns(t[first_of]))
    events = rows(rrd, EVENTS_ENTITY)
    np.testing.assert_array_equal(times(events), time_ns([s[0] for s in SWITCHES]))
    texts = [v[0] for v in events.column("TextLog:text").to_pylist()]
    assert "straight -> yaw" in texts[0] and "yaw -> tramp" in texts[1]


def test_stored_blueprint(rrd):
    reader = RrdReader(rrd)
    (blueprint,) = reader.blueprints()
    (rec,) = reader.recordings()
    assert blueprint.application_id == rec.application_id == recording.APP_ID
    views = blueprint_views(rrd)
    assert views["3D"] == {"/scene"}
    assert views["TextDocument"] == {recording.INFO_ENTITY}
    assert "/states" in views["TimeSeries"] and SPEED_ENTITY in views["TimeSeries"]
    assert views["StateTimeline"] == {MODE_ENTITY}
    assert views["TextLog"] == {EVENTS_ENTITY}


def test_mode_inputs():
    t = np.linspace(0.0, 1.0, 5)

    class Mode(enum.Enum):
        STRAIGHT = "straight"
        YAW = "yaw"

    assert recording.mode_segments([Mode.STRAIGHT] * 2 + [Mode.YAW] * 3, t) == [(0.0, "straight"), (0.5, "yaw")]
    assert recording.mode_segments(np.array(["a", "a", "b", "b", "a"]), t) == [(0.0, "a"), (0.5, "b"), (1.0, "a")]
    assert recording.mode_segments([(0.0, Mode.YAW), (0.3, "tramp")], t) == [(0.0, "yaw"), (0.3, "tramp")]
    assert recording.mode_segments([(0.0, "a"), (0.2, "a"), (0.3, "b")], t) == [(0.0, "a"), (0.3, "b")]
    assert recording.mode_switches([(0.3, Mode.YAW, "tramp")], t) == [recording.ModeSwitch(0.3, "yaw", "tramp")]

    class Detected:   # any object with time, before, after (the simulation's own switch records)
        time, before, after, speed = 0.4, Mode.STRAIGHT, Mode.YAW, 16.7

    assert recording.mode_switches([Detected()], t) == [recording.ModeSwitch(0.4, "straight", "yaw")]


def test_each_recording_has_its_own_id_and_incomplete_runs_say_so(tmp_path):
    short = simulate(n=101, seconds=0.2, status=SimulationStatus.SOLVER_FAILED)
    a = write_recording(str(tmp_path / "a.rrd"), short, None, (), pressures=PRESSURE)
    b = write_recording(str(tmp_path / "b.rrd"), short, None, (), pressures=PRESSURE)
    assert a.recording_id != b.recording_id
    assert [r.recording_id for r in RrdReader(a.path).recordings()] == [a.recording_id]
    events = rows(a.path, EVENTS_ENTITY)
    assert events.column("TextLog:level").to_pylist() == [["WARN"]]
    assert "solver_failed" in events.column("TextLog:text").to_pylist()[0][0]
    assert times(events)[0] == time_ns(short.t[-1])


def test_stored_poses_are_used(tmp_path):
    """A multibody trajectory brings its own poses (extra["poses"]); they are recorded as given."""
    short = simulate(n=51, seconds=0.1)
    poses = reduced_model_poses(short, ShimmyModel(), PRESSURE).to_dict()
    poses["axle"]["position"] = poses["axle"]["position"] + [0.25, 0.0, 0.0]
    mbs = Trajectory(t=short.t, x=short.x, speed=short.speed, model="mbs", integrator="test", extra={"poses": poses})
    path = str(tmp_path / "mbs.rrd")
    write_recording(path, mbs, [(0.0, "straight")], ())  # no pressure needed
    got = np.array(rows(path, "/scene/axle").column("Transform3D:translation").to_pylist()).reshape(-1, 3)
    np.testing.assert_array_equal(got, poses["axle"]["position"][recording.scene_indices(short.t)].astype(np.float32))
    broken = dict(poses, tie_rod=poses["tie_rod"][:, :1])
    with pytest.raises(ValueError, match="tie_rod must have shape"):
        write_recording(str(tmp_path / "bad.rrd"), Trajectory(t=short.t, x=short.x, speed=short.speed, model="mbs",
                                                              integrator="test", extra={"poses": broken}))
    assert not os.path.exists(tmp_path / "bad.rrd")


def test_bad_input_is_refused_before_writing(tmp_path):
    short = simulate(n=51, seconds=0.1)
    target = tmp_path / "x.rrd"
    with pytest.raises(ValueError, match="pressure"):
        write_recording(str(target), short)
    with pytest.raises(ValueError, match="outside the trajectory"):
        write_recording(str(target), short, None, [(5.0, "a", "b")], pressures=PRESSURE)
    with pytest.raises(ValueError, match="one label per sample"):
        write_recording(str(target), short, ["yaw"] * 3, pressures=PRESSURE)
    with pytest.raises(ValueError, match="in time order"):
        write_recording(str(target), short, [(0.05, "yaw"), (0.0, "tramp")], pressures=PRESSURE)
    assert os.listdir(tmp_path) == []


# --- atomic write ----------------------------------------------------------------------------------------------

@pytest.fixture
def short():
    return simulate(n=51, seconds=0.1)


@pytest.mark.skipif(os.geteuid() == 0, reason="root ignores directory permissions")
def test_unwritable_folder(tmp_path, short):
    locked = tmp_path / "locked"
    locked.mkdir(mode=0o500)
    with pytest.raises(RecordingError, match="cannot write the recording"):
        write_recording(str(locked / "r.rrd"), short, pressures=PRESSURE)
    assert os.listdir(locked) == []


@pytest.mark.skipif(not os.path.isdir("/sys"), reason="needs a folder nobody can write, even root")
def test_folder_even_root_cannot_write(short):
    with pytest.raises(RecordingError, match="cannot write the recording /sys/r.rrd"):
        write_recording("/sys/r.rrd", short, pressures=PRESSURE)


def test_missing_folder_and_directory_in_the_way(tmp_path, short):
    with pytest.raises(RecordingError, match="does not exist"):
        write_recording(str(tmp_path / "nope" / "r.rrd"), short, pressures=PRESSURE)
    (tmp_path / "r.rrd").mkdir()
    with pytest.raises(RecordingError, match="a directory is in the way"):
        write_recording(str(tmp_path / "r.rrd"), short, pressures=PRESSURE)
    assert os.listdir(tmp_path) == ["r.rrd"] and os.listdir(tmp_path / "r.rrd") == []


@pytest.mark.parametrize("error", [RuntimeError("boom"), KeyboardInterrupt()])
def test_failure_while_writing_leaves_nothing_behind(tmp_path, short, monkeypatch, error):
    target = tmp_path / "r.rrd"
    target.write_bytes(b"previous recording")

    def explode(*args, **kwargs):
        raise error

    monkeypatch.setattr(recording, "log_series", explode)
    with pytest.raises(type(error)):
        write_recording(str(target), short, pressures=PRESSURE)
    assert os.listdir(tmp_path) == ["r.rrd"] and target.read_bytes() == b"previous recording"


@pytest.mark.filterwarnings("ignore:RRD file has no footer")
def test_truncated_file_is_caught(tmp_path, short, monkeypatch):
    """A full disk shows as a file the reader rejects: the check before the rename catches it."""
    real_write = recording.write_runs

    def write_then_truncate(tmp, *args):
        real_write(tmp, *args)
        with open(tmp, "r+b") as fh:
            fh.truncate(os.path.getsize(tmp) // 2)

    monkeypatch.setattr(recording, "write_runs", write_then_truncate)
    with pytest.raises(RecordingError, match="came out"):
        write_recording(str(tmp_path / "r.rrd"), short, pressures=PRESSURE)
    assert os.listdir(tmp_path) == []


# --- scene -----------------------------------------------------------------------------------------------------

def one_sample(theta1=0.0, theta2=0.0, psi=0.0, alpha1=0.0, alpha2=0.0, t=(0.0, 0.5)):
    x = np.zeros((len(t), 8))
    x[:, [0, 2, 4, 6, 7]] = [theta1, theta2, psi, alpha1, alpha2]
    return Trajectory(t=np.array(t), x=x, speed=np.full(len(t), SPEED), model="reduced", integrator="-")


def test_rest_pose_and_wheel_spin():
    g = AxleGeometry.from_params()
    p = reduced_model_poses(one_sample(), ShimmyModel(), PRESSURE)
    np.testing.assert_allclose(p.bodies["wheel_right"].position[0], [0.0, -g.L / 2, g.R], atol=1e-15)
    np.testing.assert_allclose(p.bodies["wheel_left"].position[0], [0.0, g.L / 2, g.R], atol=1e-15)
    np.testing.assert_allclose(p.bodies["axle"].quaternion[0], [0, 0, 0, 1], atol=1e-15)
    np.testing.assert_allclose(p.force_vectors, 0.0, atol=1e-12)
    # After 0.5 s at V the wheel has turned V t / R about its own y axis (forward roll: top moves forward).
    top = rotate(p.bodies["wheel_right"].quaternion[1], [0.0, 0.0, g.R])
    angle = SPEED * 0.5 / g.R
    np.testing.assert_allclose(top, [g.R * np.sin(angle), 0.0, g.R * np.cos(angle)], atol=1e-12)


def test_tramp_raises_the_left_wheel():
    g = AxleGeometry.from_params()
    psi = 0.02
    p = reduced_model_poses(one_sample(psi=psi), ShimmyModel(), PRESSURE)
    np.testing.assert_allclose(p.bodies["wheel_left"].position[0, 2], g.R + g.L / 2 * np.sin(psi), rtol=1e-12)
    np.testing.assert_allclose(p.bodies["wheel_right"].position[0, 2], g.R - g.L / 2 * np.sin(psi), rtol=1e-12)


def test_yaw_about_the_tilted_kingpin():
    g = AxleGeometry.from_params()
    theta = 0.1
    p = reduced_model_poses(one_sample(theta1=theta), ShimmyModel(), PRESSURE)
    knuckle = p.bodies["knuckle_right"]
    e = np.array([-np.sin(g.gamma), 0.0, np.cos(g.gamma)])  # kingpin axis, top rearward
    np.testing.assert_allclose(g.kingpin_axis, e)
    np.testing.assert_allclose(rotate(knuckle.quaternion[0], e), e, atol=1e-15)  # the rotation is about it
    x_turned = rotate(knuckle.quaternion[0], [1.0, 0.0, 0.0])
    cos_expected = np.cos(theta) + (1 - np.cos(theta)) * e[0] ** 2  # Rodrigues, x . R x
    assert x_turned[0] == pytest.approx(cos_expected, rel=1e-14)
    np.testing.assert_allclose(knuckle.quaternion[1], knuckle.quaternion[0])  # knuckles do not spin
    # The wheel centre turned about the kingpin: same distance l from it, rotated by theta in plan view.
    offset = p.bodies["wheel_right"].position[0] - knuckle.position[0]
    np.testing.assert_allclose(np.linalg.norm(offset), g.l, rtol=1e-12)
    assert np.arctan2(offset[0], -offset[1]) == pytest.approx(theta, rel=2e-3)  # caster: 2nd order
    lateral = wheel_lateral_axis(p.bodies["wheel_right"].quaternion)[0]
    assert np.arctan2(-lateral[0], lateral[1]) == pytest.approx(theta, rel=2e-3)


def test_tyre_forces_act_behind_the_contact_with_the_model_force():
    alpha = np.radians(2.0)
    model = ShimmyModel()
    p = reduced_model_poses(one_sample(alpha1=alpha, alpha2=-alpha), model, PRESSURE)
    w_right, w_left = model.tyres(PRESSURE)
    np.testing.assert_allclose(p.lateral_forces()[0], [w_right.force.force(alpha), w_left.force.force(-alpha)],
                               rtol=1e-13)
    assert w_right.force.force(alpha) < 0.0 and p.force_vectors[0, 0, 1] < 0.0  # eq. 2.4: opposes the slip
    np.testing.assert_allclose(p.force_points[:, :, 2], 0.0, atol=1e-15)  # on the road
    behind = p.bodies["wheel_right"].position[0, 0] - p.force_points[0, 0, 0]
    assert behind == pytest.approx(w_right.trail_at(alpha), rel=1e-12)


def test_pose_dictionary_round_trip():
    p = reduced_model_poses(one_sample(theta1=0.05, psi=0.01), ShimmyModel(), PRESSURE)
    q = ScenePoses.from_dict(p.to_dict(), 2)
    for body in BODY_NAMES:
        np.testing.assert_array_equal(q.bodies[body].quaternion, p.bodies[body].quaternion)
    as_pairs = {k: ((v["position"], v["quaternion"]) if k in BODY_NAMES else v) for k, v in p.to_dict().items()}
    ScenePoses.from_dict(as_pairs, 2)
    with pytest.raises(ValueError, match="missing drag_link"):
        ScenePoses.from_dict({k: v for k, v in p.to_dict().items() if k != "drag_link"}, 2)


def test_multibody_pose_record_layout(tmp_path):
    """The multibody simulation's pose record (mbs_shimmy.simulation.pose_record), stored directly in extra."""
    short = simulate(n=51, seconds=0.1)
    p = reduced_model_poses(short, ShimmyModel(), PRESSURE)
    record = {"bodies": {name: {"position": p.bodies[name].position, "quaternion_xyzw": p.bodies[name].quaternion}
                         for name in BODY_NAMES},
              "links": dict(p.links),
              "contact": {side: {"point": p.force_points[:, k], "force": p.force_vectors[:, k] + [0.0, 0.0, 6e3]}
                          for k, side in enumerate(("right", "left"))},
              "travel": np.zeros(51)}
    mbs = Trajectory(t=short.t, x=short.x, speed=short.speed, model="mbs", integrator="test", extra=record)
    path = str(tmp_path / "mbs.rrd")
    write_recording(path, mbs)
    vectors = np.array(rows(path, "/scene/tyre_forces").column("Arrows3D:vectors").to_pylist())
    np.testing.assert_allclose(vectors[:, :, 2], 6e3 * recording.FORCE_ARROW_M_PER_N, rtol=1e-6)
    left = p.lateral_forces()[:, 1]
    np.testing.assert_allclose(scalars(rows(path, FORCE_ENTITIES["left"])),
                               left[recording.series_indices(short.t, left)], rtol=1e-12)
    with pytest.raises(ValueError, match="pose record is malformed"):
        ScenePoses.from_dict({"bodies": record["bodies"], "links": record["links"]}, 51)


def test_rerun_switched_off_is_reported(tmp_path, short, monkeypatch):
    """RERUN=off makes the SDK drop everything silently; the read-back turns that into an error."""
    monkeypatch.setenv("RERUN", "off")
    with pytest.raises(RecordingError, match="RERUN=off"):
        write_recording(str(tmp_path / "r.rrd"), short, pressures=PRESSURE)
    assert os.listdir(tmp_path) == []
