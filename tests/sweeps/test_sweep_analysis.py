"""Sensitivity estimates of `shimmy sweep` against a function with known Sobol' indices; maps and plot."""

from __future__ import annotations

import math

import numpy as np
import pyarrow as pa

from axles.axle import AxleData
from comparisons.sweeps.analysis import OutputChoice, sensitivity, stability_fraction, write_plot
from comparisons.sweeps.design import make_design, parse_vary
from comparisons.sweeps.sample import SweepTask, evaluate_batch


def _linear_table(design):
    """y = 2 u1 + u2 with u the inputs scaled to [0, 1]: S1 = ST = (0.8, 0.2), SRC = (2, 1) / sqrt(5)."""
    u = (design.values - [0.5, 0.05]) / [3.0, 0.25]
    y = 2.0 * u[:, 0] + u[:, 1]
    return pa.table({"pressure": design.values[:, 0], "t0": design.values[:, 1], "onset_kmh": y,
                     "status": ["ok"] * len(y)})


def test_sobol_indices_and_src_of_a_known_function():
    variations = [parse_vary("pressure=uniform:0.5:3.5"), parse_vary("t0=uniform:0.05:0.3")]
    out = OutputChoice("onset_kmh")
    sal = make_design(variations, 1024, 5, "saltelli")
    s = sensitivity(_linear_table(sal), sal, out)
    assert s.method == "sobol"
    for name, want in (("pressure", 0.8), ("t0", 0.2)):
        assert abs(s.indices[name]["S1"] - want) < 0.05 and abs(s.indices[name]["ST"] - want) < 0.05
    qmc = make_design(variations, 256, 5, "sobol")
    r = sensitivity(_linear_table(qmc), qmc, out)
    assert r.method == "src" and abs(r.r2 - 1.0) < 1e-12
    y = _linear_table(qmc).column("onset_kmh").to_numpy()
    for j, (name, slope, ideal) in enumerate((("pressure", 2 / 3.0, 2 / math.sqrt(5)), ("t0", 1 / 0.25,
                                                                                        1 / math.sqrt(5)))):
        # exact for this sample's spreads; the ideal value for uncorrelated, infinitely many samples
        assert math.isclose(r.indices[name]["src"], slope * qmc.values[:, j].std() / y.std(), rel_tol=1e-9)
        assert abs(r.indices[name]["src"] - ideal) < 2e-3
    lo, hi = r.swing["pressure"]
    spread = np.quantile(qmc.values[:, 0], [0.05, 0.95])
    assert math.isclose(hi - lo, 2.0 * (spread[1] - spread[0]) / 3.0, rel_tol=1e-9)


def test_stability_map_and_plot_from_a_small_grid(tmp_path):
    design = make_design([parse_vary("pressure=1:3:3"), parse_vary("t0=0.05:0.1:2")], None, None)
    task = SweepTask(AxleData(), (), 2.5, 2.5, design.names)
    table = evaluate_batch(task, 0, 0, design.values)
    speeds = np.array([30.0, 60.0, 150.0, 250.0])
    frac = stability_fraction(table, "pressure", np.array([0.5, 1.5, 2.5, 3.5]), speeds)
    rows = table.to_pylist()
    for k, p in enumerate((1.0, 2.0, 3.0)):
        mine = [r for r in rows if r["pressure"] == p]
        for j, v in enumerate(speeds):
            unstable = [any(a <= v <= b for a, b in zip(r["unstable_from_kmh"], r["unstable_to_kmh"])) for r in mine]
            assert frac[j, k] == np.mean(unstable)
    path = tmp_path / "map.png"
    out = OutputChoice.parse(None, task)
    write_plot(str(path), table, design, task, out, sensitivity(table, design, out))
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
