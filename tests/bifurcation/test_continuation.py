"""The continuation algorithm on curves known in closed form: steps over a narrow gap only where asked, and never
over a genuine corner."""

import numpy as np
import pytest

from bifurcation.continuation import ContinuationSettings, Stop, continue_curve
from bifurcation.special_points import BranchStatus

SETTINGS = ContinuationSettings(ds=0.05, ds_min=1e-6, ds_max=0.1)


def line_with_gap(width: float):
    """z = p, with no solution the corrector can use for p in (0, width): the residual is NaN there (as a
    discretised curve's steep piece where a node crosses a kink, seen from the continuation).  The steps reach
    ds_max = 0.1 (0.071 in p) before the gap: 0.06 is too wide for a regular step from where they stand."""
    def G(u):
        p, z = u
        r = np.array([z - p]) if not 0.0 < p < width else np.array([np.nan])
        return r, np.array([[-1.0, 1.0]])
    return G


def bend(slope: float, delta: float = 1e-9):
    """z = p for p < 0 and z = (1 + slope) p beyond, the corner smoothed over delta: a curve that turns."""
    def G(u):
        p, z = u
        s = 0.5 * (1.0 + np.tanh(np.clip(p / delta, -50, 50)))
        ds_ = 0.5 / delta / np.cosh(np.clip(p / delta, -50, 50)) ** 2
        return np.array([z - p - slope * p * s]), np.array([[-1.0 - slope * (s + p * ds_), 1.0]])
    return G


def run(G, corner_steps: int):
    settings = ContinuationSettings(**{**SETTINGS.__dict__, "corner_steps": corner_steps})
    return continue_curve(G, np.array([-0.5, -0.5]), np.array([1.0, 1.0]), np.ones(2), settings,
                          accept=lambda b: Stop(BranchStatus.COMPLETE) if b.points[-1][0] > 0.5 else None)


def test_a_narrow_gap_stops_the_curve_without_corner_steps():
    branch = run(line_with_gap(0.06), corner_steps=0)
    assert branch.status is BranchStatus.STEP_UNDERFLOW
    assert branch.points[-1][0] < 0.0 and branch.corners == []


def test_corner_steps_cross_a_narrow_gap_and_record_where():
    branch = run(line_with_gap(0.06), corner_steps=2)
    assert branch.status is BranchStatus.COMPLETE
    assert len(branch.corners) == 1
    k = branch.corners[0]
    before, after = branch.points[k - 1], branch.points[k]
    assert before[0] <= 0.0 and after[0] >= 0.06          # the step spans the gap
    for u in branch.points:                                 # and every point is on the curve
        assert u[1] == pytest.approx(u[0], abs=1e-12)


def test_a_gap_wider_than_the_longest_step_is_not_crossed():
    branch = run(line_with_gap(0.12), corner_steps=2)
    assert branch.status is BranchStatus.STEP_UNDERFLOW
    assert branch.corners == []


@pytest.mark.parametrize("corner_steps", [0, 2])
def test_a_genuine_corner_is_never_stepped_over(corner_steps):
    """The curve turns by 56 degrees at p = 0, more than max_turn: it ends there either way."""
    branch = run(bend(2.0), corner_steps)
    assert branch.status is BranchStatus.STEP_UNDERFLOW
    assert branch.corners == []
    assert abs(branch.points[-1][0]) < 1e-3


def test_a_gentle_bend_is_followed_without_corner_steps():
    branch = run(bend(0.2), corner_steps=2)
    assert branch.status is BranchStatus.COMPLETE and branch.corners == []


def noisy_line(noise: float, condition: float, seed: int = 0):
    """z = p seen through a residual with rounding noise of size ``noise`` and a Jacobian whose z column is
    ``condition`` small: Newton's steps near the solution are the noise's image, noise / condition, and never fall
    below it (a cycle fold made by a kink: weighted steps of 1e-7 at a collocation residual of 3e-12)."""
    rng = np.random.default_rng(seed)

    def G(u):
        p, z = u
        return np.array([condition * (z - p) + noise * rng.standard_normal()]), np.array([[-condition, condition]])
    return G


@pytest.mark.parametrize("floor_tol, complete", [(0.0, False), (1e-6, True)])
def test_newton_at_its_residuals_rounding_floor_is_accepted_only_below_the_floor_tolerance(floor_tol, complete):
    settings = ContinuationSettings(**{**SETTINGS.__dict__, "newton_tol": 1e-8, "floor_tol": floor_tol})
    branch = continue_curve(noisy_line(3e-12, 1e-5), np.array([-0.5, -0.5]), np.array([1.0, 1.0]), np.ones(2),
                            settings, accept=lambda b: Stop(BranchStatus.COMPLETE) if b.points[-1][0] > 0.5 else None)
    assert (branch.status is BranchStatus.COMPLETE) is complete
    if complete:   # every accepted point within the floor's image of the curve
        assert all(abs(u[1] - u[0]) < 1e-6 for u in branch.points)
    else:
        assert branch.status is BranchStatus.STEP_UNDERFLOW


def test_a_step_far_above_the_floor_is_not_accepted_by_it():
    """Noise whose image (1e-4) is above the floor tolerance: no point is accepted at all."""
    settings = ContinuationSettings(**{**SETTINGS.__dict__, "newton_tol": 1e-8, "floor_tol": 1e-6})
    branch = continue_curve(noisy_line(1e-9, 1e-5), np.array([-0.5, -0.5]), np.array([1.0, 1.0]), np.ones(2),
                            settings, accept=lambda b: Stop(BranchStatus.COMPLETE) if b.points[-1][0] > 0.5 else None)
    assert branch.status is BranchStatus.STEP_UNDERFLOW and len(branch.points) == 1
