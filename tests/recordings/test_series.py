"""``shimmy simulate --series``: the time series as CSV or Parquet, in interface units, with the detected mode."""

import json

import numpy as np
import pyarrow.csv as pacsv
import pyarrow.parquet as pq
import pytest

from comparisons.cli.main import main
from comparisons.recordings.series import mode_per_sample


def test_mode_per_sample():
    t = np.array([0.0, 0.5, 1.0, 1.5, 2.0])
    assert mode_per_sample(t, [(0.0, "yaw"), (1.0, "tramp")]) == ["yaw", "yaw", "tramp", "tramp", "tramp"]
    assert mode_per_sample(t, [(0.7, "yaw")]) == ["", "", "yaw", "yaw", "yaw"]


def test_csv_and_parquet_hold_the_run(tmp_path, capsys):
    csv, parquet = tmp_path / "run.csv", tmp_path / "run.parquet"
    args = ["simulate", "--pressure", "1.5", "--speed", "60", "--duration", "1.5"]
    assert main(args + ["--series", str(csv)]) == 0
    assert main(args + ["--series", str(parquet), "--json", "--set", "t0=0.08"]) == 0
    out = json.loads(capsys.readouterr().out.split("time series written")[-1].split("\n", 1)[1])
    a = pacsv.read_csv(csv)
    b = pq.read_table(parquet)
    assert a.column_names == ["time_s", "speed_kmh", "theta1_deg", "theta1_dot_deg_per_s", "theta2_deg",
                              "theta2_dot_deg_per_s", "psi_deg", "psi_dot_deg_per_s", "alpha1_deg", "alpha2_deg",
                              "mode"]
    assert b.column_names == a.column_names and a.num_rows == 1501
    assert a.column("theta1_deg")[0].as_py() == pytest.approx(np.degrees(0.01), rel=1e-12)   # default start
    np.testing.assert_allclose(a.column("speed_kmh").to_numpy(), 60.0, rtol=1e-14)
    assert set(a.column("mode").to_pylist()) == {"yaw"} and out["final"]["mode"] == "yaw"
    assert out["schedule"] == {"speed_kmh": 60.0} and out["fidelity"] is None and out["duration_requested_s"] == 1.5
    meta = json.loads(b.schema.metadata[b"shimmy"])
    assert meta["units"]["psi_dot_deg_per_s"] == "deg/s" and meta["axle"]["overrides"] == {"t0": 0.08}
    assert meta["pressure_bar"] == 1.5 and meta["schedule"] == "60 km/h"


def test_bad_series_name_is_refused_before_the_run(tmp_path, capsys):
    assert main(["simulate", "--pressure", "1.5", "--speed", "60", "--series", str(tmp_path / "x.xlsx")]) == 2
    err = capsys.readouterr().err
    assert "must end in .csv or .parquet" in err and len(err.splitlines()) == 1
    assert main(["simulate", "--pressure", "1.5", "--speed", "60", "--series", str(tmp_path / "no" / "x.csv")]) == 2
