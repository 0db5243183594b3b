"""Progress of the commands that can take long: plain lines on stderr when piped (at most one per
PLAIN_EVERY_S seconds, so that a short run prints none), nothing on stdout under --json; the cycle
continuation reports inside a branch (cycles so far, speed, collocation mesh), not only per branch."""

import io
import json

import pytest

from comparisons.cli import progress as progress_module
from comparisons.cli.main import main
from comparisons.cli.progress import PlainProgress


def test_plain_lines_are_spaced_and_close_with_the_time(monkeypatch):
    now = [0.0]
    monkeypatch.setattr(progress_module.time, "perf_counter", lambda: now[0])
    out = io.StringIO()
    with PlainProgress(4, "figures", stream=out, every=5.0) as bar:
        bar.update(1)                      # at 0 s: too soon
        now[0] = 6.0
        bar.update(1)                      # a line
        now[0] = 7.0
        bar.set_postfix_str("fig 3")       # too soon after the last
        now[0] = 12.0
        bar.set_postfix_str("fig 4")       # a line
    lines = out.getvalue().splitlines()
    assert lines == ["figures 2/4 (6 s)", "figures 2/4: fig 4 (12 s)", "figures: done in 12.0 s"]


def test_a_short_job_prints_nothing():
    out = io.StringIO()
    with PlainProgress(3, "figures", stream=out) as bar:
        bar.update(3)
    assert out.getvalue() == ""


def test_cycles_piped_reports_the_continuation_inside_a_branch(monkeypatch, capsys):
    monkeypatch.setattr(progress_module, "PLAIN_EVERY_S", 0.0)    # every update a line
    assert main(["cycles", "--pressure", "1.5", "--vmin", "20", "--vmax", "40", "--json"]) == 0
    captured = capsys.readouterr()
    json.loads(captured.out)                                      # stdout is the JSON alone
    lines = [x for x in captured.err.splitlines() if x.startswith("cycle branches")]
    inside = [x for x in lines if " cycles, at " in x and "mesh intervals" in x]
    assert len(inside) > 5, captured.err[-2000:]
    assert lines[-1].startswith("cycle branches: done in ")


def piped_lines(monkeypatch, capsys, argv, prefix):
    """Run a command with every progress update a line; (its JSON, the progress lines starting with prefix)."""
    monkeypatch.setattr(progress_module, "PLAIN_EVERY_S", 0.0)
    assert main(argv) == 0
    captured = capsys.readouterr()
    return json.loads(captured.out), [x for x in captured.err.splitlines() if x.startswith(prefix)]


def test_mbs_simulate_reports_simulated_time(monkeypatch, capsys):
    out, lines = piped_lines(monkeypatch, capsys, ["simulate", "--model", "mbs", "--fidelity", "full", "--pressure",
                                                   "1.5", "--speed", "60", "--duration", "0.2", "--json"], "simulating")
    assert out["model"] == "mbs"
    said = [float(x.split(": ")[1].split(" of ")[0]) for x in lines if " s simulated" in x]
    assert len(said) >= 50 and said == sorted(said) and 0.19 <= said[-1] <= 0.2, lines[-3:]
    assert lines[-1].startswith("simulating: done in ")


def test_margins_reports_each_pressure(monkeypatch, capsys):
    out, lines = piped_lines(monkeypatch, capsys, ["margins", "--range", "1.5", "2.5", "--pressures", "4",
                                                   "--speeds", "11", "--json"], "margins")
    assert [x.split(" (")[0] for x in lines[:-1]] == [f"margins: pressures of the grid {k}/4" for k in range(1, 5)]
    assert lines[-1].startswith("margins: pressures of the grid: done in ")


def test_kick_search_reports_each_run(monkeypatch, capsys):
    """``cycles --kick``: one line per settling run of the kick search (the runs are stood in for by a rule that
    leaves the lower state for kicks above 0.05 rad)."""
    import math

    import numpy as np

    from comparisons.studies import kick as kick_module
    from comparisons.studies.limit_cycle import SteadyAmplitude
    states = (kick_module.Attractor("straight running", 0.0, 0.0), kick_module.Attractor("yaw cycle", 0.1, 0.01))

    def settle(x0):
        big = x0[kick_module.TH1] > 0.05
        return SteadyAmplitude(30.0, 0.1 if big else 0.0, 0.01 if big else 0.0, True, np.zeros(8))

    monkeypatch.setattr(kick_module, "bistable_speeds", lambda family, diagram, min_width: [30.0])
    monkeypatch.setattr(kick_module, "coexisting_states", lambda family, diagram, speed: (states, 0.02))
    monkeypatch.setattr(kick_module, "settle_function", lambda family, speed: settle)
    out, lines = piped_lines(monkeypatch, capsys, ["cycles", "--pressure", "1.5", "--vmin", "20", "--vmax", "40",
                                                   "--kick", "--json"], "kick thresholds")
    (kick,) = out["kicks"]
    assert kick["kick_theta1_deg"] == pytest.approx(math.degrees(0.05), rel=0.02)
    runs = [x for x in lines if ", run " in x]
    assert len(runs) >= 5 and all("108.00 km/h" in x for x in runs)
    assert [int(x.split(", run ")[1].split(":")[0]) for x in runs] == list(range(1, len(runs) + 1))
    assert lines[-1].startswith("kick thresholds: runs: done in ")
