"""``shimmy margins`` (the least damping ratio of straight running over speed and pressure) and the margin panel
of ``shimmy curves --plot``."""

import json

import pytest

from comparisons.cli.main import main


def test_margins_json_of_the_full_geometry(capsys):
    assert main(["margins", "--model", "mbs", "--fidelity", "full", "--range", "1.5", "2.5", "--pressures", "3",
                 "--speeds", "9", "--vmax", "120", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["model"] == "mbs" and out["fidelity"] == "full"
    assert out["pressures_bar"] == [1.5, 2.0, 2.5] and out["speeds_kmh"][0] == 0.5 and out["speeds_kmh"][-1] == pytest.approx(120)
    assert len(out["damping_ratio"]) == 3 and all(len(row) == 9 for row in out["damping_ratio"])
    low = out["minimum"]
    assert low["damping_ratio"] == min(min(row) for row in out["damping_ratio"])
    assert low["damping_ratio"] < 0 and low["mode"] == "yaw" and low["pressure_bar"] == 1.5   # shimmy at 1.5 bar
    assert {m for row in out["mode"] for m in row} <= {"yaw", "tramp", "lateral", "bounce", "gear"}


def test_margins_text_and_plot(tmp_path, capsys):
    png = tmp_path / "margins.png"
    assert main(["margins", "--pressures", "4", "--speeds", "21", "--plot", str(png)]) == 0
    text = capsys.readouterr().out
    assert text.startswith("Stability margins, reduced model") and "0.5-3.5 bar" not in text
    assert "least damping ratio" in text and png.stat().st_size > 10_000


@pytest.mark.parametrize("args, fragment", [
    (["margins", "--range", "3", "2"], "LO < HI"),
    (["margins", "--range", "0.5", "30"], "must lie within"),
    (["margins", "--speeds", "0"], "--speeds must be a whole number within [1, 2001]"),
    (["margins", "--model", "reduced", "--fidelity", "full"], "apply to --model mbs only"),
])
def test_margins_bad_input_is_one_line_exit_2(args, fragment, capsys):
    assert main(args) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and fragment in err[0]


@pytest.mark.slow
def test_curves_over_pressure_plots_the_margin_panel(tmp_path):
    png = tmp_path / "curves.png"
    assert main(["curves", "--param", "pressure", "--range", "2.3", "2.8", "--vmax", "120", "--plot", str(png)]) == 0
    assert png.stat().st_size > 30_000
