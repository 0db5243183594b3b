"""What a person sees of a recording: min/max decimation that keeps every peak, the size of a 100 s run, and
the side-by-side recording of two models."""

import os

import numpy as np
import pyarrow as pa
import pytest
from rerun.chunk import RrdReader
from rrd_helpers import blueprint_views, rows, time_series_views

from axles.units import BAR, from_kmh
from comparisons.recordings import writer as recording
from comparisons.recordings.decimation import (cycle_envelopes, envelope_amplitude, envelope_indices, peak_loss,
                                               uniform_indices)
from comparisons.recordings.layout import WAVE_WINDOW_S, RunPaths
from comparisons.recordings.scene import reduced_model_poses
from comparisons.recordings.writer import ComparedRun, write_comparison, write_recording
from reduced_model.model import STATE_NAMES, ShimmyModel
from reduced_model.modes import ModeClassifier
from reduced_model.simulation import integrate
from reduced_model.trajectory import SpeedSchedule, Trajectory
from axles.pressures import TyrePressures


def test_envelope_keeps_every_peak_where_striding_loses_them():
    t = np.arange(0.0, 20.0, 1e-3)
    y = 12.0 * np.sin(2 * np.pi * 9.3 * t + 0.3) * np.minimum(t / 10.0, 1.0)
    kept = envelope_indices(t, y, 0.01)
    assert len(kept) <= 2 * 2000 + 2
    assert peak_loss(y, kept) == 0.0
    # The measure can fail: a 100 Hz stride cuts the 9.3 Hz peaks by 1 - cos(pi 9.3/100) ~ 4 %.
    assert 0.03 < peak_loss(y, uniform_indices(t, 100.0)) < 0.05
    # Hand-made: a peak dropped from the kept set is missed by exactly its excess over its neighbours.
    z = np.array([0.0, 1.0, 3.0, 1.0, 0.0, -2.0, 0.0])
    assert peak_loss(z, np.array([0, 1, 3, 4, 5, 6])) == pytest.approx(2.0 / 3.0)
    assert peak_loss(z, np.arange(7)) == 0.0


def test_envelope_indices_per_bin():
    t = np.arange(10) * 0.1
    y = np.array([0.0, 5.0, -1.0, 2.0, 2.0, 7.0, 1.0, -3.0, 4.0, 0.0])
    # Bins of 0.3 s: [0, 1, 2], [3, 4, 5], [6, 7, 8], [9]; min and max of each, plus both ends.
    np.testing.assert_array_equal(envelope_indices(t, y, 0.3 - 1e-9), [0, 1, 2, 3, 5, 7, 8, 9])


@pytest.fixture(scope="module")
def ramp(tmp_path_factory):
    """The issue's example: t = 0.25 m, 1.5 bar, 120-200 km/h in 100 s, the tramp cycle in its last 30 s."""
    model = ShimmyModel().with_params(t0=0.25)
    tr = integrate(model, TyrePressures.uniform(1.5 * BAR), SpeedSchedule.ramp(from_kmh(120), from_kmh(200), 100.0), 100.0)
    history = ModeClassifier().classify(tr)
    path = tmp_path_factory.mktemp("ramp") / "ramp.rrd"
    summary = write_recording(str(path), tr, history.segments(), history.switches, "ramp", model=model,
                              pressures=TyrePressures.uniform(1.5 * BAR))
    return tr, summary


def test_100_s_run_is_small_and_keeps_its_peaks(ramp):
    tr, summary = ramp
    assert np.max(np.abs(np.degrees(tr.state("theta1")[tr.t > 70.0]))) > 10.0   # a real tramp cycle
    assert summary.bytes == os.path.getsize(summary.path) <= 15e6     # was 57 MB at 1 kHz
    for k, name in enumerate(STATE_NAMES):
        y = tr.x[:, k]
        table = rows(summary.path, recording.STATE_ENTITIES[name])
        recorded_ns = table.column("sim_time").cast(pa.int64()).to_numpy()
        kept = np.searchsorted(recording.time_ns(tr.t), recorded_ns)
        assert len(kept) < 0.25 * len(tr.t)
        assert peak_loss(y, kept) <= 0.01, name


def side_by_side_runs(n=401, seconds=2.0):
    model = ShimmyModel()
    reduced = integrate(model, TyrePressures.uniform(1.5 * BAR), SpeedSchedule.constant(from_kmh(60)), seconds,
                       sample_interval=seconds / (n - 1))
    poses = reduced_model_poses(reduced, model, TyrePressures.uniform(1.5 * BAR)).to_dict()
    # A stand-in for the MBS: the same motion, twice the yaw, its own poses.
    x = reduced.x.copy()
    x[:, 0] *= 2.0
    mbs = Trajectory(t=reduced.t, x=x, speed=reduced.speed, model="mbs", integrator="test", extra={"poses": poses})
    return model, reduced, mbs


def test_side_by_side_recording(tmp_path):
    model, reduced, mbs = side_by_side_runs()
    path = str(tmp_path / "both.rrd")
    summary = write_comparison(path, [ComparedRun(reduced, [(0.0, "yaw")]), ComparedRun(mbs, [(0.0, "straight"),
                                                                                               (1.0, "yaw")])],
                               "both", model=model, pressures=TyrePressures.uniform(1.5 * BAR))
    assert summary.path == path and os.path.getsize(path) > 0
    store = RrdReader(path).store().summary()
    for key in ("reduced", "mbs"):
        p = RunPaths(key)
        assert f"{p.scene}/wheel_left" in store and p.state("theta1") in store and p.mode in store
    # Each state of both models under one parent: one plot per state overlays them.
    for key, tr in (("reduced", reduced), ("mbs", mbs)):
        values = np.array(rows(path, f"/states/theta1_deg/{key}").column("Scalars:scalars").to_pylist())[:, 0]
        assert values.max() == pytest.approx(np.degrees(tr.state("theta1")).max(), rel=1e-12)
    views = blueprint_views(path)
    assert views["3D"] == {"/scene/reduced", "/scene/mbs"}
    assert "/states/theta1_deg" in views["TimeSeries"] and "/states/psi_deg" in views["TimeSeries"]
    assert views["StateTimeline"] == {"/mode"}
    with pytest.raises(ValueError, match="different models"):
        write_comparison(str(tmp_path / "x.rrd"), [ComparedRun(reduced), ComparedRun(reduced)], pressures=TyrePressures.uniform(1.5 * BAR))


@pytest.mark.slow
@pytest.mark.skipif(__import__("comparisons.recordings.screenshots", fromlist=["x"]).lavapipe_icd() is None,
                    reason="no software Vulkan driver (Debian: apt-get install -y mesa-vulkan-drivers)")
def test_screenshot_in_the_real_viewer(tmp_path):
    """The README's screenshots come from the real viewer, headless (about 10 s)."""
    import matplotlib.image

    from comparisons.recordings.screenshots import take_screenshots
    model, reduced, mbs = side_by_side_runs()
    path = str(tmp_path / "both.rrd")
    write_comparison(path, [ComparedRun(reduced, [(0.0, "yaw")]), ComparedRun(mbs, [(0.0, "yaw")])], "both",
                     model=model, pressures=TyrePressures.uniform(1.5 * BAR))
    (png,) = take_screenshots(path, [1.0], str(tmp_path / "shots"), size="1200x800")
    image = matplotlib.image.imread(png)
    assert image.shape[0] >= 800 and image.shape[1] >= 1200
    assert np.std(image[..., :3]) > 0.05          # not a blank frame


def test_cycle_envelopes_follow_every_swing():
    t = np.arange(0.0, 10.0, 1e-3)
    amplitude = np.where(t < 6.0, 3.0 + t, 0.0)                  # growing, then gone (straight running)
    y = 1.0 + amplitude * np.sin(2 * np.pi * 5.0 * t) + 1e-9 * np.sin(2 * np.pi * 400.0 * t)
    upper, lower = cycle_envelopes(t, y, 0.05)
    swings = t < 6.0
    # One point per swing (5 Hz for 6 s) and at most one per 50 ms bin after it, plus both ends.
    assert abs(np.sum(t[upper] < 6.0) - 30) <= 2 and len(upper) <= 30 + 4 * 20 + 2
    np.testing.assert_allclose(y[upper][t[upper] < 5.9][1:], 1.0 + (3.0 + t[upper][t[upper] < 5.9][1:]), atol=1e-3)
    np.testing.assert_allclose(y[lower][t[lower] < 5.9][1:], 1.0 - (3.0 + t[lower][t[lower] < 5.9][1:]), atol=1e-3)
    assert upper[0] == lower[0] == 0 and upper[-1] == lower[-1] == len(t) - 1
    grid = np.arange(1.0, 5.5, 0.02)
    # The amplitude ignores the offset 1.0; linear interpolation between swings is exact for a linear growth.
    np.testing.assert_allclose(envelope_amplitude(t, y, grid, 0.05), 3.0 + grid, atol=0.11)
    assert np.all(np.abs(envelope_amplitude(t, y, np.arange(6.5, 9.9, 0.1), 0.05)) < 1e-8)
    assert swings.any()
    # At rest for 2 s, then swinging: the envelopes follow the rest, they do not cut across to the first swing.
    z = np.where(t < 2.0, 0.0, 4.0 * np.sin(2 * np.pi * 5.0 * (t - 2.0)))
    upper, lower = cycle_envelopes(t, z, 0.05)
    assert np.max(np.abs(np.interp(np.arange(0.0, 1.95, 0.01), t[upper], z[upper]))) == 0.0
    assert np.max(np.abs(np.interp(np.arange(0.0, 1.95, 0.01), t[lower], z[lower]))) == 0.0
    assert np.sum(t[upper] < 2.0) <= 41


def test_recording_has_envelopes_waveform_window_and_no_legend_on_the_data(ramp):
    tr, summary = ramp
    paths = RunPaths()
    y = np.degrees(tr.state("theta1"))
    for bound, pick in (("upper", np.max), ("lower", np.min)):
        table = rows(summary.path, paths.envelope("theta1_deg", bound))
        values = np.array(table.column("Scalars:scalars").to_pylist())[:, 0]
        assert len(values) < 0.02 * len(tr.t)          # a point per swing, not a band of samples
        assert pick(values) == pytest.approx(pick(y), rel=1e-12)
    assert rows(summary.path, paths.envelope("tyre_forces/right_N", "upper")).num_rows > 10
    views = time_series_views(summary.path)
    by_origin = {}
    for v in views:
        by_origin.setdefault(v["origin"], []).append(v)
    assert by_origin["/envelopes"][0]["axis"] == ("Absolute", 0, recording.time_ns(tr.t[-1]))
    (wave,) = [v for v in by_origin["/states"]]
    half = int(0.5 * WAVE_WINDOW_S * 1e9)
    assert wave["axis"] == ("CursorRelative", -half, half)
    assert all(v["legend"] is False for v in views)               # the view names say which colour is which
    assert "theta1 blue" in wave["name"] and "psi green" in wave["name"]


def test_side_by_side_draws_the_difference_and_every_run_visibly(tmp_path):
    model, reduced, mbs = side_by_side_runs(n=2001, seconds=4.0)
    path = str(tmp_path / "both.rrd")
    write_comparison(path, [ComparedRun(reduced, [(0.0, "yaw")]),
                            ComparedRun(mbs, [(0.0, "yaw")], title="full geometry, MBS")],
                     "both", model=model, pressures=TyrePressures.uniform(1.5 * BAR))
    # The stand-in MBS has twice the reduced model's theta1 and the same psi: the difference of the
    # amplitudes is the reduced model's theta1 amplitude, and zero for psi.
    diff = rows(path, RunPaths("mbs").difference("theta1_deg"))
    t = diff.column("sim_time").cast(pa.int64()).to_numpy() * 1e-9
    values = np.array(diff.column("Scalars:scalars").to_pylist())[:, 0]
    theta1 = np.degrees(reduced.state("theta1"))
    expected = envelope_amplitude(reduced.t, theta1, t, 0.05)
    np.testing.assert_allclose(values, expected, atol=1e-9)
    assert np.max(np.abs(values)) > 0.1
    psi = np.array(rows(path, RunPaths("mbs").difference("psi_deg")).column("Scalars:scalars").to_pylist())
    assert np.max(np.abs(psi)) < 1e-9
    for key in ("reduced", "mbs"):
        assert rows(path, RunPaths(key).envelope("theta1_deg", "upper")).num_rows > 5
    views = time_series_views(path)
    origins = {v["origin"] for v in views}
    assert {"/envelopes/theta1_deg", "/envelopes/psi_deg", "/states/theta1_deg", "/difference"} <= origins
    (difference,) = [v for v in views if v["origin"] == "/difference"]
    assert "full geometry, MBS minus reduced model" in difference["name"]
    assert all(v["legend"] is False for v in views)
    # Neither run hides the other: the second is drawn wider and translucent around the first.
    styles = {}
    for key in ("reduced", "mbs"):
        static = [c.to_record_batch() for c in RrdReader(path).stream().filter(
            content=RunPaths(key).envelope("theta1_deg", "upper"), is_static=True)]
        batch = next(b for b in static if "SeriesLines:widths" in b.schema.names)
        styles[key] = (batch.column("SeriesLines:widths").to_pylist()[0][0],
                       batch.column("SeriesLines:colors").to_pylist()[0][0] & 0xFF)
    assert styles["mbs"][0] > 2 * styles["reduced"][0] and styles["mbs"][1] < 0xFF == styles["reduced"][1]
