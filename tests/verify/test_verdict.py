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
from comparisons.verify.rendering import render_html, render_markdown
from comparisons.verify.report import CheckStatus, Report, Row, Section
from comparisons.verify.scan import BoundaryKind, BoundaryMethod, Model, growth_root, scan_family
from comparisons.verify.verdict import DisagreementKind, stretches, verdict_of

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
    (w,) = stretches(case.windows_of(Model.FULL))
    expected = (f"the reduced model is shimmy-free above 2.61 bar and runs straight at {case.label}; the full "
                f"geometry shimmies at {case.label} {w.text()}")
    assert one[0].text == expected
    assert w.text().endswith("km/h (yaw throughout)")
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
    assert abs(growth_root(scan_family(axle, Model.REDUCED), 2.5, 3.0) - fold) < 1e-3


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
    assert report.overall() == (f"all {passed} equivalence checks passed; 2 could not be checked (counted apart); "
                                f"nothing checked in {empty[0].title}, {empty[1].title}")
    text = render_markdown(report)
    assert text.index("## Verdict") < text.index("## Summary")
    assert "**No shimmy at any speed in 0.5-3.5 bar in either model.**" in text
    assert "Verdict</h2>" in render_html(report, str(tmp_path))


def test_nothing_checked_never_reads_as_passed():
    nothing = Section("cycles", "Limit cycles", ("case",), (Row({}, CheckStatus.COULD_NOT_CHECK, "no shimmy"),))
    info = Section("plan", "Plan", ("case",), (Row({"case": "1 bar"}, CheckStatus.INFO),))
    report = Report((info, nothing), quick=True)
    assert not report.failed and report.overall() == ("nothing was checked; 1 could not be checked (counted apart); "
                                                      "nothing checked in Limit cycles")
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


def window(low_kmh: float, high_kmh: float, mode: str, unstable: tuple[str, ...]):
    from axles.units import from_kmh
    from comparisons.verify.scan import Window
    return Window(from_kmh(low_kmh), from_kmh(high_kmh), mode, 3.0, closed=True, unstable=unstable)


def test_one_window_per_maximal_unstable_stretch_with_each_modes_ranges():
    """The old verdict cut one unstable stretch at every Hopf point inside it ("from 0.5 to 165.5 km/h (yaw) and
    from 165.5 to 363.9 km/h (yaw) and ..."); now the windows of a case are disjoint and do not touch, and each
    lists its modes with their own ranges."""
    from comparisons.verify.plan import VMAX
    from comparisons.verify.scan import Window
    from reduced_model.family import MIN_SPEED
    from axles.units import from_kmh, kmh
    parts = (Window(MIN_SPEED, from_kmh(184.0), "yaw", 3.0, False, ("yaw",)),
             window(184.0, 196.0, "tramp", ("yaw", "tramp")),
             Window(from_kmh(196.0), VMAX, "yaw", 3.0, False, ("yaw",)))
    (one,) = stretches(parts)
    assert (one.low, one.high) == (MIN_SPEED, VMAX)
    assert one.text() == ("from 0.5 to 400.0 km/h, from the lowest speed and up to the top of the speed window (yaw "
                          "throughout, tramp from 184.0 to 196.0 km/h)")
    data = one.to_json()
    assert [m["mode"] for m in data["modes"]] == ["yaw", "tramp"]
    assert data["modes"][1]["ranges_kmh"] == [[pytest.approx(184.0), pytest.approx(196.0)]]
    # two stretches apart, a mode growing on two ranges of one stretch
    two = stretches((window(40.0, 60.0, "yaw", ("yaw",)), window(60.0, 70.0, "tramp", ("tramp",)),
                     window(70.0, 80.0, "yaw", ("yaw",)), window(90.0, 95.0, "yaw", ("yaw",))))
    assert [(round(kmh(w.low), 6), round(kmh(w.high), 6)) for w in two] == [(40.0, 80.0), (90.0, 95.0)]
    assert all(a.high < b.low for a, b in zip(two[:-1], two[1:]))      # disjoint, not touching
    assert two[0].text() == ("from 40.0 to 80.0 km/h (yaw from 40.0 to 60.0 km/h and from 70.0 to 80.0 km/h, "
                             "tramp from 60.0 to 70.0 km/h)")


def test_the_full_geometrys_line_carries_its_robustness():
    """Where the report has a Robustness section, the full geometry's line says in what share of its plausible
    axles it shimmies at that case."""
    from comparisons.verify.scan import Boundary, BoundaryKind
    from comparisons.verify.verdict import CaseFacts, ModelVerdict, RobustnessShare, Verdict
    facts = CaseFacts("1.5 bar", 1.5, 1.5, stretches((window(40.0, 60.0, "yaw", ("yaw",)),)))
    models = tuple(ModelVerdict(m, (0.5, 3.5), Boundary(BoundaryKind.SHIMMY_FREE_ABOVE, 2.6), (facts,))
                   for m in (Model.REDUCED, Model.FULL))
    verdict = Verdict(models, (), robustness=(RobustnessShare("1.5 bar", 0.39, 64),))
    line = next(x for x in verdict.lines() if x.startswith("At 1.5 bar"))
    assert line == ("At 1.5 bar: the reduced model shimmies from 40.0 to 60.0 km/h (yaw throughout); the full geometry "
                    "shimmies from 40.0 to 60.0 km/h (yaw throughout); over its plausible dimensions the full geometry "
                    "shimmies at 1.5 bar in 39 % of axles (64 sampled).")
    assert verdict.to_json()["robustness"][0]["share"] == 0.39


def test_each_models_bistable_map_is_under_its_key_in_the_verdict_json():
    """The section "Bistable regions" adds each model's map to the verdict: a line per model and, in the JSON, a
    key ``bistable`` under that model; a map not computed says so, never reads as "no region"."""
    from comparisons.studies.bistable_map import BistableMap, BistableRegion, MapStatus, Slice
    from comparisons.verify.bistable_rows import BistableFact
    from comparisons.verify.scan import Boundary, BoundaryKind
    from comparisons.verify.verdict import ModelVerdict, Verdict
    models = tuple(ModelVerdict(m, (0.5, 3.5), Boundary(BoundaryKind.SHIMMY_FREE_ABOVE, 2.6), ())
                   for m in (Model.REDUCED, Model.FULL))
    region = BistableRegion(((1.5e5, 44.0, 51.0),), (1e5, 1.5e5), (1.5e5, 2e5))
    found = BistableMap("the reduced model", (0.1, 111.0), (Slice(1e5, (), True, True),
                                                            Slice(1.5e5, ((44.0, 51.0),), True, True),
                                                            Slice(2e5, (), True, True)),
                        (region,), 2.6e5, (2.55e5, 2.6e5), MapStatus.COMPLETE)
    verdict = Verdict(models, (), bistable=(BistableFact(Model.REDUCED, found),
                                            BistableFact(Model.FULL, None, "too slow here")))
    out = verdict.to_json()
    reduced, full = out["models"]
    assert reduced["bistable"]["regions"][0]["pressure_bar"] == [1.5, 1.5]
    assert reduced["bistable"]["regions"][0]["speed_kmh"] == pytest.approx([158.4, 183.6])
    assert reduced["bistable"]["stable_shimmy_free_above_bar"] == 2.6
    assert full["bistable"]["status"] == "not_computed" and full["bistable"]["reason"] == "too slow here"
    lines = verdict.lines()
    assert ("The reduced model: bistable at 1.5 bar, 158.4-183.6 km/h; no stable shimmy at any speed above 2.60 bar."
            in lines)
    assert "The full geometry: bistable regions not computed (too slow here)." in lines
