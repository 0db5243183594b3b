"""Output paths and defaults that escaped before (issue 33): a 4200-byte ``verify --out``, two options naming the
same file (sweep's ``--out`` among them), an empty ``sweep --out``, and the default output of ``sweep --compute
margins``."""

from __future__ import annotations

import os

import pytest

from axles.axle import AxleData
from comparisons.cli.main import main
from comparisons.sweeps.analysis import DEFAULT_OUTPUTS, OutputChoice
from comparisons.sweeps.sample import COMPUTE, SweepTask

SWEEP = ["sweep", "--vary", "k1=50000:60000:2", "--pressure", "2"]


@pytest.fixture
def run(capsys, monkeypatch, tmp_path):
    monkeypatch.chdir(tmp_path)

    def call(*args):
        code = main(list(args))
        out, err = capsys.readouterr()
        return code, out, err
    return call


@pytest.mark.parametrize("path", ["a/" * 2100, "a/" * 1000 + "b" * 300, "x" * 4200],
                         ids=["4200 bytes of short names", "a name over 255 bytes", "one 4200-byte name"])
@pytest.mark.parametrize("command", ["verify", "figures"])
def test_long_out_folder_is_one_line_exit_2(run, tmp_path, command, path):
    code, out, err = run(command, "--out", path)
    assert code == 2 and err.count("\n") == 1 and err.startswith("shimmy: error: --out "), err
    assert "Traceback" not in err and len(err) < 400        # the path is cut, not echoed whole
    assert list(tmp_path.iterdir()) == []                    # nothing was created


def test_deep_out_folder_within_the_limits_is_made_without_recursion(tmp_path):
    from comparisons.files import prepare_folder
    deep = tmp_path / ("a/" * 1200)                          # 1200 levels: os.makedirs would recurse past 1000
    try:
        assert prepare_folder(str(deep)) == str(deep).rstrip("/")
        assert deep.is_dir()
    finally:   # removed here, bottom up: pytest's clean-up of old temporary folders recurses once per level
        folder = str(deep).rstrip("/")
        while folder != str(tmp_path):
            if os.path.isdir(folder):
                os.rmdir(folder)
            folder = os.path.dirname(folder)


@pytest.mark.parametrize("args, fragment", [
    (["--out", "X.parquet", "--plot", "X.parquet"], "--out and --plot name the same file X.parquet"),
    (["--out", "./X.parquet", "--plot", "X.parquet"], "name the same file"),
    (["--out", ""], "--out: an empty file name"),
    (["--out", "   "], "--out: an empty file name"),
])
def test_sweep_out_takes_part_in_the_output_checks(run, tmp_path, args, fragment):
    code, out, err = run(*SWEEP, *args)
    assert code == 2 and err.count("\n") == 1 and fragment in err, err
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("compute", COMPUTE)
def test_default_output_follows_compute(compute):
    """Each --compute alone has a default output that is a column of its own sweep (margins had none)."""
    task = SweepTask(AxleData(), (), 2.0, 2.0, ("k1",), compute=(compute,))
    choice = OutputChoice.parse(None, task)
    assert choice.label == DEFAULT_OUTPUTS[compute]
    assert choice.column in task.schema().names


def test_default_output_keeps_hopf_first():
    task = SweepTask(AxleData(), (), 2.0, 2.0, ("k1",), compute=("margins", "hopf"))
    assert OutputChoice.parse(None, task).label == "onset_kmh"
