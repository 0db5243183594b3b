"""Property-based tests (Hypothesis) of every input path of issue 33: generated axle files (broken TOML, extreme
numbers, deep nesting, wrong types) and generated scheduler addresses each end in exactly one documented outcome,
within a time bound:

* an axle file: an axle, or one :class:`AxleFileError` line that starts with the file's name; at the command line
  exit 0, or exit 2 with one ``shimmy: error:`` line;
* a ``--scheduler`` address: a normalised ``tcp://HOST:PORT`` that reads back as itself, or one
  :class:`UsageError` line naming ``--scheduler``.

The CI profile runs a few seconds; the slow suite (``-m slow``) runs the same properties on many more examples.
"""

from __future__ import annotations

import time

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from axles.axle import entries, paper_axle
from axles.axle_file import AxleFileError, format_axle, parse_axle
from axles.limits import UsageError
from comparisons.cli.main import main
from comparisons.sweeps.cluster import scheduler_address

TIME_BOUND_S = 2.0
CI = settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture,
                                                                     HealthCheck.too_slow])
LONG = settings(max_examples=1000, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture,
                                                                         HealthCheck.too_slow])

PAPER = format_axle(paper_axle())
LINES = PAPER.splitlines()
VALUE_LINES = [i for i, line in enumerate(LINES) if " = " in line and not line.startswith("#")]

# --- generated axle files -------------------------------------------------------------------------------------

extreme_numbers = st.one_of(
    st.integers().map(str),
    st.integers(min_value=10 ** 15, max_value=10 ** 400).map(lambda n: str(n * (-1) ** (n % 2))),
    st.integers(min_value=1, max_value=6000).map(lambda n: "9" * n),
    st.floats(allow_nan=True, allow_infinity=True).map(lambda x: repr(x).replace("inf", "inf").replace("nan", "nan")),
    st.sampled_from(["inf", "-inf", "nan", "+nan", "1e308", "1e309", "-1e-320", "0x7fffffffffffffff", "0b1", "0o7",
                     "1_000_000", "1e1000", "0.0", "-0.0"]),
)
wrong_types = st.sampled_from(['"6.0"', "true", "false", "[]", "[1.0]", "[1.0, 2.0, 3.0]", "{}", "{a = 1}",
                               "1979-05-27", "07:32:00", "1979-05-27T07:32:00Z", "'''x'''", '"""\n"""', "[[1.0]]"])
nesting = st.tuples(st.integers(1, 4000), st.sampled_from(["[]", "{}", "[{", "{["])).map(
    lambda t: _nest(*t))
junk = st.text(max_size=40)


def _nest(depth: int, kind: str) -> str:
    if kind == "[]":
        return "[" * depth + "1" + "]" * depth
    if kind == "{}":
        return "{a = " * depth + "1" + "}" * depth
    return ("[{a = " * depth)[: depth * 3] + "1"      # unbalanced: a syntax error after the nesting


@st.composite
def axle_files(draw) -> str:
    """The paper's axle file with a few of its values, lines or bytes replaced."""
    lines = list(LINES)
    for _ in range(draw(st.integers(1, 3))):
        how = draw(st.sampled_from(["value", "line", "truncate", "insert", "section"]))
        present = [i for i in VALUE_LINES if i < len(lines) and " = " in lines[i]]
        if how == "value" and present:
            i = draw(st.sampled_from(present))
            key = lines[i].split(" = ")[0].strip()
            value = draw(st.one_of(extreme_numbers, wrong_types, nesting, junk))
            lines[i] = f"{key} = {value}"
        elif how == "line" and lines:
            lines[draw(st.integers(0, len(lines) - 1))] = draw(junk)
        elif how == "truncate":
            lines = lines[:draw(st.integers(0, len(lines)))]
        elif how == "insert":
            lines.insert(draw(st.integers(0, len(lines))), draw(st.one_of(junk, nesting.map(lambda v: f"x = {v}"))))
        else:
            lines.insert(draw(st.integers(0, len(lines))), draw(st.sampled_from(
                ["[table1]", "[multibody]", "[plausible]", "[operating]", "[nope]", "[[table1]]", "base = 'YANG2024'",
                 f"{draw(st.sampled_from(sorted(entries())))} = 1.0"])))
    return "\n".join(lines) + "\n"


def check_axle_file(text: str, tmp_path, capsys) -> None:
    """Exactly one outcome: an axle, or one AxleFileError line naming the file; the command agrees."""
    path = tmp_path / "gen.toml"
    path.write_bytes(text.encode("utf-8", "surrogatepass"))
    start = time.monotonic()
    try:
        axle = parse_axle(text, source=str(path))
        outcome = "axle"
    except AxleFileError as exc:
        message = str(exc)
        assert "\n" not in message and message.startswith(f"{path}"), message
        outcome = "refused"
    assert time.monotonic() - start < TIME_BOUND_S
    if outcome == "axle":
        axle.check_consistent()                      # what was accepted is consistent
        for name, e in entries().items():
            lo, hi = e.range_si
            assert lo <= axle.value(name) <= hi, name
    code = main(["params", "--axle", str(path)])
    out, err = capsys.readouterr()
    assert "Traceback" not in err
    if outcome == "axle":
        assert code == 0, err
    else:
        assert code == 2 and err.count("\n") == 1 and err.startswith("shimmy: error: "), err
    assert time.monotonic() - start < 2 * TIME_BOUND_S


@CI
@given(text=axle_files())
def test_generated_axle_files_end_in_one_documented_outcome(text, tmp_path, capsys):
    check_axle_file(text, tmp_path, capsys)


@CI
@given(text=st.text(max_size=300))
def test_any_text_as_an_axle_file(text, tmp_path, capsys):
    check_axle_file(text, tmp_path, capsys)


@pytest.mark.slow
@LONG
@given(text=st.one_of(axle_files(), st.text(max_size=2000)))
def test_generated_axle_files_long(text, tmp_path, capsys):
    check_axle_file(text, tmp_path, capsys)


# --- generated scheduler addresses ----------------------------------------------------------------------------

schemes = st.sampled_from(["tcp://", "TCP://", "tls://", "udp://", "inproc://", "ucx://", "ws://", "", "tcp:/", "://"])
hosts = st.one_of(st.sampled_from(["127.0.0.1", "localhost", "[::1]", "::1", "scheduler.example.org", "", " ",
                                   "-x-", "a..b", "256.1.1.1", "x" * 64, "h_st", "[::1", "ü.example"]),
                  st.text(max_size=20))
ports = st.one_of(st.integers(-10, 70000).map(str), st.sampled_from(["", "abc", "8786/x", "٣", " 8786", "1e3",
                                                                     "08786", "8786:1"]),
                  st.text(max_size=6))


@st.composite
def addresses(draw) -> str:
    if draw(st.booleans()):
        return draw(st.text(max_size=40))
    sep = draw(st.sampled_from([":", ":", "", "::", " :"]))
    return draw(schemes) + draw(hosts) + sep + draw(ports)


def check_address(address: str) -> None:
    start = time.monotonic()
    try:
        normalised, host, port = scheduler_address(address)
    except UsageError as exc:
        message = str(exc)
        assert message.startswith("--scheduler ") and "\n" not in message.replace("\\n", ""), message
        assert message.isprintable() or "\\" in repr(message)
        return
    finally:
        assert time.monotonic() - start < TIME_BOUND_S
    assert normalised.startswith("tcp://") and 1 <= port <= 65535
    assert scheduler_address(normalised) == (normalised, host, port)


@settings(CI, max_examples=300)
@given(address=addresses())
def test_generated_addresses_end_in_one_documented_outcome(address):
    check_address(address)


@pytest.mark.slow
@settings(LONG, max_examples=5000)
@given(address=addresses())
def test_generated_addresses_long(address):
    check_address(address)
