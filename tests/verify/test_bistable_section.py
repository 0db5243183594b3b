"""``verify``'s section "Bistable regions" for both models: the full geometry's map is computed in a second process
when one is running, quick or not, each map within its time budget, and a continuation that fails or a map past its
budget is "could not check" with the reason, never read as "no region".  The maps are made up here (the studies are
tested in tests/studies/test_bistable_map.py); the full geometry's own map is the slow test at the end."""

import pytest

from axles.axle import paper_axle
from axles.units import BAR, from_kmh
from comparisons.studies.bistable_map import BistableMap, BistableRegion, MapStatus, Slice
from comparisons.verify import bistable_rows
from comparisons.verify.context import Context
from comparisons.verify.report import CheckStatus, Row
from comparisons.verify.scan import Model


def made_up_map(label, region=False):
    v = from_kmh(1.0)
    slices = (Slice(1e5, ((150 * v, 160 * v),) if region else (), True, True), Slice(2e5, (), False, True))
    regions = (BistableRegion(((1e5, 150 * v, 160 * v),), (1e5, 1e5), (1e5, 2e5)),) if region else ()
    return BistableMap(label, (0.0, 400 * v), slices, regions, 1.6e5, (1.5e5, 1.6e5), MapStatus.COMPLETE)


@pytest.fixture
def calls(monkeypatch):
    """The models whose maps were asked for, and the regions whose kicks were checked."""
    asked = {"maps": [], "kicks": []}

    def model_map(axle, model, grid, xtol, budget_s=None, progress=lambda text: None):
        asked["maps"].append(model)
        asked.setdefault("budgets", []).append(budget_s)
        if model is Model.FULL and asked.get("fail"):
            raise RuntimeError("the branch at 1 bar did not converge")
        return made_up_map(model.label, region=model is Model.FULL), 12.0

    def region_row(axle, model, region, kick_tol):
        asked["kicks"].append(model)
        return Row({"model": model.value}, CheckStatus.PASS, "kick checked")

    monkeypatch.setattr(bistable_rows, "model_map", model_map)
    monkeypatch.setattr(bistable_rows, "region_row", region_row)
    return asked


def facts(section):
    return {f.model: f for f in section.verdict_facts}


def test_quick_computes_both_maps_within_the_quick_budget(calls):
    section = bistable_rows.bistable_section(Context(out="unused", quick=True, axle=paper_axle()))
    assert calls["maps"] == [Model.REDUCED, Model.FULL] and calls["kicks"] == [Model.FULL]
    assert calls["budgets"] == [bistable_rows.QUICK_BUDGET_S] * 2
    assert facts(section)[Model.FULL].map is not None


def test_a_map_past_its_budget_is_could_not_check_with_where_it_stopped(monkeypatch):
    """A slice stopped by the budget: the map's row says which pressures and where the branch was."""
    v = from_kmh(1.0)
    over = BistableMap("the full geometry", (0.0, 400 * v),
                       (Slice(1e5, (), False, False, "stopped on a branch at 6.1 km/h", over_budget=True),
                        Slice(2e5, (), False, True)), (), None, None, MapStatus.OVER_BUDGET, 30.0, False)
    monkeypatch.setattr(bistable_rows, "model_map", lambda *a, **k: (over, 30.2))
    section = bistable_rows.bistable_section(Context(out="unused", quick=True, axle=paper_axle()))
    rows = [r for r in section.rows if r.cells["model"] == "full"]
    assert [r.status for r in rows] == [CheckStatus.COULD_NOT_CHECK]
    assert "the time budget of 30 s ran out at 1 bar (stopped on a branch at 6.1 km/h)" in rows[0].note
    assert "stable-shimmy-free pressure is not determined" in rows[0].note
    got = facts(section)[Model.FULL].to_json()
    assert got["status"] == "over_budget" and got["stable_shimmy_free_determined"] is False


def test_the_full_verify_computes_the_full_geometry_and_checks_its_regions(calls):
    section = bistable_rows.bistable_section(Context(out="unused", quick=False, axle=paper_axle()))
    assert calls["maps"] == [Model.REDUCED, Model.FULL] and calls["kicks"] == [Model.FULL]
    full = facts(section)[Model.FULL]
    assert full.map is not None and full.to_json()["regions"][0]["speed_kmh"] == pytest.approx([150.0, 160.0])
    rows = [r for r in section.rows if r.cells["model"] == "full"]
    assert [r.status for r in rows] == [CheckStatus.INFO, CheckStatus.PASS]
    assert rows[0].note.startswith("the full geometry: bistable at 1 bar, 150.0-160.0 km/h")
    assert "(12 s)" in rows[0].note


def test_a_failed_continuation_is_could_not_check_with_its_error(calls):
    calls["fail"] = True
    section = bistable_rows.bistable_section(Context(out="unused", quick=False, axle=paper_axle()))
    full = facts(section)[Model.FULL]
    assert full.map is None and "did not converge" in full.reason
    (row,) = [r for r in section.rows if r.cells["model"] == "full"]
    assert row.status is CheckStatus.COULD_NOT_CHECK and "a continuation failed" in row.note


class FakeBackground:
    def __init__(self):
        self.jobs = {}

    def submit(self, key, job, *args):
        self.jobs[key] = (job, args)

    def started(self, key):
        return key in self.jobs

    def result(self, key):
        job, args = self.jobs.pop(key)
        return job(*args)


def test_the_full_map_runs_in_the_background_quick_or_not(calls):
    background = FakeBackground()
    bistable_rows.start_full_map(Context(out="unused", quick=True, axle=paper_axle(), background=background))
    job, (_, _, grid, _, budget) = background.jobs.pop(bistable_rows.FULL_JOB)
    assert len(grid) == 7 and budget == bistable_rows.QUICK_BUDGET_S
    ctx = Context(out="unused", quick=False, axle=paper_axle(), background=background)
    bistable_rows.start_full_map(ctx)
    job, (axle, model, grid, xtol, budget) = background.jobs[bistable_rows.FULL_JOB]
    assert model is Model.FULL and grid[0] == pytest.approx(0.5 * BAR) and xtol == pytest.approx(0.01 * BAR)
    assert budget == bistable_rows.BUDGET_S
    found, _ = bistable_rows.full_map(ctx)        # collected from the job, not computed again
    assert found.label == Model.FULL.label and not background.jobs


def test_the_background_job_and_its_result_cross_a_process_boundary():
    """A spawned process receives the job by pickling and sends the map back the same way."""
    import pickle
    ctx = Context(out="unused", quick=False, axle=paper_axle())
    _, grid, xtol, budget = bistable_rows.map_settings(ctx)
    job = pickle.loads(pickle.dumps((bistable_rows.model_map, (ctx.axle, Model.FULL, grid, xtol, budget))))
    assert job[0] is bistable_rows.model_map and job[1][1] is Model.FULL
    found = made_up_map("the full geometry", region=True)
    assert pickle.loads(pickle.dumps((found, 1.0)))[0].to_json() == found.to_json()


@pytest.mark.slow
def test_the_full_geometry_of_the_paper_axle_loses_its_stable_shimmy_where_its_hopf_points_vanish():
    """The full geometry's own map on the paper's axle at 1.5-2.5 bar (about 2 min on the twin under load): its
    Hopf points there are subcritical only by the camber kink, their unstable cycles folding back within 1e-4 km/h
    at a hundredth of a degree (tests/mbs/test_mbs_kink.py), so no region a kick could use; and the pressure
    above which no stable cycle exists is where straight running stops shimmying at all: Hopf points at the
    bracket's low end, none at its high end (the linear test, independent of the cycles)."""
    from bifurcation.equilibria.hopf import find_hopf_points
    from comparisons.verify.scan import VMAX
    axle = paper_axle()
    found, _ = bistable_rows.model_map(axle, Model.FULL, [1.5 * BAR, 2.0 * BAR, 2.5 * BAR], 0.02 * BAR)
    assert found.status is MapStatus.COMPLETE and found.regions == ()
    assert [s.stable_cycle for s in found.slices] == [True, True, False]
    lo, hi = found.stable_shimmy_free_bracket
    assert hi - lo <= 0.02 * BAR and found.stable_shimmy_free == hi
    family = bistable_rows.family_at(axle, Model.FULL)
    below, above = (find_hopf_points(f, f.nominal, from_kmh(0.5), VMAX, lyapunov=False)
                    for f in (family(lo), family(hi)))
    assert len(below) == 2 and len(above) == 0
