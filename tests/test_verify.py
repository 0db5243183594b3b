"""``shimmy verify``: report contents, exit status and safe writing."""

import json
import os
import subprocess
import sys

import pytest

from comparisons.cli import main
from comparisons.report import CheckStatus, Report, Row, Section, render_markdown, write_atomically


def test_verify_quick_writes_report_with_expected_rows(tmp_path, capsys):
    out = tmp_path / "rep"
    assert main(["verify", "--quick", "--out", str(out), "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["failed"] is False
    hopf = next(s for s in summary["sections"] if s["key"] == "hopf")
    by_key = {(r["model"], r["pressure_bar"], r["point"]): r for r in hopf["rows"]}
    assert by_key[("section 3", 2.5, "HB1")]["status"] == "pass"
    assert by_key[("section 3", 1.5, "HB1")]["status"] == "known difference"
    assert by_key[("section 3", 2.7, "none")]["status"] == "pass"
    text = (out / "report.md").read_text()
    assert text.startswith("# shimmy verification report") and "## Summary" in text
    assert not [f for f in os.listdir(out) if f.startswith(".tmp-")]


def test_failed_row_makes_report_fail():
    section = Section("x", "X", ("a",), (Row({"a": 1.0}, CheckStatus.PASS), Row({"a": 2.0}, CheckStatus.FAIL)))
    report = Report((section,), quick=True)
    assert report.failed and "FAILED" in render_markdown(report)


def test_file_in_the_way_of_out(tmp_path):
    blocker = tmp_path / "blocker"
    blocker.write_text("x")
    proc = subprocess.run([sys.executable, "-m", "comparisons.cli", "verify", "--quick", "--out", str(blocker)],
                          capture_output=True, text=True)
    assert proc.returncode == 2 and "file is in the way" in proc.stderr and len(proc.stderr.splitlines()) == 1


def test_out_that_cannot_be_created(tmp_path):
    blocker = tmp_path / "blocker"
    blocker.write_text("x")
    proc = subprocess.run([sys.executable, "-m", "comparisons.cli", "verify", "--quick", "--out",
                           str(blocker / "sub")], capture_output=True, text=True)
    assert proc.returncode == 2 and "cannot create the folder" in proc.stderr
    assert len(proc.stderr.splitlines()) == 1


@pytest.mark.skipif(os.geteuid() == 0, reason="root ignores directory permissions")
def test_unwritable_out(tmp_path):
    locked = tmp_path / "locked"
    locked.mkdir(mode=0o500)
    proc = subprocess.run([sys.executable, "-m", "comparisons.cli", "verify", "--quick", "--out",
                           str(locked / "sub")], capture_output=True, text=True)
    assert proc.returncode == 2 and len(proc.stderr.splitlines()) == 1


def test_interrupted_write_leaves_no_file(tmp_path):
    target = tmp_path / "report.md"

    class Exploding:
        pass

    with pytest.raises(TypeError):
        write_atomically(str(target), Exploding())  # fails inside the write
    assert not target.exists() and os.listdir(tmp_path) == []
    with pytest.raises(IsADirectoryError):
        write_atomically(str(tmp_path), "x")
