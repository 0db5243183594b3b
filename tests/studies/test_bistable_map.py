"""Bistable regions in (speed, pressure) (issue 30, item 5): slices joined into regions, brackets, the
stable-shimmy-free pressure, and one region of the paper's t0 = 0.25 m axle checked by runs."""

import json

import pytest

from axles.units import BAR, from_kmh, kmh
from comparisons.studies.bistable_map import MapStatus, Slice, bistable_map, regions_of

KMH = from_kmh(1.0)


def test_overlapping_intervals_of_neighbouring_pressures_form_one_region():
    slices = [Slice(1e5, (), False, True),
              Slice(2e5, ((100 * KMH, 110 * KMH), (300 * KMH, 310 * KMH)), True, True),
              Slice(3e5, ((105 * KMH, 120 * KMH),), True, True),
              Slice(4e5, ((130 * KMH, 140 * KMH),), True, True),      # no overlap with 105-120: a new region
              Slice(5e5, (), True, True)]
    regions = regions_of(slices)
    assert [tuple(p for p, _, _ in r.slices) for r in regions] == [(2e5, 3e5), (2e5,), (4e5,)]
    first = next(r for r in regions if r.slices[0][1] == 100 * KMH)
    assert first.low_bracket == (1e5, 2e5) and first.high_bracket == (3e5, 4e5)
    assert [round(kmh(v), 9) for v in first.speed_range] == [100, 120]
    lone = next(r for r in regions if r.slices[0][1] == 300 * KMH)
    assert lone.high_bracket == (2e5, 3e5)
    json.dumps([r.to_json() for r in regions])


def test_no_interval_no_region():
    assert regions_of([Slice(1e5, (), True, True), Slice(2e5, (), False, True)]) == ()


@pytest.fixture(scope="module")
def paper_t025_map():
    from axles.axle import paper_axle
    from comparisons.verify.bistable_rows import family_at
    from comparisons.verify.scan import VMAX, Model
    axle = paper_axle().with_values({"t0": 0.25})
    found = bistable_map(family_at(axle, Model.REDUCED), [b * BAR for b in (0.5, 1.5, 3.5)], from_kmh(0.5), VMAX,
                         "the reduced model")
    return axle, found


def test_the_paper_t025_axle_is_bistable_at_1p5_bar(paper_t025_map):
    """The reduced model's window of figures 9-11 (t0 = 0.25 m, 1.5 bar): a stable cycle beside another stable
    state between 159.2 and 184.7 km/h (the computed cycles' speeds), not at 0.5 bar nor at 3.5 bar."""
    _, found = paper_t025_map
    assert found.status is MapStatus.COMPLETE
    (region,) = found.regions
    assert [p for p, _, _ in region.slices] == [1.5 * BAR]
    assert region.low_bracket == (0.5 * BAR, 1.5 * BAR) and region.high_bracket == (1.5 * BAR, 3.5 * BAR)
    lo, hi = region.speed_range
    assert kmh(lo) == pytest.approx(159.2, abs=0.1) and kmh(hi) == pytest.approx(184.7, abs=0.1)
    assert found.stable_shimmy_free is None        # stable shimmy up to 3.5 bar at t0 = 0.25 m
    assert "bistable at 1.5 bar, 159.2-184.7 km/h" in found.text()


def test_a_kick_check_of_the_region_passes(paper_t025_map):
    """Runs of the same model: the threshold kick leaves the lower state inside the region, and ends on the one
    stable state just beyond it."""
    from comparisons.verify.bistable_rows import region_row
    from comparisons.verify.report import CheckStatus
    from comparisons.verify.scan import Model
    axle, found = paper_t025_map
    row = region_row(axle, Model.REDUCED, found.regions[0])
    assert row.status is CheckStatus.PASS, row.note
    assert 5.0 < row.cells["kick_deg"] < 9.0


def test_the_stable_shimmy_free_pressure_is_bracketed_by_bisection():
    """The paper's axle (t0 = 0.07 m): stable cycles at 2.5 bar, none at 3.0 bar: the pressure above which no
    stable shimmy exists lies between them, to the bisection's tolerance, beside the linear boundary."""
    from axles.axle import paper_axle
    from comparisons.verify.bistable_rows import family_at
    from comparisons.verify.scan import VMAX, Model
    found = bistable_map(family_at(paper_axle(), Model.REDUCED), [2.5 * BAR, 3.0 * BAR], from_kmh(0.5), VMAX,
                         "the reduced model", xtol=0.05 * BAR)
    assert found.regions == ()
    lo, hi = found.stable_shimmy_free_bracket
    assert 2.5 * BAR <= lo < hi <= 3.0 * BAR and hi - lo <= 0.05 * BAR and found.stable_shimmy_free == hi
    assert f"no stable shimmy at any speed above {hi / BAR:.2f} bar" in found.text()


def test_a_map_past_its_budget_says_where_it_stopped_and_claims_nothing_it_did_not_compute():
    """A budget far too small (1 ms for three pressures): the first slice stops on its first cycle and says where;
    the others are not started; no region and no stable-shimmy-free pressure are read off slices never computed."""
    from axles.axle import paper_axle
    from comparisons.verify.bistable_rows import family_at
    from comparisons.verify.scan import VMAX, Model
    found = bistable_map(family_at(paper_axle(), Model.REDUCED), [b * BAR for b in (1.5, 2.5, 3.5)], from_kmh(0.5),
                         VMAX, "the reduced model", budget_s=1e-3)
    assert found.status is MapStatus.OVER_BUDGET and not found.status.is_complete
    assert all(s.over_budget and not s.complete and s.intervals == () for s in found.slices)
    assert found.slices[0].message.startswith("stopped on a branch at ")
    assert [s.message for s in found.slices[1:]] == ["not started: the budget was spent"] * 2
    assert found.regions == () and not found.free_determined and found.stable_shimmy_free is None
    assert "the time budget of 0.001 s ran out at 1.5 bar, 2.5 bar, 3.5 bar" in found.text()
    assert found.to_json()["status"] == "over_budget"


def test_a_budget_it_stays_within_changes_nothing(paper_t025_map):
    axle, unbounded = paper_t025_map
    from comparisons.verify.bistable_rows import family_at
    from comparisons.verify.scan import VMAX, Model
    found = bistable_map(family_at(axle, Model.REDUCED), [b * BAR for b in (0.5, 1.5, 3.5)], from_kmh(0.5), VMAX,
                         "the reduced model", budget_s=600.0)
    assert found.status is MapStatus.COMPLETE and found.regions == unbounded.regions
    assert found.text() == unbounded.text()


def test_a_branch_past_its_budget_stops_with_what_it_computed():
    """``BranchBudget`` (figure 9 for the full geometry): a branch past its wall clock ends as ``stopped``, not
    complete, with the cycles it computed and a message saying where; the next branch starts its own budget."""
    from axles.pressures import TyrePressures
    from axles.units import from_kmh
    from bifurcation.cycles.branches import cycle_diagram
    from bifurcation.special_points import BranchStatus
    from comparisons.studies.budget import BranchBudget
    from reduced_model.family import SpeedFamily
    from reduced_model.model import ShimmyModel

    family = SpeedFamily(ShimmyModel(), pressures=TyrePressures.uniform(1.5e5))
    whole = cycle_diagram(family, family.nominal, 0.0, from_kmh(400.0))
    hook = BranchBudget(0.0, family.state_names)
    cut = cycle_diagram(family, family.nominal, 0.0, from_kmh(400.0), accept_hook=hook, progress=hook.next_branch)
    assert whole.complete and not cut.complete
    assert len(cut.branches) >= len(whole.branches)
    for b in cut.branches:
        assert b.status is BranchStatus.STOPPED and not b.status.is_complete
        assert len(b.points) >= 1 and "stopped after its time budget of 0 s, at" in str(b.message)


def test_a_bisection_slice_that_stopped_early_is_named_in_the_maps_text(monkeypatch):
    """A random plausible axle (CAMPAIGN-45-07) said 'INCOMPLETE: ' and nothing more: the bisection for the
    stable-shimmy-free pressure met a slice whose continuation stopped early, off the grid, where the text looked
    only at the grid.  Its pressure and its branch's message are now in the text."""
    import comparisons.studies.bistable_map as bm

    def fake_slice(family, q, p_min, p_max, deadline=float("inf")):
        if q < 1.0 * BAR:
            return Slice(q, (), True, True)
        if q >= 2.0 * BAR:
            return Slice(q, (), False, True)
        return Slice(q, (), False, False, "step size underflow after 7 points")

    monkeypatch.setattr(bm, "slice_at", fake_slice)
    family = type("F", (), {"nominal": None})

    def family_at(pressure):
        f = family()
        f.nominal = pressure
        return f

    result = bistable_map(family_at, [0.5 * BAR, 2.0 * BAR], 0.0, 50.0, "the reduced model")
    assert result.status is MapStatus.INCOMPLETE
    text = result.text()
    assert "INCOMPLETE: a continuation stopped early at 1.25 bar (step size underflow after 7 points)" in text, text
