"""A clone needs nothing outside the repository: no tracked file names the workplace's folder of shared notes
(the README once pointed there for the paper and its reading notes, which a clone does not have; they are now the
citation and docs/paper-notes.md)."""

import subprocess

import pytest

from tests.docs.conftest import ROOT

OUTSIDE = "shared" + "/"      # spelt in two parts so that this file does not name it itself


def _tracked_files() -> list[str]:
    try:
        out = subprocess.run(["git", "ls-files", "-z"], cwd=ROOT, capture_output=True, check=True, timeout=30)
    except (OSError, subprocess.SubprocessError):
        pytest.skip("not a git checkout: the tracked files are unknown")
    return [name for name in out.stdout.decode().split("\0") if name]


def test_no_tracked_file_names_the_shared_folder():
    named = []
    for name in _tracked_files():
        path = ROOT / name
        if not path.is_file():
            continue   # deleted in the work tree but still in the index
        text = path.read_bytes().decode("utf-8", errors="replace")
        named += [f"{name}:{n}" for n, line in enumerate(text.splitlines(), 1) if OUTSIDE in line]
    assert not named, "files that point outside the repository:\n" + "\n".join(named)


def test_paper_notes_and_citation_exist():
    notes = (ROOT / "docs" / "paper-notes.md").read_text()
    for reading in ("p_dy2", "p_py3", "p_py1", "p_py2", "p_cy1_rl", "k5_0"):
        assert reading in notes
    citation = (ROOT / "CITATION.cff").read_text()
    assert "cff-version: 1.2.0" in citation and "Mavros" in citation and "ANZIAM" in citation
