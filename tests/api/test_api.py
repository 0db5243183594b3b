"""The notebook API (comparisons.api): the README's example as written, equal to the command's numbers; the typed
inputs and their errors; one simulate for both models; no Exudyn for reading an axle; the example notebook."""

import contextlib
import doctest
import io
import json
import math
import pathlib
import runpy
import subprocess
import sys

import numpy as np
import pytest

import comparisons.api as api
import comparisons.results as results
from comparisons.api import Axle, TyrePressures, hopf_points, simulate
from axles.axle_file import format_axle
from axles.limits import PRESSURE_RANGE_BAR, SPEED_RANGE_KMH
from axles.units import KMH
from bifurcation.special_points import BranchStatus
from axles.parameters import ParameterError
from reduced_model.trajectory import SimulationStatus

ROOT = pathlib.Path(__file__).resolve().parents[2]

README_EXAMPLE = '''\
from comparisons.api import Axle, TyrePressures, hopf_points

axle = Axle.paper()                          # or Axle.from_file("mytruck.toml")
family = axle.reduced(effects="hcl,pt").family(TyrePressures.both(1.5))   # bar
result = hopf_points(family, vmax_kmh=400)
print(result)                                # a table: speed km/h, frequency Hz, l1, criticality
print([round(p.speed_kmh, 3) for p in result.points])
'''


@pytest.fixture(scope="module")
def cli_hopf():
    out = subprocess.run([sys.executable, "-m", "comparisons.cli", "hopf", "--pressure", "1.5", "--effects", "hcl,pt",
                          "--json"], capture_output=True, text=True, cwd=ROOT, check=True)
    return json.loads(out.stdout)["hopf"]


def test_the_readme_holds_the_example_as_tested():
    assert f"```python\n{README_EXAMPLE}```" in (ROOT / "README.md").read_text()


def test_the_readme_example_runs_as_written_and_gives_the_commands_numbers(cli_hopf):
    namespace: dict = {}
    printed = io.StringIO()
    with contextlib.redirect_stdout(printed):
        exec(compile(README_EXAMPLE, "README.md", "exec"), namespace)
    points = namespace["result"].points
    assert len(cli_hopf) >= 2 and len(points) == len(cli_hopf)
    for mine, theirs in zip(points, cli_hopf):
        assert mine.speed_kmh == pytest.approx(theirs["speed_kmh"], rel=0, abs=1e-9)
        assert mine.frequency_hz == pytest.approx(theirs["frequency_hz"], rel=0, abs=1e-9)
        assert mine.first_lyapunov == pytest.approx(theirs["first_lyapunov"], rel=1e-9, abs=0)
        assert mine.criticality.value == theirs["criticality"]
        assert mine.speed == pytest.approx(theirs["speed_kmh"] * KMH, rel=1e-12)   # SI in the field
    lines = printed.getvalue().splitlines()
    assert lines[-1] == str([round(h["speed_kmh"], 3) for h in cli_hopf])
    table = "\n".join(lines[:-1])
    assert "speed km/h" in table and "frequency Hz" in table and "criticality" in table
    for h in cli_hopf:
        assert f"{h['speed_kmh']:.4f}" in table and h["criticality"] in table


def test_a_result_renders_as_html_with_labelled_units():
    result = hopf_points(Axle.paper().reduced().family(TyrePressures.of_bar(2.0, 1.8)), vmax_kmh=150)
    html = result._repr_html_()
    assert html.startswith("<table>") and "<th>speed km/h</th>" in html and "right 2 / left 1.8 bar" in html
    assert html.count("<tr>") == len(result.points) + 1 and result.status is BranchStatus.COMPLETE
    assert all(SPEED_RANGE_KMH[0] <= p.speed_kmh <= 150 for p in result.points)


# --- inputs -----------------------------------------------------------------------------------------------------

@pytest.mark.parametrize("right, left, side", [(PRESSURE_RANGE_BAR[1] * 1.5, 1.5, "right"),
                                               (1.5, PRESSURE_RANGE_BAR[0] / 2, "left"),
                                               (float("nan"), 1.5, "right"), (1.5, -1.0, "left")])
def test_a_pressure_outside_its_range_is_a_one_line_parameter_error(right, left, side):
    lo, hi = PRESSURE_RANGE_BAR
    with pytest.raises(ParameterError) as exc:
        TyrePressures.of_bar(right, left)
    message = str(exc.value)
    assert "\n" not in message and message.startswith(f"{side} tyre pressure must be within [{lo:g}, {hi:g}] bar")


def test_pressures_become_pascal_in_one_place():
    lo, hi = PRESSURE_RANGE_BAR
    assert TyrePressures.both(lo).right == lo * 1e5 and TyrePressures.both(hi).left == hi * 1e5   # ends inside
    assert TyrePressures.of_bar(1.5, 1.2) == TyrePressures(1.5e5, 1.2e5)
    assert TyrePressures.of_bar(1.5, 1.2).right_bar == 1.5 and TyrePressures.both(2).alike
    assert str(TyrePressures.of_bar(1.5, 1.2)) == "right 1.5 / left 1.2 bar" and str(TyrePressures.both(2)) == "2 bar"
    with pytest.raises(ParameterError, match="must be a number"):
        TyrePressures.both("1.5")
    family = Axle.paper().reduced().family(TyrePressures.of_bar(1.5, 1.2))
    assert family.problem.pressures == TyrePressures(1.5e5, 1.2e5) and family.q == pytest.approx(1.35e5)


def test_an_axle_with_values_in_interface_units_and_from_its_file(tmp_path):
    axle = Axle.paper().with_values(gamma=4.0, k1=40000.0)
    assert axle.value("gamma") == 4.0 and axle.params.gamma == pytest.approx(math.radians(4.0))
    assert axle.with_set("gamma=3", "k1=40000").params == Axle.paper().with_values(gamma=3.0, k1=4e4).params
    path = tmp_path / "truck.toml"
    path.write_text(format_axle(axle.data))
    read = Axle.from_file(path)
    assert read.params == axle.params and read.dims == axle.dims and read.data.file == str(path)
    with pytest.raises(ParameterError, match=r"gamma = 90 deg is outside its physical range \["):
        axle.with_values(gamma=90.0)
    with pytest.raises(ParameterError, match="did you mean 'gamma'"):
        axle.with_set("gama=3")


def test_fidelity_comes_from_a_name_or_the_assumptions_kept():
    assert Axle.paper().mbs().fidelity.label == "reduced" and Axle.paper().mbs("full").fidelity.label == "full"
    kept = Axle.paper().mbs(assume=("small_angles",)).fidelity
    assert kept.names == ("small_angles",)
    with pytest.raises(ParameterError, match="not both"):
        Axle.paper().mbs(fidelity="full", assume=("small_angles",))
    with pytest.raises(ParameterError, match="fidelity must be 'reduced' or 'full'"):
        Axle.paper().mbs(fidelity="fast")


# --- simulate: one call for both models --------------------------------------------------------------------------

def test_simulate_takes_the_same_call_for_both_models():
    axle = Axle.paper()
    call = dict(ramp_kmh=(40.0, 60.0, 0.5), duration_s=0.6, initial_deg={"theta1": 1.0, "psi_dot": 5.0})
    runs = [simulate(model, TyrePressures.of_bar(1.5, 1.3), **call) for model in (axle.reduced(), axle.mbs())]
    for run in runs:
        assert run.status is SimulationStatus.COMPLETE and run.duration == pytest.approx(0.6)
        assert run.trajectory.state("theta1")[0] == pytest.approx(math.radians(1.0), rel=1e-12)
        assert run.trajectory.state("psi_dot")[0] == pytest.approx(math.radians(5.0), rel=1e-12)
        assert run.trajectory.speed[0] == pytest.approx(40 * KMH) and run.trajectory.speed[-1] == pytest.approx(
            60 * KMH)
        assert "deg/s" in str(run) and "40 to 60 km/h" in str(run)
    reduced, mbs = runs
    assert (reduced.trajectory.model, mbs.trajectory.model) == ("reduced", "mbs")
    # With every assumption on, the MBS is the reduced model: the same motion (tests/mbs checks it closely).
    t = mbs.trajectory.t
    for name in ("theta1", "theta2", "psi"):
        mine = np.interp(t, reduced.trajectory.t, reduced.trajectory.state(name))
        assert np.max(np.abs(mine - mbs.trajectory.state(name))) < 1e-4 * math.radians(1.0) + 1e-6


@pytest.mark.parametrize("kwargs, message", [
    (dict(speed_kmh=60, ramp_kmh=(1, 2, 3)), "either speed_kmh or ramp_kmh"),
    (dict(), "either speed_kmh or ramp_kmh"),
    (dict(speed_kmh=SPEED_RANGE_KMH[1] * 2), f"speed_kmh must be within [{SPEED_RANGE_KMH[0]:g}, "),
    (dict(speed_kmh=60, initial_deg={"theta3": 1.0}), "unknown state 'theta3'"),
    (dict(speed_kmh=60, initial_deg={"theta1": 90.0}), "initial theta1 must be within [-45, 45] deg"),
    (dict(ramp_kmh=(20, 40)), "ramp_kmh must be (FROM, TO, SECONDS)"),
])
def test_simulate_refuses_bad_input_before_the_work(kwargs, message):
    with pytest.raises(ParameterError) as exc:
        simulate(Axle.paper().mbs(), TyrePressures.both(1.5), duration_s=kwargs.pop("duration_s", 1.0), **kwargs)
    assert message in str(exc.value)


# --- light import; the example notebook; the docstrings' examples -----------------------------------------------

def test_reading_an_axle_loads_no_exudyn_until_the_multibody_model_is_made():
    code = ("import sys, comparisons.api as api\n"
            "axle = api.Axle.paper().with_values(gamma=3.0)\n"
            "api.hopf_points(axle.reduced().family(api.TyrePressures.both(1.5)), vmax_kmh=100)\n"
            "mbs = axle.mbs(fidelity='full')\n"
            "print('exudyn' in sys.modules)\n"
            "mbs.family(api.TyrePressures.both(1.5)).problem\n"
            "print('exudyn' in sys.modules)\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, check=True)
    assert out.stdout.split() == ["False", "True"]


def test_the_example_notebook_runs():
    printed = io.StringIO()
    with contextlib.redirect_stdout(printed):
        ns = runpy.run_path(str(ROOT / "docs" / "examples" / "notebook.py"))
    reduced, mbs, full = ns["reduced_hopf"], ns["mbs_hopf"], ns["full_hopf"]
    assert reduced.points and all(r.status is BranchStatus.COMPLETE for r in (reduced, mbs, full))
    # At the reduced fidelity the MBS has the reduced model's Hopf points; at full fidelity they move.
    assert [p.speed_kmh for p in mbs.points] == pytest.approx([p.speed_kmh for p in reduced.points], abs=1e-3)
    assert [p.first_lyapunov for p in mbs.points] == pytest.approx([p.first_lyapunov for p in reduced.points],
                                                                   rel=1e-3)
    assert abs(full.points[0].speed_kmh - reduced.points[0].speed_kmh) > 1.0
    # Windows by mode: every Hopf point in exactly one window, straight running unstable inside each window, a
    # mode's windows apart; the reduced model's 134.8 km/h point is the end of its yaw window (the index pairing once called it an onset), and its tramp onset is not dropped.
    for (name, found), hopf, model in zip(ns["windows"].items(), (reduced, full),
                                          (ns["reduced"], ns["axle"].mbs(fidelity="full", effects="hcl,pt"))):
        members = [p for w in found.windows for p in w.points]
        assert sorted(p.speed for p in members) == [p.speed for p in hopf.points], name
        problem = model.family(ns["pressures"]).problem
        for w in found.windows:
            assert w.low < w.high
            middle = np.linalg.eigvals(problem.linear_matrix(0.5 * (w.low + w.high), problem.nominal))
            assert middle.real.max() > 0.0, (name, w.text())
        for mode in ("yaw", "tramp"):
            spans = [(w.low, w.high) for w in found.windows if w.mode == mode]
            assert all(a[1] <= b[0] for a, b in zip(spans, spans[1:])), (name, mode)
    (yaw,) = [w for w in ns["windows"]["the reduced model"].windows if w.mode == "yaw"]
    assert yaw.end.speed_kmh == pytest.approx(134.824, abs=1e-3) and yaw.onset.speed_kmh < 20.0
    assert [w.end for w in ns["windows"]["the reduced model"].windows if w.mode == "tramp"] == [None]
    assert "tramp from 170.663 to the top of the window" in printed.getvalue()
    (branch,) = ns["cycles"].branches
    assert branch.start.speed == pytest.approx(reduced.points[0].speed, rel=1e-9) and branch.peak_theta1 > 0.0
    assert all(run.status is SimulationStatus.COMPLETE for run in ns["runs"].values())
    assert "differs from the paper in gamma = 4 deg" in printed.getvalue()


@pytest.mark.parametrize("module", [api, results])
def test_the_docstring_examples_hold(module):
    outcome = doctest.testmod(module)
    assert outcome.attempted > 0 and outcome.failed == 0
