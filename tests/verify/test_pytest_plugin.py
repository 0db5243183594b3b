"""The pytest plugin (:mod:`comparisons.verify.pytest_plugin`) as an engineer runs it: ``python -m pytest --axle
FILE.toml --quick`` in a folder of their own, outside the checkout, on an axle file written by ``shimmy params``."""

import subprocess
import sys
import xml.etree.ElementTree as ET

import pytest

CHECKS = {"test_axle_file_round_trip", "test_axle_entries_in_range", "test_mbs_straight_running",
          "test_eigenvalues_equal", "test_hopf_points_equal", "test_criticality", "test_transient_equal",
          "test_limit_cycle_amplitude"}


def pytest_in(folder, *args, timeout=300):
    """A fresh ``python -m pytest`` in ``folder`` (no cache folder left behind)."""
    return subprocess.run([sys.executable, "-m", "pytest", "-p", "no:cacheprovider", *args], cwd=folder,
                          capture_output=True, text=True, timeout=timeout)


@pytest.fixture(scope="module")
def paper_file(tmp_path_factory):
    path = tmp_path_factory.mktemp("axle") / "paper.toml"
    proc = subprocess.run([sys.executable, "-m", "comparisons.cli", "params", "--write", str(path)],
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    return path


def junit_cases(path):
    """(testsuite element, {name: outcome}) of a JUnit XML file; outcome: passed, skipped, failure or error."""
    suite = ET.parse(path).getroot().find("testsuite")
    cases = {}
    for case in suite.findall("testcase"):
        children = [c.tag for c in case]
        cases[case.get("name")] = next((t for t in ("failure", "error", "skipped") if t in children), "passed")
        assert case.get("classname") == "comparisons.verify.equivalence_checks", case.get("classname")
    return suite, cases


def test_quick_checks_run_from_a_folder_outside_the_checkout(paper_file, tmp_path):
    proc = pytest_in(tmp_path, "--axle", str(paper_file), "--quick", "--junitxml", "checks.xml", "-rs")
    assert proc.returncode == 0, proc.stdout[-4000:] + proc.stderr[-2000:]
    suite, cases = junit_cases(tmp_path / "checks.xml")
    passed = [name for name, outcome in cases.items() if outcome == "passed"]
    assert int(suite.get("tests")) == len(cases) and int(suite.get("failures")) == int(suite.get("errors")) == 0
    assert len(passed) >= 8 and f"{len(passed)} passed" in proc.stdout
    assert CHECKS <= {name.split("[")[0] for name in passed}
    # quick: two pressures of the axle's window (its low end and an asymmetric pair)
    assert {name for name in cases if name.startswith("test_hopf_points_equal")} == {
        "test_hopf_points_equal[0.5bar]", "test_hopf_points_equal[R2-L1.6bar]"}
    # the paper's trail t0 = 0.07 m has no bistable window: the jump checks say so instead of passing silently
    assert {cases[n] for n in cases if "bistable" in n} == {"skipped"}
    assert "no bistable window of this axle in 0.5-3.5 bar" in proc.stdout
    assert "shimmy equivalence checks (quick): axle paper" in proc.stdout   # named after its file
    assert sorted(p.name for p in tmp_path.iterdir()) == ["checks.xml"]


def test_bistable_window_of_the_paper_axle_at_t0_025(paper_file, tmp_path):
    """figures 9a-11's t0 = 0.25 m by --axle-set: the plan finds the window; just past each of its ends, from the
    cycle that ends there, and from two starts inside it, both models end in the same mode (ramps are not
    checked: their jump speed is not well posed)."""
    proc = pytest_in(tmp_path, "--axle", str(paper_file), "--axle-set", "t0=0.25", "--quick", "-k", "bistable",
                     "--junitxml", "jumps.xml", "-rs")
    assert proc.returncode == 0, proc.stdout[-4000:] + proc.stderr[-2000:]
    _, cases = junit_cases(tmp_path / "jumps.xml")
    assert cases == {"test_bistable_window_ends": "passed", "test_bistable_two_starts": "passed"}
    assert "differs from the paper in t0 = 0.25 m" in proc.stdout


@pytest.mark.parametrize("content, message", [
    ('name = "bad"\nbase = "YANG2024"\n[table1]\nt0 = -1.0\n', "t0 = -1 m is outside its physical range"),
    (None, "cannot read the axle file"),
])
def test_bad_axle_file_is_one_usage_line(tmp_path, content, message):
    path = tmp_path / "axle.toml"
    if content is not None:
        path.write_text(content)
    proc = pytest_in(tmp_path, "--axle", str(path), "--quick", timeout=120)
    assert proc.returncode == 4, proc.stdout + proc.stderr          # pytest's usage-error exit code
    lines = [line for line in proc.stderr.splitlines() if line.strip()]
    assert len(lines) == 1 and lines[0].startswith("ERROR: --axle: ") and message in lines[0], proc.stderr
    assert "Traceback" not in proc.stdout + proc.stderr


def test_axle_set_without_axle_or_out_of_range_is_a_usage_error(paper_file, tmp_path):
    proc = pytest_in(tmp_path, "--axle-set", "t0=0.25", timeout=120)
    assert proc.returncode == 4 and proc.stderr.strip() == "ERROR: --axle-set NAME=VALUE needs --axle FILE.toml"
    proc = pytest_in(tmp_path, "--axle", str(paper_file), "--axle-set", "t0=9", timeout=120)
    assert proc.returncode == 4 and proc.stderr.strip() == \
        "ERROR: --axle-set: t0 = 9 m is outside its physical range [0.001, 0.5] m", proc.stderr


def test_the_plugin_adds_nothing_without_axle_and_adds_its_checks_to_given_paths(paper_file, tmp_path):
    (tmp_path / "test_mine.py").write_text("def test_mine():\n    pass\n")
    proc = pytest_in(tmp_path, "--co", "-q", timeout=120)
    assert proc.returncode == 0 and proc.stdout.splitlines()[0] == "test_mine.py::test_mine", proc.stdout
    assert "1 test collected" in proc.stdout
    proc = pytest_in(tmp_path, "--co", "-q", "--axle", str(paper_file), "--quick", "test_mine.py", timeout=120)
    ids = [line for line in proc.stdout.splitlines() if "::" in line]
    assert proc.returncode == 0 and ids[0].endswith("test_mine.py::test_mine"), proc.stdout
    assert {i.split("::")[1].split("[")[0] for i in ids[1:]} >= CHECKS
