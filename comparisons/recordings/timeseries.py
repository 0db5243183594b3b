"""The plotted series of a recording (:mod:`comparisons.recordings.writer` writes the rest): each series' waveform
decimated to its per-bin extremes, its per-cycle envelopes, and in side-by-side files the difference of the runs'
amplitudes; their styles (name, colour, width, min/max aggregation).  Entity paths are in
:mod:`comparisons.recordings.layout`; a ``run`` is the writer's prepared run (its ``trajectory``, ``paths``,
``title``, ``series()`` and ``enveloped()``)."""

from __future__ import annotations

import numpy as np

from comparisons.recordings.decimation import cycle_envelopes, envelope_amplitude, envelope_indices
from comparisons.recordings.layout import ENVELOPE_BOUNDS, FORCE_COLOURS, RUN_WIDTHS, STATE_COLOURS, TIMELINE, series_leaves

SERIES_BIN_S = 0.01             # min and max of every 10 ms: at most 200 samples per second and series
ENVELOPE_MIN_PERIOD_S = 0.05    # one envelope point per swing of any oscillation below 20 Hz (shimmy: 3-12 Hz)
DIFFERENCE_RATE_HZ = 50.0       # the amplitude difference: 5-10 points per shimmy cycle


def time_ns(t) -> np.ndarray:
    """Simulated time as integer nanoseconds (rounded: float durations would be truncated by Rerun)."""
    return np.round(np.asarray(t, dtype=float) * 1e9).astype(np.int64)


def series_indices(t: np.ndarray, values: np.ndarray) -> np.ndarray:
    """The samples of one waveform that go into a recording: its lowest and highest in every
    :data:`SERIES_BIN_S` (:func:`~comparisons.recordings.decimation.envelope_indices`)."""
    return envelope_indices(t, values, SERIES_BIN_S)


def time_index(rr, seconds: np.ndarray):
    """The timeline column of ``seconds`` (integer nanoseconds)."""
    return [rr.TimeColumn(TIMELINE, duration=time_ns(seconds).astype("timedelta64[ns]"))]


def series_style(rec, entity: str, name: str, colour: int, width: float = RUN_WIDTHS[0]) -> None:
    """A series' name, colour and width, drawn with min/max aggregation (static, on its entity)."""
    import rerun as rr
    rec.log(entity, rr.SeriesLines(names=[name], colors=[colour], widths=[width], aggregation_policy="minmax"),
            static=True)


def log_series(rec, run) -> None:
    import rerun as rr
    t = run.trajectory.t
    for entity, values in run.series().items():
        idx = series_indices(t, values)
        rec.send_columns(entity, indexes=time_index(rr, t[idx]), columns=rr.Scalars.columns(scalars=values[idx]))


def log_envelopes(rec, run) -> None:
    """Every series' per-cycle upper and lower envelope (:func:`comparisons.recordings.decimation.cycle_envelopes`)."""
    import rerun as rr
    t, leaves = run.trajectory.t, series_leaves()
    for key, values in run.enveloped().items():
        for bound, idx in zip(ENVELOPE_BOUNDS, cycle_envelopes(t, values, ENVELOPE_MIN_PERIOD_S)):
            rec.send_columns(run.paths.envelope(leaves[key], bound), indexes=time_index(rr, t[idx]),
                             columns=rr.Scalars.columns(scalars=values[idx]))


def difference_grid(runs: list) -> np.ndarray:
    """The times (s) where every run has data, at :data:`DIFFERENCE_RATE_HZ`."""
    start = max(float(r.trajectory.t[0]) for r in runs)
    end = min(float(r.trajectory.t[-1]) for r in runs)
    return np.arange(start, end, 1.0 / DIFFERENCE_RATE_HZ) if end > start else np.array([])


def log_differences(rec, runs: list) -> None:
    """Side by side: each run's amplitude minus the first run's, per series, on :func:`difference_grid`."""
    import rerun as rr
    grid = difference_grid(runs)
    if len(runs) < 2 or len(grid) < 2:
        return
    reference, leaves = runs[0], series_leaves()
    ref_values = reference.enveloped()
    for run in runs[1:]:
        for key, values in run.enveloped().items():
            diff = (envelope_amplitude(run.trajectory.t, values, grid, ENVELOPE_MIN_PERIOD_S)
                    - envelope_amplitude(reference.trajectory.t, ref_values[key], grid, ENVELOPE_MIN_PERIOD_S))
            entity = run.paths.difference(leaves[key])
            colour = STATE_COLOURS.get(key) or FORCE_COLOURS[key.split()[-1]]
            series_style(rec, entity, f"{key}: {run.title.split(' (')[0]} minus {reference.title.split(' (')[0]}",
                          colour)
            rec.send_columns(entity, indexes=time_index(rr, grid), columns=rr.Scalars.columns(scalars=diff))
