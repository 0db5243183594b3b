"""``verify``'s section "Bistable regions" for both models: the full geometry's map is computed in the full verify
(in a second process when one is running), left out of ``--quick`` with the reason, and a continuation that fails
is "could not check" with its error, never read as "no region".  The maps are made up here (the studies are
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

    def model_map(axle, model, grid, xtol, progress=lambda text: None):
        asked["maps"].append(model)
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


def test_quick_leaves_the_full_geometry_out_with_the_reason(calls):
    section = bistable_rows.bistable_section(Context(out="unused", quick=True, axle=paper_axle()))
    assert calls["maps"] == [Model.REDUCED]
    full = facts(section)[Model.FULL]
    assert full.map is None and "not computed in --quick" in full.reason
    (row,) = [r for r in section.rows if r.cells["model"] == "full"]
    assert row.status is CheckStatus.COULD_NOT_CHECK and full.reason in row.note
    assert full.to_json()["status"] == "not_computed"


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


def test_the_full_map_runs_in_the_background_in_the_full_verify_only(calls):
    background = FakeBackground()
    bistable_rows.start_full_map(Context(out="unused", quick=True, axle=paper_axle(), background=background))
    assert background.jobs == {}
    ctx = Context(out="unused", quick=False, axle=paper_axle(), background=background)
    bistable_rows.start_full_map(ctx)
    job, (axle, model, grid, xtol) = background.jobs[bistable_rows.FULL_JOB]
    assert model is Model.FULL and grid[0] == pytest.approx(0.5 * BAR) and xtol == pytest.approx(0.01 * BAR)
    found, _ = bistable_rows.full_map(ctx)        # collected from the job, not computed again
    assert found.label == Model.FULL.label and not background.jobs


def test_the_background_job_and_its_result_cross_a_process_boundary():
    """A spawned process receives the job by pickling and sends the map back the same way."""
    import pickle
    ctx = Context(out="unused", quick=False, axle=paper_axle())
    _, grid, xtol = bistable_rows.map_settings(ctx)
    job = pickle.loads(pickle.dumps((bistable_rows.model_map, (ctx.axle, Model.FULL, grid, xtol))))
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
