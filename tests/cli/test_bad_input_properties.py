"""Property-based tests (Hypothesis) of the command line and the model inputs: whatever is typed, the answer is
either exit 2 with one line on stderr or a finite result; nonsense is never accepted."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from axles.axle import entries, paper_axle
from axles.limits import UsageError
from axles.units import from_kmh
from comparisons.cli.main import main
from comparisons.cli.options import parse_overrides
from reduced_model.model import ShimmyModel
from axles.parameters import ParameterError
from axles.pressures import TyrePressures

FAST = settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])

# Numbers as people type them and as they come out of scripts: every float, with huge, tiny, signed, special.
special = st.sampled_from(["nan", "inf", "-inf", "1e308", "1e-300", "-1e-300", "0", "-0", "", " ", "abc", "1e",
                           "0x10", "1_000", "٣", "1e309", "--1", "1,5"])
float_text = st.one_of(st.floats(allow_nan=True, allow_infinity=True).map(repr), special,
                       st.floats(min_value=-1e6, max_value=1e6).map(lambda v: f"{v:g}"))
any_text = st.one_of(float_text, st.text(max_size=12))


def one_line_refusal_or_finite(code: int, out: str, err: str) -> None:
    assert "Traceback" not in err
    if code == 2:
        lines = err.strip().splitlines()
        assert len(lines) == 1 and lines[0].startswith("shimmy: error:"), err
        return
    assert code in (0, 3), (code, err)
    data = json.loads(out, parse_constant=lambda c: pytest.fail(f"{c} in the JSON"))
    assert data is not None


@FAST
@given(name=st.sampled_from(sorted(entries())), text=float_text, speed=st.floats(1.0, 400.0))
def test_any_set_value_is_refused_with_its_range_or_gives_a_finite_model(name, text, speed):
    """--set NAME=VALUE: outside the physical range (or not a number) one UsageError naming the range; inside, the
    linearised reduced model at any speed in the window is finite."""
    e = entries()[name]
    try:
        overrides = parse_overrides([f"{name}={text}"])
        axle = paper_axle().with_overrides(overrides)
    except (UsageError, ParameterError) as exc:
        message = str(exc)
        assert "\n" not in message
        value = _float_or_none(text)
        if value is not None and math.isfinite(value):
            lo, hi = e.range
            assert not lo <= value <= hi or "range" in message, message
            assert f"[{lo:g}, {hi:g}]" in message or "range" in message
        return
    value = float(text)
    lo, hi = e.range
    assert lo <= value <= hi, f"{name}={text} accepted outside [{lo:g}, {hi:g}]"
    model = ShimmyModel(params=axle.params)
    try:
        A = model.linear_matrix(from_kmh(speed), TyrePressures.uniform(2.5e5))
    except ParameterError:
        return   # the tyre model refuses this combination with one line (e.g. a negative cornering stiffness)
    assert np.all(np.isfinite(A)) and np.all(np.isfinite(np.linalg.eigvals(A)))


def _float_or_none(text):
    try:
        return float(text)
    except ValueError:
        return None


@pytest.fixture
def short_runs(monkeypatch):
    """The parsing and checks under test are the real ones; the simulation is cut to 50 ms to keep CI fast."""
    import comparisons.cli.commands.simulate as simulate_command
    real = simulate_command.simulate_model

    def short(args, ramp, duration, initial):
        return real(args, ramp, min(duration, 0.05), initial)
    monkeypatch.setattr(simulate_command, "simulate_model", short)


@FAST
@given(speed=float_text, duration=float_text, initial=st.tuples(st.sampled_from(["theta1", "psi", "theta2_dot",
                                                                                  "alpha1", "bogus"]), any_text),
       pressure=float_text)
def test_simulate_options_refused_in_one_line_or_finite(short_runs, capsys, speed, duration, initial, pressure):
    argv = ["simulate", "--pressure", pressure, "--speed", speed, "--duration", duration,
            "--initial", f"{initial[0]}={initial[1]}", "--json"]
    code = _main(argv)
    captured = capsys.readouterr()
    one_line_refusal_or_finite(code, captured.out, captured.err)
    if code in (0, 3):
        assert 0.5 <= float(speed) <= 1000 and 0.01 <= float(duration) <= 1000 and 0.05 <= float(pressure) <= 20


@FAST
@given(ramp=st.one_of(st.tuples(float_text, float_text, float_text).map(":".join), st.text(max_size=15)))
def test_ramp_refused_in_one_line_or_finite(short_runs, capsys, ramp):
    code = _main(["simulate", "--pressure", "2.5", "--ramp", ramp, "--json"])
    captured = capsys.readouterr()
    one_line_refusal_or_finite(code, captured.out, captured.err)


@settings(max_examples=25, deadline=None)
@given(vmax=float_text, lo=float_text, hi=float_text)
def test_speed_and_parameter_windows_refused_in_one_line(vmax, lo, hi):
    """Only the checks run: a valid window is replaced by the empty computation below (no continuation in CI)."""
    import argparse

    from axles.limits import PRESSURE_RANGE_BAR, SPEED_RANGE_KMH
    from comparisons.cli.options import check_window, ranged
    v_lo, v_hi = SPEED_RANGE_KMH
    try:
        v = ranged("--vmax", v_lo, v_hi, "km/h", lo_open=True)(vmax)
    except argparse.ArgumentTypeError as exc:
        assert "\n" not in str(exc) and "must" in str(exc)
        v = None
    if v is not None:
        assert v_lo < v <= v_hi, f"a window that does not reach above {v_lo} km/h was accepted"
    try:
        a, b = float(lo), float(hi)
    except ValueError:
        return
    try:
        check_window(a, b, "pressure", "bar")
    except UsageError as exc:
        assert "\n" not in str(exc)
        return
    p_lo, p_hi = PRESSURE_RANGE_BAR
    assert p_lo <= a < b <= p_hi


def _main(argv):
    try:
        return main(argv)
    except SystemExit as exc:   # argparse's own errors
        return exc.code
