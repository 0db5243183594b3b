"""``--brake-slip`` / ``--brake-force`` at the command line (issue 32): one typed Braking made by the parser module,
range-checked once, exit 2 with one line on bad values, JSON unchanged without braking."""

from __future__ import annotations

import json

import pytest

from axles.braking import FREE_ROLLING, Braking
from comparisons.cli.main import main, parse_command


def _json(capsys, *argv):
    assert main(list(argv)) == 0
    return json.loads(capsys.readouterr().out)


def test_the_parser_makes_the_braking_once():
    assert parse_command(["hopf", "--pressure", "2", "--brake-slip", "0.05"]).braking == Braking(0.05, 0.05)
    assert parse_command(["hopf", "--pressure", "2", "--brake-slip", "0.05,0"]).braking == Braking(0.05, 0.0)
    assert parse_command(["cycles", "--pressure", "2", "--brake-force", "1000,2000"]).braking == Braking(
        1000.0, 2000.0, by_force=True)
    assert parse_command(["hopf", "--pressure", "2", "--brake-slip=-0.05,0"]).braking == Braking(-0.05, 0.0)
    assert parse_command(["hopf", "--pressure", "2", "--brake-force", "-1500"]).braking == Braking(
        -1500.0, -1500.0, by_force=True)
    assert parse_command(["hopf", "--pressure", "2"]).braking is FREE_ROLLING
    assert parse_command(["figures"]).braking is None     # a command without braking options


@pytest.mark.parametrize("argv,message", [
    (["--brake-slip", "1.5"], "--brake-slip: right brake slip must be within [-1, 1] (-), got 1.5"),
    (["--brake-slip", "0.1,-1.5"], "--brake-slip: left brake slip must be within [-1, 1] (-), got -1.5"),
    (["--brake-slip", "nan"], "must be within [-1, 1]"),
    (["--brake-slip", "-0.05,0"], "--brake-slip: expected one argument"),     # argparse: '=' needed (the help)
    (["--brake-slip", "a"], "--brake-slip must be a number (or right,left), got 'a'"),
    (["--brake-slip", "0.1,0.1,0.1"], "--brake-slip takes one value or right,left"),
    (["--brake-force=-2e5"], "--brake-force: right brake force must be within [-100000, 100000] N, got -200000"),
    (["--brake-force", "9000"], "brake force = 9000 N is beyond the tyre's grip: at most 6253.2 N"),
    (["--brake-force=-9000,0"], "drive force = 9000 N is beyond the tyre's grip: at most"),
    (["--brake-slip", "0.1", "--brake-force", "10"], "not allowed with argument"),
])
def test_bad_braking_is_one_line_and_exit_2(capsys, argv, message):
    try:
        code = main(["hopf", "--pressure", "2.5", *argv])
    except SystemExit as exc:          # argparse's own errors leave through the parser's one-line error
        code = exc.code
    assert code == 2
    err = capsys.readouterr().err.strip()
    assert message in err and len(err.splitlines()) == 1 and "Traceback" not in err


def test_json_has_braking_only_under_braking(capsys):
    free = _json(capsys, "hopf", "--pressure", "2.5", "--json")
    zero = _json(capsys, "hopf", "--pressure", "2.5", "--brake-slip", "0", "--json")
    assert "braking" not in free and zero == free         # zero brake slip is free rolling
    braked = _json(capsys, "hopf", "--pressure", "2.5", "--brake-slip", "0.05,0", "--json")
    assert braked["braking"] == {"quantity": "brake_slip", "unit": "-", "right": 0.05, "left": 0.0}
    # braking the right wheel widens the 2.5 bar yaw window at both ends (docs/results.md, "Braking")
    assert [round(h["speed_kmh"], 2) for h in braked["hopf"]] == [33.06, 90.37]
    # and holds both wheels steered toward the braked (right) wheel: theta < 0 about +z
    steady = braked["steady_state"]
    assert steady["speed_kmh"] == 60.0 and steady["theta1_deg"] < steady["theta2_deg"] < -0.5


def test_hopf_curve_in_brake_slip_closes_the_yaw_window(capsys):
    """curves --param brake_slip at 2.5 bar: the yaw mode's Hopf curve runs from both free-rolling Hopf points
    (46.14, 70.50 km/h at slip 0) to a fold where the window closes (docs/results.md, "Braking")."""
    out = _json(capsys, "curves", "--param", "brake_slip", "--range", "0", "0.1", "--pressure", "2.5", "--vmax", "120",
                "--json")
    assert out["param"] == "brake_slip" and out["unit"] == "-" and out["complete"]
    (fold,) = [s for s in out["special_points"] if s["kind"] == "hopf_fold"]
    assert fold["speed_kmh"] == pytest.approx(59.049, abs=1e-3) and fold["value"] == pytest.approx(0.0919, abs=1e-4)
    ends = sorted(p[0] for c in out["curves"] for p in (c["points"][0], c["points"][-1]))
    assert ends == pytest.approx([46.1426, 70.5006], abs=1e-3)
