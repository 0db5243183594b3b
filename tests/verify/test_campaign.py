"""``tools/verify_campaign.py``: ``verify --quick`` on random axles drawn as a new user makes them (issue 29), whose
exit code must be 0 wherever the two equal models agree: CI runs one seeded axle with t0 in 0.12-0.3 m (where
bistable windows, torus points and narrow stable windows appear), the slow suite two more and 40 more (20 of them
with t0 drawn)."""

import numpy as np
import pytest


def test_the_draws_stay_in_their_ranges_and_repeat_with_the_seed(campaign_tool):
    from axles.axle import entries, paper_axle
    tool = campaign_tool
    paper = paper_axle()
    a = tool.draw_axle(np.random.default_rng(7), "A", t0=True)
    b = tool.draw_axle(np.random.default_rng(7), "A", t0=True)
    assert (a.params, a.dims) == (b.params, b.dims)
    for name in tool.VEHICLE:
        ratio = a.value(name) / paper.value(name) if paper.value(name) else 1.0
        assert 1 - tool.SCALE <= ratio <= 1 + tool.SCALE, name
    for name, e in entries().items():
        if e.section == "multibody":
            lo, hi = paper.plausible_range(name)
            assert lo <= a.value(name) <= hi, name
        elif name not in tool.VEHICLE and name != "t0":
            assert a.value(name) == paper.value(name), name
    assert tool.T0_M[0] <= a.params.t0 <= tool.T0_M[1]
    plain = tool.draw_axle(np.random.default_rng(7), "A", t0=False)
    assert plain.params.t0 == paper.params.t0 and plain.dims == a.dims     # t0 drawn or not, the rest the same
    # each axle its own stream: axle 3 of a campaign does not depend on the others
    assert tool.campaign_axle(29, 3, True).params == tool.campaign_axle(29, 3, True).params
    assert tool.campaign_axle(29, 3, True).name == "CAMPAIGN-29-03"
    # axle 2 of seed 29 first drew a diametral inertia below half its I2 (verify refused it, exit 2): drawn again
    tool.exists(tool.campaign_axle(29, 2, True))
    # axle 1 of seed 31 first drew wheels and knuckles with more roll inertia than its I3
    tool.exists(tool.campaign_axle(31, 1, True))


def test_a_seeded_axle_verifies_without_a_false_fail(tmp_path, campaign_tool):
    """Axle 3 of campaign 29 (t0 0.136 m: bistable windows, torus points and narrow stable windows), the cheapest
    of its eight, 2-3 minutes under a load of 8 on 2 cores (`tools/verify_campaign.py --axles 8 --t0-axles 4 --seed
    29`; the paper's own bistable window runs in tests/verify/test_verify.py).  Axles 2 (t0 0.196 m) and 7 (the
    paper's t0) run in the slow suite below, to keep CI within its 10 minutes."""
    tool = campaign_tool
    outcomes = tool.run_campaign(8, 4, seed=29, out=str(tmp_path), say=lambda line: None, numbers=(3,))
    assert [o.name for o in outcomes] == ["CAMPAIGN-29-03"]
    assert all(o.exit_code == 0 and not o.fails for o in outcomes), "\n" + tool.table(outcomes)


@pytest.mark.slow
def test_two_more_seeded_axles_verify_without_a_false_fail(tmp_path, campaign_tool):
    tool = campaign_tool
    outcomes = tool.run_campaign(8, 4, seed=29, out=str(tmp_path), say=lambda line: None, numbers=(2, 7))
    assert [o.name for o in outcomes] == ["CAMPAIGN-29-02", "CAMPAIGN-29-07"]
    assert all(o.exit_code == 0 and not o.fails for o in outcomes), "\n" + tool.table(outcomes)


@pytest.mark.slow
def test_forty_axles_verify_without_a_false_fail(tmp_path, campaign_tool):
    tool = campaign_tool
    outcomes = tool.run_campaign(40, 20, seed=2029, out=str(tmp_path), jobs=2, say=lambda line: None)
    assert all(o.exit_code == 0 and not o.fails for o in outcomes), "\n" + tool.table(outcomes)
