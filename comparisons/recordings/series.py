"""A simulated run as a table (``shimmy simulate --series FILE.csv|.parquet``): one row per sample with the time,
the speed, every state in interface units (degrees, degrees per second) and the detected mode.

Columns: ``time_s``, ``speed_kmh``, ``<state>_deg`` / ``<state>_dot_deg_per_s`` in the order of
:data:`reduced_model.model.STATE_NAMES`, ``mode`` (straight, yaw, tramp, ... as detected over the preceding
window by :class:`reduced_model.modes.ModeClassifier`).  Parquet files also carry the run's inputs (axle,
pressures, effects, model, speed schedule) as JSON in the schema metadata key ``shimmy``.
"""

from __future__ import annotations

import json
import os

import numpy as np

from axles.units import kmh
from comparisons.files import atomic_path
from comparisons.recordings.layout import STATE_LEAVES, STATE_UNIT_LABELS
from comparisons.recordings.writer import mode_label
from reduced_model.model import STATE_NAMES
from reduced_model.trajectory import Trajectory

FORMATS = (".csv", ".parquet")


def series_format(path: str) -> str:
    """".csv" or ".parquet" from the file name; ValueError otherwise."""
    ext = os.path.splitext(path)[1].lower()
    if ext not in FORMATS:
        raise ValueError(f"--series {path}: the name must end in .csv or .parquet")
    return ext


def mode_per_sample(t: np.ndarray, segments) -> list[str]:
    """The mode label of each sample from (start time s, mode) segments; "" before the first segment."""
    if not segments:
        return [""] * len(t)
    starts = np.array([s for s, _ in segments])
    labels = np.array([mode_label(m) for _, m in segments] + [""], dtype=object)
    k = np.searchsorted(starts, t, side="right") - 1
    return list(labels[np.where(k >= 0, k, -1)])


def series_table(trajectory: Trajectory, segments, inputs: dict | None = None):
    """The run as a pyarrow Table (module docstring)."""
    import pyarrow as pa
    columns = {"time_s": np.asarray(trajectory.t, dtype=float),
               "speed_kmh": kmh(np.asarray(trajectory.speed, dtype=float))}
    for k, name in enumerate(STATE_NAMES):
        columns[STATE_LEAVES[name]] = np.degrees(trajectory.x[:, k])
    columns["mode"] = mode_per_sample(trajectory.t, segments)
    table = pa.table(columns)
    meta = {"units": {"time_s": "s", "speed_kmh": "km/h",
                      **{STATE_LEAVES[n]: STATE_UNIT_LABELS[n] for n in STATE_NAMES}},
            "model": trajectory.model, "integrator": trajectory.integrator, "status": trajectory.status.value,
            **(inputs or {})}
    return table.replace_schema_metadata({"shimmy": json.dumps(meta)})


def write_series(path: str, table) -> None:
    """Write ``table`` as CSV or Parquet by the file name, atomically."""
    ext = series_format(path)
    with atomic_path(path) as tmp:
        if ext == ".csv":
            import pyarrow.csv as pacsv
            pacsv.write_csv(table, tmp)
        else:
            import pyarrow.parquet as pq
            pq.write_table(table, tmp)
