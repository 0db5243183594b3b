"""The verify section "Stability margins" on an axle with no Hopf point at all (the paper's axle with
c4 = 120 N m s/rad): it still checks something, and says the axle is damped everywhere."""

from axles.axle import AxleData
from comparisons.verify.context import Context
from comparisons.verify.margins import FIGURE, margins_section
from comparisons.verify.plan import Plan
from comparisons.verify.report import CheckStatus


def test_a_stable_axle_has_a_margin_figure_and_passing_checks(tmp_path):
    axle = AxleData().with_overrides({"c4": 120.0})
    section = margins_section(Context(out=str(tmp_path), quick=True, axle=axle, plan=Plan((), ())))
    assert section.key == "margins" and (tmp_path / FIGURE).stat().st_size > 10_000
    checks = [r for r in section.rows if r.status is not CheckStatus.INFO]
    assert len(checks) >= 3 and all(r.status is CheckStatus.PASS for r in checks)
    zero = [r for r in checks if r.cells["quantity"].startswith("zero level")]
    assert {r.cells["model"] for r in zero} == {"reduced model", "MBS, full geometry"}
    assert all("no Hopf point and no zero level" in r.note for r in zero)
    minima = {r.cells["model"]: r.cells for r in section.rows if r.cells["quantity"] == "minimum margin"}
    assert set(minima) == {"reduced model", "MBS, full geometry"}
    assert all(m["damping_ratio"] > 0 for m in minima.values())


def test_the_margin_minima_reach_the_verdict(tmp_path):
    """The section hands each model's minimum to the verdict as data (sentence and JSON from the same point)."""
    axle = AxleData().with_overrides({"c4": 120.0})
    section = margins_section(Context(out=str(tmp_path), quick=True, axle=axle, plan=Plan((), ())))
    facts = {f.model: f for f in section.verdict_facts}
    assert set(facts) == {"reduced model", "MBS, full geometry"}
    minima = {r.cells["model"]: r.cells for r in section.rows if r.cells["quantity"] == "minimum margin"}
    for model, fact in facts.items():
        data = fact.to_json()
        assert data["damping_ratio"] == minima[model]["damping_ratio"] > 0
        assert f"{data['damping_ratio']:+.4f}" in fact.text() and "every mode is damped" in fact.text()
