"""Progress of the commands that can take long: plain lines on stderr when piped (at most one per
PLAIN_EVERY_S seconds, so that a short run prints none), nothing on stdout under --json; the cycle
continuation reports inside a branch (cycles so far, speed, collocation mesh), not only per branch."""

import io
import json

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
