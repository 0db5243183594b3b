"""The full geometry at the plan's bistable case on another axle: where its branches are continued (on normal forms
whose folds are known), the second process it runs in, and, in the slow suite, the whole case at t0 = 0.25 m."""

import math
import os
import time

import numpy as np
import pytest

from comparisons.verify.background import Background, BackgroundJobError
from comparisons.studies.onset import onset_windows
from comparisons.studies.kick import bistable_windows
from bifurcation.cycles.branches import cycle_diagram
from bifurcation.equilibria.hopf import find_hopf_points
from bifurcation.special_points import PointKind
from tests.bifurcation.test_cycles_toy import SHIFT, ToyFamily, W, subcritical, supercritical

PAST = 0.05


def subcritical_above(X, V):
    """The subcritical normal form with the speed reversed: straight running stable above SHIFT, fold at mu = 1."""
    return subcritical(X, 2.0 * SHIFT - V)


def two_points(X, V):
    """Two uncoupled oscillators: subcritical at SHIFT (stable side below), supercritical at 2 SHIFT (unstable
    above).  Between them one pair is unstable, so straight running is stable only below SHIFT."""
    u, v = X[2], X[3]
    mu = V - 2.0 * SHIFT
    r2 = u * u + v * v
    return np.concatenate([subcritical(X[:2], V), [mu * u - 1.7 * W * v - u * r2, 1.7 * W * u + mu * v - v * r2]])


@pytest.mark.parametrize("field, fold", [(subcritical, SHIFT - 1.0), (subcritical_above, SHIFT + 1.0)])
def test_the_onset_window_of_a_subcritical_point_holds_its_fold_and_bistable_window(field, fold):
    family = ToyFamily(field, 2)
    hopf = find_hopf_points(family, 0.0, 0.5, 6.0)
    ((a, b),) = onset_windows(family, 0.0, hopf, 0.5, 6.0, PAST)
    (h,) = hopf
    assert min(abs(a - h.p), abs(b - h.p)) == pytest.approx(PAST)       # just past the Hopf point
    assert a < fold < b
    diagram = cycle_diagram(family, 0.0, a, b)
    assert diagram.complete
    (found,) = diagram.points_of(PointKind.CYCLE_FOLD)
    assert found.p == pytest.approx(fold, abs=1e-4)
    ((low, high),) = bistable_windows(diagram, family)
    assert sorted([low, high])[0] == pytest.approx(min(h.p, fold), abs=0.05)
    assert sorted([low, high])[1] == pytest.approx(max(h.p, fold), abs=0.05)


def test_no_window_from_a_supercritical_point_and_none_past_the_next_hopf_point():
    assert onset_windows(ToyFamily(supercritical, 2), 0.0, find_hopf_points(ToyFamily(supercritical, 2), 0.0, 0.5, 6.0),
                         0.5, 6.0, PAST) == []
    family = ToyFamily(two_points, 4)
    hopf = find_hopf_points(family, 0.0, 0.5, 9.0)
    assert len(hopf) == 2
    assert onset_windows(family, 0.0, hopf, 0.5, 9.0, PAST) == [(0.5, SHIFT + PAST)]


def test_a_background_job_returns_its_value_and_raises_its_error_where_collected():
    with Background() as background:
        background.submit("root", math.sqrt, 2.0)
        background.submit("domain", math.sqrt, -1.0)
        assert background.started("root") and not background.started("other")
        with pytest.raises(ValueError, match="already started"):
            background.submit("root", math.sqrt, 3.0)
        assert background.result("root") == math.sqrt(2.0)
        with pytest.raises(ValueError, match="math domain error"):
            background.result("domain")


def test_a_job_whose_process_dies_says_so_and_an_uncollected_one_is_stopped():
    with Background() as background:
        background.submit("dies", os._exit, 3)
        with pytest.raises(BackgroundJobError, match="exit code 3"):
            background.result("dies")
        background.submit("sleeps", time.sleep, 120.0)
        start = time.monotonic()
    assert time.monotonic() - start < 10.0      # close() ended the sleeping process instead of waiting for it


@pytest.mark.slow
def test_full_geometry_at_t0_0_25_in_verify_has_its_window_ramps_and_kick(tmp_path):
    """The background job of the full verify at the paper's bistable case (t0 = 0.25 m, 1.5 bar), about 4 min."""
    from axles.axle import AxleData
    from comparisons.verify.other_axle import full_geometry_at
    from comparisons.verify.plan import BistableCase
    from comparisons.verify.report import CheckStatus
    case = BistableCase(AxleData().with_overrides({"t0": 0.25}), 1.5, math.nan, math.nan, "the paper's figure 9")
    result = full_geometry_at(case, str(tmp_path), True)
    failed = [r for r in result.rows if r.status is CheckStatus.FAIL]
    assert not failed, failed
    what = [r.cells["what"] for r in result.rows]
    assert any(w.startswith("bistable window") for w in what)
    ramps = [r for r in result.rows if "ramp" in r.cells["what"]]
    assert len(ramps) == 2 and all(r.status is CheckStatus.PASS for r in ramps)
    kick = [r for r in result.rows if r.cells["what"].startswith("kick threshold (full geometry)")]
    assert len(kick) == 1 and kick[0].status is CheckStatus.PASS
    assert result.recordings and all("full" in name for name in result.recordings)
    for name in result.recordings + result.figures:
        assert (tmp_path / name).stat().st_size > 0
