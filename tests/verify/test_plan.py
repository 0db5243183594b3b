"""The plan of ``shimmy verify`` for an axle other than the paper's: it finds the bistable window by itself.

The whole quick report for this axle (ramps, two starts, recordings) is in the slow suite
(``tests/verify/test_verify.py::test_verify_axle_plans_and_finds_the_bistable_window``); this test runs the plan
alone, which is where the window is found."""

from axles.axle import paper_axle
from comparisons.verify.plan import CaseKind, axle_plan


def test_plan_finds_the_bistable_window_of_the_paper_axle_with_t0_025():
    axle = paper_axle().with_values({"t0": 0.25})
    plan = axle_plan(axle, quick=True)
    assert len(plan.bistable) == 1
    window = plan.bistable[0]
    # It overlaps figure 9a's T2..S1 (157.38-184.75 km/h at 1.5 bar).
    assert window.low_kmh < 185.0 and window.high_kmh > 157.0 and window.low_kmh < window.high_kmh
    assert all(c.pressure_right_bar == c.pressure_left_bar for c in plan.cases)
    assert any(c.pressure_right_bar == window.pressure_bar for c in plan.cases)
    assert all(c.reason for c in plan.cases)
    assert any(c.kind is CaseKind.MODE for c in plan.cases)          # the axle shimmies: its modes are cases
