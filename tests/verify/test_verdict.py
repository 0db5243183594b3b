"""The plan from both models and the verdict (issue 21), on the two example axles of docs/examples/.

CI tests call the plan, verdict and section functions directly (about 20 s together); a whole ``verify --quick`` on
each axle is a ``slow`` test.
"""

import dataclasses
import json
import os
import subprocess
import sys

import pytest

from axles.axle_file import read_axle
from comparisons.verify.context import Context
from comparisons.verify.plan import CaseKind, axle_plan
from comparisons.verify.report import CheckStatus, Report, Row, Section, render_html, render_markdown
from comparisons.verify.scan import BoundaryKind, BoundaryMethod, Model, family_of, growth_root
from comparisons.verify.verdict import DisagreementKind, verdict_of

EXAMPLES = os.path.join(os.path.dirname(__file__), "..", "..", "docs", "examples")
SHIMMIES_IN_FULL = os.path.join(EXAMPLES, "full-geometry-shimmies.toml")
STABLE = os.path.join(EXAMPLES, "stable-c4-120.toml")


@pytest.fixture(scope="module")
def plan_a():
    return axle_plan(read_axle(SHIMMIES_IN_FULL), quick=True)


@pytest.fixture(scope="module")
def plan_b():
    return axle_plan(read_axle(STABLE), quick=True)


def test_plan_of_axle_a_has_a_case_where_only_the_full_geometry_shimmies(plan_a):
    reduced, full = plan_a.scan_of(Model.REDUCED), plan_a.scan_of(Model.FULL)
    # The reduced model's boundary is the paper's F1 (Table 1 is the paper's); the full geometry's lies higher.
    assert reduced.boundary.method is BoundaryMethod.FOLD and abs(reduced.boundary.pressure_bar - 2.60934) < 1e-4
    assert full.boundary.kind is BoundaryKind.SHIMMY_FREE_ABOVE and full.boundary.pressure_bar > 2.7
    only_full = [c for c in plan_a.cases if c.shimmies(Model.FULL) and not c.shimmies(Model.REDUCED)]
    assert only_full, [c.reason for c in plan_a.cases]
    for c in only_full:
        assert reduced.boundary.pressure_bar < c.pressure_right_bar < full.boundary.pressure_bar
        assert "only the full geometry shimmies here" in c.reason
        assert [w.mode for w in c.windows_of(Model.FULL)] == ["yaw"]
    assert any(c.chosen_by is Model.FULL for c in plan_a.cases)
    assert all(c.reason for c in plan_a.cases)


def test_verdict_of_axle_a_names_the_disagreement(plan_a):
    verdict = verdict_of(plan_a)
    one = [d for d in verdict.disagreements if d.kind is DisagreementKind.ONE_MODEL]
    assert one and all(d.shimmies is Model.FULL and d.other is Model.REDUCED for d in one)
    case = next(c for c in plan_a.cases if c.label == one[0].case)
    w = case.windows_of(Model.FULL)[0]
    expected = (f"the reduced model is shimmy-free above 2.61 bar and runs straight at {case.label}; the full "
                f"geometry shimmies at {case.label} {w.text()}")
    assert one[0].text == expected
    assert w.text().endswith("km/h (yaw)")
    boundary = next(d for d in verdict.disagreements if d.kind is DisagreementKind.BOUNDARY)
    assert boundary.shimmies is Model.FULL
    lines = verdict.lines()
    high = plan_a.scan_of(Model.FULL).boundary.pressure_bar
    assert lines[0] == f"Shimmy-free at every speed in both models above {high:.2f} bar."
    assert "The models disagree: " + expected + "." in lines
    as_json = json.loads(json.dumps(verdict.to_json()))
    assert as_json["lines"] == lines and as_json["margins"] == []
    assert {m["model"] for m in as_json["models"]} == {"reduced", "full"}


def test_growth_root_is_the_fold_of_the_hopf_curves(plan_a):
    """Two methods for one boundary: the root in pressure of the largest growth rate over speed against the
    highest fold of the reduced model's Hopf curves (the full geometry's quick boundary uses the former)."""
    axle = read_axle(SHIMMIES_IN_FULL)
    fold = plan_a.scan_of(Model.REDUCED).boundary.pressure_bar
    assert abs(growth_root(family_of(axle, Model.REDUCED), 2.5, 3.0) - fold) < 1e-3


def test_plan_and_verdict_of_the_stable_axle(plan_b):
    assert {c.kind for c in plan_b.cases} == {CaseKind.STABLE} and len(plan_b.cases) == 3
    verdict = verdict_of(plan_b)
    assert all(m.boundary.kind is BoundaryKind.NO_SHIMMY for m in verdict.models)
    assert verdict.disagreements == ()
    assert verdict.lines()[0] == "No shimmy at any speed in 0.5-3.5 bar in either model."


def test_stable_axle_is_still_checked(plan_b, tmp_path):
    """Axle (b): eigenvalues and a transient of the MBS with the reduced model's assumptions pass against the
    reduced model; the cycle and assumption sections have nothing to check and are not counted as passed."""
    from comparisons.verify.cycles import cycles_section
    from comparisons.verify.sections import assumptions_section, hopf_section, transient_section
    axle = read_axle(STABLE)
    one_case = dataclasses.replace(plan_b, cases=plan_b.cases[:1])
    ctx = Context(out=str(tmp_path), quick=True, axle=axle, plan=one_case, recordings=False)
    hopf, transient = hopf_section(ctx), transient_section(ctx)
    eigen = [r for r in hopf.rows if r.cells["point"] == "eigenvalues"]
    assert len(eigen) == 2 and all(r.status is CheckStatus.PASS for r in eigen)
    assert [r.status for r in transient.rows] == [CheckStatus.PASS]
    assert "decays in both models" in transient.rows[0].note
    empty = [cycles_section(ctx), assumptions_section(ctx)]
    assert all([r.status for r in s.rows] == [CheckStatus.COULD_NOT_CHECK] for s in empty)
    report = Report((hopf, transient, *empty), quick=True, plan=plan_b, axle=axle, verdict=verdict_of(plan_b))
    passed = report.count(CheckStatus.PASS)
    assert not report.failed and passed == hopf.count(CheckStatus.PASS) + 1
    assert report.overall() == (f"all {passed} equivalence checks passed; 2 could not be checked (not counted as "
                                f"passed); nothing checked in {empty[0].title}, {empty[1].title}")
    text = render_markdown(report)
    assert text.index("## Verdict") < text.index("## Summary")
    assert "**No shimmy at any speed in 0.5-3.5 bar in either model.**" in text
    assert "Verdict</h2>" in render_html(report, str(tmp_path))


def test_nothing_checked_never_reads_as_passed():
    nothing = Section("cycles", "Limit cycles", ("case",), (Row({}, CheckStatus.COULD_NOT_CHECK, "no shimmy"),))
    info = Section("plan", "Plan", ("case",), (Row({"case": "1 bar"}, CheckStatus.INFO),))
    report = Report((info, nothing), quick=True)
    assert not report.failed and report.overall() == ("nothing was checked; 1 could not be checked (not counted as "
                                                  "passed); nothing checked in Limit cycles")
    assert "passed" not in render_markdown(report).split("Overall: ")[1].split("\n")[0]
    assert report.summary_rows()[1]["could not check"] == 1 and report.summary_rows()[1]["pass"] == 0


def run_quick(axle_file, out):
    proc = subprocess.run([sys.executable, "-m", "comparisons.cli", "verify", "--quick", "--no-recordings", "--axle",
                           axle_file, "--out", str(out), "--json"], capture_output=True, text=True, timeout=1200)
    assert proc.returncode == 0, proc.stderr
    return json.loads(proc.stdout)


@pytest.mark.slow
def test_verify_quick_on_axle_a(tmp_path):
    summary = run_quick(SHIMMIES_IN_FULL, tmp_path)
    kinds = {d["kind"] for d in summary["verdict"]["disagreements"]}
    assert {"one_model", "boundary"} <= kinds
    assert any("the full geometry shimmies at" in line for line in summary["verdict"]["lines"])
    text = (tmp_path / "report.md").read_text()
    assert text.index("## Verdict") < text.index("## Run") < text.index("## Summary")
    assert not summary["failed"] and "Overall: all " in text


@pytest.mark.slow
def test_verify_quick_on_axle_b(tmp_path):
    summary = run_quick(STABLE, tmp_path)
    by_key = {s["key"]: s for s in summary["sections"]}
    assert all(r["status"] == "pass" for r in by_key["transient"]["rows"])
    assert [r["status"] for r in by_key["cycles"]["rows"]] == ["could not check"]
    assert summary["verdict"]["headline"] == "No shimmy at any speed in 0.5-3.5 bar in either model."
    assert "nothing checked in" in (tmp_path / "report.md").read_text()
