"""Branch switching at a period-doubling point, on a vector field whose doubled cycles are known exactly.

The supercritical normal-form cycle (radius r = sqrt(mu), frequency W) carries a block that rotates at half the
cycle's angle with a cubic saturation: in the frame turning with theta / 2 it reads w' = diag(a + BETA r,
a - BETA r) w - |w|^2 w, a = mu - C.  Where a + BETA r > 0 the cycle has a multiplier below -1 and the doubled
cycles have |w| = sqrt(a + BETA r) (constant in the turning frame, so period 2 T in the original one).
"""

import numpy as np
import pytest
import test_cycles_toy as toy
from test_cycle_curve_ends import ComplexStepFamily

from bifurcation.cycles.branches import branch_from_hopf
from bifurcation.cycles.period_doubling import branch_from_period_doubling
from bifurcation.special_points import BranchStatus, PointKind, PointStatus


def saturated_flip(X, V):
    x, y, u, v = X
    a = V - toy.SHIFT - toy.C_TORUS
    half = 0.5 * toy.W
    s = u * u + v * v
    return np.concatenate([toy.supercritical(X[:2], V),
                           [a * u - half * v + toy.BETA * (x * u + y * v) - s * u,
                            half * u + a * v + toy.BETA * (y * u - x * v) - s * v]])


def test_doubled_branch_has_the_known_amplitude_and_twice_the_period():
    family = toy.ToyFamily(saturated_flip, 4)
    h = toy.first_hopf(family)
    branch = branch_from_hopf(family, h, 0.0, toy.SHIFT + 2.0)
    pd = min(branch.points_of(PointKind.PERIOD_DOUBLING), key=lambda p: p.p)
    assert pd.status is PointStatus.LOCATED
    mu_pd = pd.p - toy.SHIFT          # a + BETA sqrt(mu) = 0
    assert mu_pd - toy.C_TORUS + toy.BETA * np.sqrt(mu_pd) == pytest.approx(0.0, abs=1e-9)
    doubled = branch_from_period_doubling(family, pd, 0.0, toy.SHIFT + 2.0)
    assert doubled.status is BranchStatus.COMPLETE and len(doubled.points) > 5
    for p in doubled.points:
        mu = p.p - toy.SHIFT
        assert p.period == pytest.approx(2 * 2 * np.pi / toy.W, rel=1e-9)
        assert p.amplitude[2] == pytest.approx(np.sqrt(mu - toy.C_TORUS + toy.BETA * np.sqrt(mu)), rel=1e-7)
        assert p.amplitude[0] == pytest.approx(np.sqrt(mu), rel=1e-7)
        assert p.stable and p.meets_tolerance


class FlipInTwoParameters(ComplexStepFamily):
    """The supercritical cycle with the half-rotating block damped by a = mu - q: period doubling where
    mu - q + BETA sqrt(mu) = 0, i.e. along the curve q = mu + BETA sqrt(mu)."""

    param = "c"
    n = 4

    def rhs(self, X, V, q):
        X = np.asarray(X)
        x, y, u, v = X
        mu = V - toy.SHIFT
        r2 = x * x + y * y
        a = mu - q
        half = 0.5 * toy.W
        return np.array([mu * x - toy.W * y - x * r2, toy.W * x + mu * y - y * r2,
                         a * u - half * v + toy.BETA * (x * u + y * v), half * u + a * v + toy.BETA * (y * u - x * v)])


def test_period_doubling_curve_by_the_minimally_augmented_system():
    from bifurcation.cycle_curves.curve import cycle_bifurcation_curve
    from bifurcation.equilibria.hopf import find_hopf_points

    family = FlipInTwoParameters()
    (h,) = [h for h in find_hopf_points(family, 0.3, toy.SHIFT - 0.2, toy.SHIFT + 0.2) if abs(h.omega - toy.W) < 1e-9]
    pd = min(branch_from_hopf(family, h, 0.0, toy.SHIFT + 2.0).points_of(PointKind.PERIOD_DOUBLING),
             key=lambda p: p.p)
    curve = cycle_bifurcation_curve(family, pd, 0.1, 1.0, toy.SHIFT + 1e-3, toy.SHIFT + 3.0)
    mu = curve.ps - toy.SHIFT
    assert curve.kind is PointKind.PERIOD_DOUBLING and curve.complete
    assert np.max(np.abs(curve.qs - mu - toy.BETA * np.sqrt(mu))) < 1e-9
    assert curve.qs.min() == pytest.approx(0.1) and curve.qs.max() == pytest.approx(1.0)
