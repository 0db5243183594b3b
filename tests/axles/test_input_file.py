"""The one reader of input files (axles/input_file.py) on the files that escaped before (issue 33): deep nesting,
huge integers, devices, FIFOs, oversized and non-UTF-8 files, and entries that contradict each other.  Each ends in
one line naming the file (and the line and entry where known): exit 2 at the command line, exit 4 with one
``ERROR:`` line in the pytest plugin, an :class:`AxleFileError` (a ValueError) in the API."""

from __future__ import annotations

import os
import subprocess
import sys
import time

import numpy as np
import pytest

from axles.axle_file import AxleFileError, read_axle
from axles.input_file import MAX_BYTES, InputFileError, finite_number, parse_toml
from axles.parameters import ParameterError
from comparisons.api import Axle
from comparisons.cli.main import main

HEAD = 'name = "x"\nbase = "YANG2024"\n[table1]\n'

# (case, file text or None for a special file, fragment of the message, line named or None)
BROKEN = [
    ("nested 3000 deep", HEAD + "I1 = " + "[" * 3000 + "]" * 3000 + "\n", "nested more than", 4),
    ("nested inline tables", HEAD + "I1 = " + "{a = " * 50 + "1" + "}" * 50 + "\n", "nested more than", 4),
    ("5000-digit integer", HEAD + "I1 = " + "9" * 5000 + "\n", "more than 100 digits in 'I1'", 4),
    ("400-digit integer", HEAD + "\n\nk1 = " + "1" * 400 + "\n", "more than 100 digits in 'k1'", 6),
    ("400-digit float", HEAD + "I1 = " + "9" * 400 + ".0\n", "more than 100 digits in 'I1'", 4),
    ("digits with underscores", HEAD + "I1 = " + "1_0" * 120 + "\n", "more than 100 digits", 4),
    ("I1 below the wheel's own inertia", HEAD + "I1 = 0.2\n", "smaller than the wheel's own inertia", 4),
    ("I2 above twice the diametral inertia", HEAD + "I2 = 30.0\n", "exceeds twice the diametral inertia", 4),
    ("not UTF-8", HEAD + "# caf\xe9\n", "not a text file", 4),
    ("inf", HEAD + "I1 = inf\n", "must be a finite number", 4),
    ("nan", HEAD + "\n[multibody]\nwheel_mass = nan\n", "must be a finite number", 6),
]


def _write(path, text):
    path.write_bytes(text.encode("latin-1") if "\xe9" in text else text.encode())
    return path


@pytest.mark.parametrize("case, text, fragment, line", BROKEN, ids=[b[0] for b in BROKEN])
def test_broken_file_is_one_line_naming_file_line_and_entry(tmp_path, capsys, case, text, fragment, line):
    path = _write(tmp_path / "bad.toml", text)
    with pytest.raises(AxleFileError) as err:
        Axle.from_file(path)
    message = str(err.value)
    assert isinstance(err.value, ValueError) and "\n" not in message
    assert message.startswith(f"{path}:{line}: ") and fragment in message, message
    assert err.value.file == str(path) and err.value.line == line
    code = main(["hopf", "--pressure", "1.5", "--axle", str(path)])
    out, stderr = capsys.readouterr()
    assert code == 2 and stderr.count("\n") == 1 and fragment in stderr and "Traceback" not in stderr


def test_devices_and_fifos_are_refused_at_once(tmp_path, capsys):
    fifo = tmp_path / "fifo.toml"
    os.mkfifo(fifo)           # no writer: opening it for reading would wait forever
    for path in (str(fifo), "/dev/zero", "/dev/null"):
        start = time.monotonic()
        with pytest.raises(AxleFileError, match="not a regular file"):
            read_axle(path)
        assert main(["hopf", "--pressure", "1.5", "--axle", path]) == 2
        assert time.monotonic() - start < 5.0
        assert "not a regular file" in capsys.readouterr().err


def test_oversized_file_is_refused_before_reading(tmp_path):
    path = tmp_path / "big.toml"
    path.write_bytes(HEAD.encode() + b"#" * (MAX_BYTES + 1))
    with pytest.raises(AxleFileError, match=f"more than the {MAX_BYTES} an axle file may have"):
        read_axle(str(path))


def test_inconsistent_entries_refused_by_verify_before_planning(tmp_path):
    """verify refuses the file (and the same contradiction made by --set) before any planning line."""
    path = _write(tmp_path / "light.toml", HEAD + "I1 = 0.2\n")
    for args in (["--axle", str(path)], ["--set", "I1=0.2"]):
        proc = subprocess.run([sys.executable, "-m", "comparisons.cli", "verify", "--quick", *args, "--out",
                               str(tmp_path / "report")], capture_output=True, text=True, timeout=120)
        assert proc.returncode == 2, proc.stderr
        assert proc.stderr.count("\n") == 1 and "smaller than the wheel's own inertia" in proc.stderr
        assert not (tmp_path / "report").exists()


def _plugin(folder, *args):
    return subprocess.run([sys.executable, "-m", "pytest", "-p", "no:cacheprovider", "-n", "0", *args],
                          cwd=folder, capture_output=True, text=True, timeout=120)


@pytest.mark.parametrize("case", ["nested 3000 deep", "400-digit integer", "I1 below the wheel's own inertia"])
def test_plugin_gives_one_error_line_and_exit_4(tmp_path, case):
    _, text, fragment, _ = next(b for b in BROKEN if b[0] == case)
    path = _write(tmp_path / "bad.toml", text)
    proc = _plugin(tmp_path, "--axle", str(path))
    output = proc.stdout + proc.stderr
    assert proc.returncode == 4, output
    errors = [line for line in output.splitlines() if line.startswith("ERROR:")]
    assert len(errors) == 1 and fragment in errors[0] and "INTERNALERROR" not in output


def test_plugin_refuses_a_fifo_and_an_inconsistent_axle_set(tmp_path):
    fifo = tmp_path / "fifo.toml"
    os.mkfifo(fifo)
    proc = _plugin(tmp_path, "--axle", str(fifo))
    assert proc.returncode == 4 and "ERROR: --axle:" in proc.stderr and "not a regular file" in proc.stderr
    paper = tmp_path / "paper.toml"
    assert main(["params", "--write", str(paper)]) == 0
    proc = _plugin(tmp_path, "--axle", str(paper), "--axle-set", "I1=0.2")
    assert proc.returncode == 4 and "smaller than the wheel's own inertia" in proc.stderr, proc.stdout


def test_axle_name_with_line_break_and_escape_is_printed_escaped(tmp_path, capsys):
    path = _write(tmp_path / "odd.toml", 'name = "a\\nb\\u001b[31m"\nbase = "YANG2024"\n')
    assert main(["params", "--axle", str(path)]) == 0
    out = capsys.readouterr().out
    assert "\x1b" not in out and "a\\nb\\x1b[31m" in out
    assert "\n" not in Axle.from_file(path).data.label()


def test_scan_keeps_strings_and_comments_out_of_the_count():
    """Brackets and digits inside strings and comments are not nesting or numbers; a key's line is recorded."""
    text = ('name = "[[[[[[[[[[[[[[[[[[[[ ' + "1" * 200 + '"\n# ' + "[" * 40 + "\n"
            "x = '''\n" + "{" * 40 + "\n'''\n[t]\n  y = [[1, 2], [3]]\n")
    doc = parse_toml(text, "f.toml")
    assert doc.line("", "name") == 1 and doc.line("t", "y") == 7 and doc.data["t"]["y"] == [[1, 2], [3]]
    with pytest.raises(InputFileError, match=r"^f.toml:2: TOML syntax error"):
        parse_toml('a = 1\nb = ]\n', "f.toml")


def test_finite_number_accepts_numpy_scalars_and_refuses_huge_integers_by_name():
    assert finite_number("x", np.float32(1.5)) == 1.5 and finite_number("x", np.int64(3)) == 3.0
    for bad, fragment in ((10 ** 400, "too large"), (True, "must be a number"), ("1", "must be a number"),
                          (float("nan"), "finite"), (np.float64("inf"), "finite")):
        with pytest.raises(ParameterError, match=fragment) as err:
            finite_number("speed", bad, "km/h")
        assert str(err.value).startswith("speed ")
