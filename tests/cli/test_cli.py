"""The ``shimmy`` command line: JSON schemas, plots and one-line errors with exit code 2."""

import json
import subprocess
import sys

import pytest

from comparisons.cli.main import main


def run(*args):
    proc = subprocess.run([sys.executable, "-m", "comparisons.cli", *args], capture_output=True, text=True,
                          timeout=300)
    return proc.returncode, proc.stdout, proc.stderr


def test_hopf_json_schema(capsys):
    assert main(["hopf", "--pressure", "2.5", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["pressure_bar"] == 2.5 and out["effects"] == []
    assert [round(h["speed_kmh"], 2) for h in out["hopf"]] == [46.14, 70.5]
    assert {h["criticality"] for h in out["hopf"]} == {"supercritical"}
    assert all(set(h) == {"speed_kmh", "frequency_hz", "first_lyapunov", "criticality", "kink_coefficient",
                          "kink_criticality"} for h in out["hopf"])
    # the reduced model is smooth at straight running: no kink coefficient
    assert all(h["kink_coefficient"] is None and h["kink_criticality"] is None for h in out["hopf"])


def test_hopf_with_effects_and_set(capsys):
    assert main(["hopf", "--pressure", "1.5", "--effects", "all", "--set", "t0=0.1", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["effects"] == ["hcl", "pt", "rl", "vs"]


def test_curves_json_and_plot(tmp_path, capsys):
    png = tmp_path / "fig.png"
    assert main(["curves", "--param", "a0", "--range", "0.1", "0.3", "--pressure", "2.5", "--json",
                 "--plot", str(png)]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["curves"] and all(len(c["points"][0]) == 2 for c in out["curves"])
    kinds = [s["kind"] for s in out["special_points"]]
    assert kinds.count("hopf_fold") == 1
    assert png.stat().st_size > 10_000


def test_params_lists_table1(capsys):
    assert main(["params", "--json"]) == 0
    rows = json.loads(capsys.readouterr().out)["parameters"]
    pi0 = next(r for r in rows if r["name"] == "pi0")
    assert pi0["value"] == 2.5 and pi0["unit"] == "bar"


@pytest.mark.parametrize("args, fragment", [
    (["hopf", "--pressure", "-1"], "must be within [0.05, 20] bar"),
    (["hopf", "--pressure", "0"], "must be within [0.05, 20] bar"),
    (["hopf", "--pressure", "abc"], "must be a number"),
    (["hopf", "--pressure", "2", "--vmax", "-5"], "must be within (0.5, 1000] km/h"),
    (["hopf", "--pressure", "2", "--set", "zz=1"], "unknown parameter 'zz'"),
    (["hopf", "--pressure", "2", "--set", "t0"], "NAME=VALUE"),
    (["hopf", "--pressure", "2", "--set", "t0=x"], "not a number"),
    (["hopf", "--pressure", "2", "--effects", "hcl,foo"], "unknown effect 'foo'"),
    (["hopf", "--pressure", "2", "--set", "sigma0=-0.3"], "sigma0 = -0.3 m is outside its physical range"),
    (["hopf", "--pressure", "2", "--set", "k5_0=-1"], "k5_0 = -1 N/m is outside its physical range"),
    (["hopf", "--pressure", "9"], "cornering stiffness"),
    (["hopf", "--pressure", "3.5", "--effects", "pt", "--set", "p_pz1=3"], "pneumatic trail"),
    (["curves", "--param", "t0", "--range", "0.3", "0.1"], "LO < HI"),
    (["curves", "--param", "t0", "--range", "-0.1", "0.1"], "must lie within [0.001, 0.5] m"),
    (["curves", "--param", "zz", "--range", "0.1", "0.2"], "invalid choice"),
    (["bench", "nosuch"], "unknown benchmark"),
])
def test_bad_input_is_one_line_exit_2(args, fragment):
    code, out, err = run(*args)
    assert code == 2
    lines = err.strip().splitlines()
    assert len(lines) == 1 and fragment in lines[0] and "Traceback" not in err


def test_hopf_mbs_fidelities(capsys):
    assert main(["hopf", "--pressure", "2.5", "--model", "mbs", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["model"] == "mbs" and out["fidelity"] == "reduced"
    assert [round(h["speed_kmh"], 2) for h in out["hopf"]] == [46.14, 70.5]
    # The MBS's l1 (from its family's difference derivatives) is the reduced model's with every assumption on.
    assert main(["hopf", "--pressure", "2.5", "--json"]) == 0
    reduced = json.loads(capsys.readouterr().out)["hopf"]
    assert [h["criticality"] for h in out["hopf"]] == [h["criticality"] for h in reduced] != [None, None]
    assert [h["first_lyapunov"] for h in out["hopf"]] == pytest.approx([h["first_lyapunov"] for h in reduced],
                                                                      rel=1e-6)
    # The full geometry damps tramp through the sliding contact patch: no shimmy at 2.5 bar.
    assert main(["hopf", "--pressure", "2.5", "--model", "mbs", "--fidelity", "full", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["hopf"] == []


def test_simulate_mbs_with_recording(tmp_path):
    rrd = tmp_path / "run.rrd"
    code, out, err = run("simulate", "--model", "mbs", "--pressure", "1.5", "--speed", "60", "--duration", "3",
                         "--rerun", str(rrd), "--json")
    assert code == 0, err
    result = json.loads(out)
    assert result["model"] == "mbs" and result["final"]["mode"] == "yaw"
    assert rrd.stat().st_size > 100_000


def test_a_ratio_target_judges_the_ratio_not_the_time():
    """A benchmark with a ratio target is met by its ratio to the in-process baseline, so that a busy machine (slow
    baseline, slow run) does not fail it and a fast machine does not pass a slower program."""
    from comparisons.cli.benchmarks import BenchResult
    busy = BenchResult("x", "d", median_s=0.25, runs=(0.25,), baseline_s=0.02, target_s=0.2, target_ratio=13.7)
    assert busy.ratio == 12.5 and busy.meets_target and not busy.meets_time_target
    slower_program = BenchResult("x", "d", median_s=0.15, runs=(0.15,), baseline_s=0.01, target_s=0.2,
                                 target_ratio=13.7)
    assert slower_program.meets_time_target and not slower_program.meets_target
    assert BenchResult("x", "d", median_s=0.15, runs=(0.15,), baseline_s=0.01, target_s=0.2).meets_target


def test_the_simulation_benchmark_says_where_a_stage_goes():
    """The stage budget of ``shimmy bench mbs_simulation_full``: its parts are measured separately, so they must
    nest (marker reads and the compiled stage inside the force function, that inside the stage, the Python force
    function slower than the compiled one) and the evaluations must be those of the benchmark's run."""
    from comparisons.cli.benchmarks import BENCHMARKS
    (bench,) = [b for b in BENCHMARKS if b.name == "mbs_simulation_full"]
    run = bench.setup()
    trajectory = run()
    counts = bench.count(trajectory)
    assert counts["force_evaluations"] == trajectory.extra["force_evaluations"] > 5000
    assert counts["marker_reads_us"] > 0 and counts["compiled_stage_us"] > 0
    assert counts["marker_reads_us"] + counts["compiled_stage_us"] < counts["force_function_us"] * 1.2
    assert counts["force_function_us"] < counts["python_force_function_us"]
    assert 0 < counts["force_function_us"] < counts["stage_us"] and counts["exudyn_us"] > 0


def test_bench_counts_show_texts_and_small_residuals_as_they_are():
    """The twin's bench reports which derivatives it used (a text) and the largest Exudyn residual (about 1e-9):
    the text once raised a format error, and the residual read "0"."""
    from comparisons.cli.commands.bench import _count_text
    assert _count_text("twin and differences") == "twin and differences"
    assert _count_text(2.8e-9) == "2.8e-09"
    assert _count_text(3586) == "3,586" and _count_text(12.25) == "12.2" and _count_text(0.0) == "0"
