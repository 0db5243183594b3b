"""The bistable window next to a hard onset (``comparisons.studies.onset.onset_window``), as the robustness section
counts it over the plausible axles: on the paper's axle with t0 = 0.25 m at 1.5 bar the full geometry's Hopf point
at 194.65 km/h is subcritical, its unstable cycles fold back at 204.25 km/h and come back stable, and straight
running is stable above the Hopf point: a window from the Hopf point to the last stable cycle before the fold.
Checked against the whole one-parameter diagram of the same model, an independent run of the continuation over the
whole speed window."""

import pytest

from axles.pressures import TyrePressures
from axles.units import BAR, KMH, from_kmh, kmh
from bifurcation.cycles.branches import cycle_diagram
from bifurcation.equilibria.hopf import find_hopf_points
from bifurcation.special_points import PointKind
from comparisons.api import Axle
from comparisons.studies.bistable_map import MIN_WIDTH
from comparisons.studies.kick import bistable_windows
from comparisons.studies.onset import onset_window


@pytest.fixture(scope="module")
def t025():
    family = Axle.paper().with_values(t0=0.25).mbs("full").problem(TyrePressures.uniform(1.5 * BAR))
    return family, find_hopf_points(family, family.nominal, 0.0, 400 * KMH)


def test_the_window_next_to_the_hard_onset_at_t0_025(t025):
    family, points = t025
    hb = next(h for h in points if 190 * KMH < h.p < 200 * KMH)
    found = onset_window(family, hb, points, 400 * KMH, MIN_WIDTH, from_kmh(0.5))
    assert found.kind == "window"
    low, high = found.interval
    assert low == hb.p
    # the same window in the whole diagram's branches, and its fold just beyond the window's last stable cycle
    diagram = cycle_diagram(family, family.nominal, 190 * KMH, 215 * KMH)
    whole = [w for w in bistable_windows(diagram, family, MIN_WIDTH) if w[0] <= hb.p <= w[1]]
    assert len(whole) == 1 and whole[0][0] == pytest.approx(low) and kmh(abs(whole[0][1] - high)) < 0.5
    (fold,) = [p for b in diagram.branches for p in b.special_points if p.kind is PointKind.CYCLE_FOLD]
    assert 0.0 <= kmh(fold.p - high) < 0.5 and kmh(high - low) > 9.0


def test_the_kinds_on_normal_forms_whose_folds_are_known():
    """The subcritical normal form (fold at SHIFT - 1, straight running stable above the Hopf point at SHIFT): a
    window from the fold to the Hopf point; the supercritical one: no stable cycle beside stable straight running
    ("none"); two oscillators, the upper point's both sides unstable ("no_stable_side")."""
    from tests.bifurcation.test_cycles_toy import SHIFT, ToyFamily, subcritical, supercritical
    from tests.verify.test_other_axle import two_points
    family = ToyFamily(subcritical, 2)
    (h,) = find_hopf_points(family, 0.0, 0.5, 6.0)
    found = onset_window(family, h, [h], 6.0, 0.0, 0.05)
    assert found.kind == "window"
    assert found.interval[1] == pytest.approx(h.p) and found.interval[0] == pytest.approx(SHIFT - 1.0, abs=0.05)
    family = ToyFamily(supercritical, 2)
    (h,) = find_hopf_points(family, 0.0, 0.5, 6.0)
    assert onset_window(family, h, [h], 6.0, 0.0, 0.05).kind == "none"
    family = ToyFamily(two_points, 4)
    points = find_hopf_points(family, 0.0, 0.5, 9.0)
    assert onset_window(family, points[1], points, 9.0, 0.0, 0.05).kind == "no_stable_side"


def test_a_window_past_its_budget_is_not_known(t025):
    """1 ms for the branch of the hard onset at 194.65 km/h: stopped on its first cycle, said so, no interval."""
    family, points = t025
    hb = next(h for h in points if 190 * KMH < h.p < 200 * KMH)
    found = onset_window(family, hb, points, 400 * KMH, MIN_WIDTH, from_kmh(0.5), budget_s=1e-3)
    assert found.kind == "incomplete" and found.interval is None
    assert found.message.startswith("over its 0.001 s budget, stopped on a branch at 19")
