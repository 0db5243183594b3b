"""Periodic-orbit continuation on vector fields whose cycles, multipliers and bifurcations are known exactly.

Normal-form oscillators in polar form r' = r g(r^2, mu), theta' = w with mu = V - SHIFT (Hopf points of straight
running are only looked for above 0.5 km/h): cycles r^2 = root of g, period 2 pi / w, non-trivial radial
multiplier exp(T * 2 r^2 dg/d(r^2)).  Extra linear blocks attached to the cycle give a Neimark-Sacker (torus) point
and a period-doubling point at known speeds.
"""

import numpy as np
import pytest

from bifurcation.continuation import ContinuationSettings
from bifurcation.cycles import collocation as col
from bifurcation.cycles.branches import branch_from_hopf
from bifurcation.cycles.multipliers import classify_multipliers
from bifurcation.cycles.problem import CycleSettings
from bifurcation.derivatives import ComplexStepDerivatives
from bifurcation.equilibria.hopf import find_hopf_points
from bifurcation.special_points import BranchStatus, PointKind, PointStatus

SHIFT = 3.0      # m/s, speed of the Hopf point
W = 2.0          # rad/s, cycle frequency
C_TORUS = 0.3    # speed at which the attached oscillator destabilises
W2 = 3.1         # rad/s, attached oscillator (incommensurate with W)


class ToyFamily(ComplexStepDerivatives):
    """Just what the cycle code needs from a family: rhs(X, V, q) on (n, m) arrays, complex allowed."""

    param = "pressure"
    primary, primary_scale, primary_min = "p", 1.0, 0.0

    def __init__(self, field, n):
        self.field, self.n = field, n
        self.state_names = tuple(f"x{i}" for i in range(n))
        self.nominal = 1.0

    def state_scales(self, omega):
        return np.ones(self.n)

    def rhs(self, X, V, q):
        return self.field(np.asarray(X), V)

    def linear_matrix(self, V, q):
        h = 1e-30
        X = 1j * h * np.eye(self.n)
        return self.field(X, V).imag / h

    def jacobian(self, x, V, q):
        X = np.asarray(x, dtype=float)[:, None] + 1j * 1e-30 * np.eye(self.n)
        return self.field(X, V).imag / 1e-30

    def equilibrium(self, V, q):
        return np.zeros(self.n)

    def validate(self, q):
        pass


def supercritical(X, V):
    x, y = X[0], X[1]
    r2 = x * x + y * y
    mu = V - SHIFT
    return np.array([mu * x - W * y - x * r2, W * x + mu * y - y * r2])


def subcritical(X, V):
    """g = mu + 2 r^2 - r^4: subcritical Hopf at mu = 0, fold of cycles at mu = -1 (r = 1)."""
    x, y = X[0], X[1]
    r2 = x * x + y * y
    g = V - SHIFT + 2.0 * r2 - r2 * r2
    return np.array([g * x - W * y, W * x + g * y])


def with_oscillator(X, V):
    """The supercritical cycle times a linear oscillator whose damping mu - C_TORUS changes sign."""
    u, v = X[2], X[3]
    a = V - SHIFT - C_TORUS
    return np.concatenate([supercritical(X[:2], V), [a * u - W2 * v, W2 * u + a * v]])


BETA = 0.8


def with_flip(X, V):
    """A block rotating at half the cycle's angle: multipliers -exp(T (mu - C_TORUS +- BETA r)).

    In the frame turning with theta / 2 the block is diagonal, diag(a + BETA r, a - BETA r); over one period the
    frame turns by pi, so both multipliers are negative: period doubling where mu - C_TORUS + BETA sqrt(mu) = 0.
    """
    x, y, u, v = X
    a = V - SHIFT - C_TORUS
    half = 0.5 * W
    return np.concatenate([supercritical(X[:2], V),
                           [a * u - half * v + BETA * (x * u + y * v), half * u + a * v + BETA * (y * u - x * v)]])


def first_hopf(family, vmin=SHIFT - 0.2, vmax=SHIFT + 0.2):
    (h,) = [h for h in find_hopf_points(family, 0.0, vmin, vmax) if abs(h.p - SHIFT) < 1e-9]
    return h


def test_collocation_scheme():
    s = col.scheme(4)
    assert s.weights.sum() == pytest.approx(1.0)
    assert np.allclose(s.L.sum(axis=1), 1.0) and np.allclose(s.D.sum(axis=1), 0.0, atol=1e-12)
    # Gauss quadrature of degree 2m - 1 is exact.
    assert np.sum(s.weights * s.points ** 7) == pytest.approx(1 / 8, rel=1e-14)


def test_supercritical_branch_radius_period_and_multipliers():
    fam = ToyFamily(supercritical, 2)
    h = first_hopf(fam)
    assert h.first_lyapunov == pytest.approx(-2.0 / W, rel=1e-9)  # l1 = 2a/w with a = -1
    b = branch_from_hopf(fam, h, SHIFT - 1.0, SHIFT + 1.0)
    assert b.status is BranchStatus.COMPLETE and "left the window" in str(b.message)
    assert b.points[-1].p == pytest.approx(SHIFT + 1.0, abs=1e-12)
    for p in b.points:
        mu = p.p - SHIFT
        assert p.amplitude[0] == pytest.approx(np.sqrt(mu), rel=1e-8)
        assert p.period == pytest.approx(2 * np.pi / W, rel=1e-10)
        rest, trivial = classify_multipliers(p.multipliers)
        assert abs(trivial - 1.0) < 1e-9
        assert rest[0].real == pytest.approx(np.exp(-2 * mu * p.period), rel=1e-7)
        assert p.stable
    assert not b.special_points


def test_subcritical_branch_turns_at_the_fold_and_changes_stability():
    fam = ToyFamily(subcritical, 2)
    h = first_hopf(fam)
    assert h.first_lyapunov > 0
    b = branch_from_hopf(fam, h, SHIFT - 2.0, SHIFT + 1.0)
    assert b.complete
    (fold,) = b.points_of(PointKind.CYCLE_FOLD)
    assert fold.status is PointStatus.LOCATED
    assert fold.p - SHIFT == pytest.approx(-1.0, abs=1e-9)
    assert fold.data["amplitude"][0] == pytest.approx(1.0, abs=1e-5)
    for p in b.points:
        r2 = p.amplitude[0] ** 2
        assert p.p - SHIFT == pytest.approx(r2 * r2 - 2 * r2, abs=1e-7)
        if abs(r2 - 1.0) > 1e-3:
            assert p.stable == (r2 > 1.0)
    # It went down to the fold and back up to the window's top.
    assert min(p.p for p in b.points) - SHIFT == pytest.approx(-1.0, abs=0.05)
    assert b.points[-1].p == pytest.approx(SHIFT + 1.0)


def test_torus_point_of_an_attached_oscillator():
    fam = ToyFamily(with_oscillator, 4)
    b = branch_from_hopf(fam, first_hopf(fam), SHIFT - 1.0, SHIFT + 1.0)
    (torus,) = b.points_of(PointKind.TORUS)
    assert torus.status is PointStatus.LOCATED
    assert torus.p - SHIFT == pytest.approx(C_TORUS, abs=1e-8)
    mu = classify_multipliers(torus.data["multipliers"])[0]
    pair = mu[np.abs(mu.imag) > 1e-6]
    assert np.allclose(np.abs(pair), 1.0, atol=1e-7)
    assert np.cos(np.angle(pair[0])) == pytest.approx(np.cos(W2 * 2 * np.pi / W), abs=1e-7)
    assert all(p.stable == (p.p - SHIFT < C_TORUS) for p in b.points if abs(p.p - SHIFT - C_TORUS) > 1e-3)
    assert not b.points_of(PointKind.PERIOD_DOUBLING) and not b.points_of(PointKind.CYCLE_FOLD)


def test_period_doubling_point():
    fam = ToyFamily(with_flip, 4)
    b = branch_from_hopf(fam, first_hopf(fam), SHIFT - 1.0, SHIFT + 1.0)
    (pd,) = b.points_of(PointKind.PERIOD_DOUBLING)
    assert pd.status is PointStatus.LOCATED
    # mu - C + BETA sqrt(mu) = 0 with sqrt(mu) = s: s^2 + BETA s - C = 0.
    s = (-BETA + np.sqrt(BETA ** 2 + 4 * C_TORUS)) / 2
    assert pd.p - SHIFT == pytest.approx(s * s, abs=1e-8)
    mu = classify_multipliers(pd.data["multipliers"])[0]
    assert np.min(np.abs(mu + 1.0)) < 1e-7


def test_branch_failures_say_where_they_stopped():
    fam = ToyFamily(supercritical, 2)
    h = first_hopf(fam)
    few = CycleSettings(continuation=ContinuationSettings(ds=0.02, ds_max=0.1, max_steps=3))
    b = branch_from_hopf(fam, h, SHIFT - 1.0, SHIFT + 1.0, settings=few)
    assert b.status is BranchStatus.MAX_STEPS and not b.complete
    assert len(b.points) == 4 and "last cycle at" in str(b.message)
    stiff = CycleSettings(continuation=ContinuationSettings(ds=0.02, ds_min=1e-3, max_turn=1e-9))
    b = branch_from_hopf(fam, h, SHIFT - 1.0, SHIFT + 1.0, settings=stiff)
    assert b.status is BranchStatus.STEP_UNDERFLOW and "last cycle at" in str(b.message)
    hopeless = CycleSettings(continuation=ContinuationSettings(newton_max_iter=1, newton_tol=1e-300))
    b = branch_from_hopf(fam, h, SHIFT - 1.0, SHIFT + 1.0, settings=hopeless)
    assert b.status is BranchStatus.NEWTON_FAILED and b.points == () and "branch switching" in str(b.message)


def test_torus_and_fold_between_the_hopf_start_and_the_first_cycle():
    """Issue 17: bifurcations closer to the Hopf point than the first computed cycle are found and located there.
    The attached oscillator of damping mu - C with C = 1e-5 gives the torus point at V = SHIFT + C (the first
    cycle lies at mu = 4e-4); the Bautin normal form at beta = 2e-4 folds at mu = -beta^2 / 4 = -1e-8, r^2 = 1e-4,
    inside the first cycle's r^2 = 4e-4."""
    from test_cycle_curve_ends import Bautin, CycleWithOscillator

    class CloseTorus(CycleWithOscillator):
        C = 1e-5

    for family, q, kind, expected in ((CloseTorus(), 0.8, PointKind.TORUS, CloseTorus.SHIFT + 1e-5),
                                      (Bautin(), 2e-4, PointKind.CYCLE_FOLD, Bautin.SHIFT - 1e-8)):
        (h,) = [h for h in find_hopf_points(family, q, family.SHIFT - 0.2, family.SHIFT + 0.2)
                if abs(h.omega - family.W) < 1e-9]
        branch = branch_from_hopf(family, h, family.SHIFT - 1.0, family.SHIFT + 1.0)
        first = branch.points[0].p
        assert abs(first - family.SHIFT) > 5 * abs(expected - family.SHIFT)     # the point is short of it
        (point,) = branch.points_of(kind)
        assert point.status is PointStatus.LOCATED and point.data["end_segment"]
        assert point.p == pytest.approx(expected, abs=1e-12)
        assert point.bracket[1] <= 0.0          # before the first cycle on the branch's arclength


class CountingToy(ToyFamily):
    """A toy family that counts how often its Jacobians are formed."""

    def __init__(self, field, n):
        super().__init__(field, n)
        self.jacobian_batches = 0

    def rhs_and_jacobians(self, P, p, q, kink_rows=True):
        self.jacobian_batches += 1
        return super().rhs_and_jacobians(P, p, q, kink_rows)


class CostlyToy(CountingToy):
    """The same field, flagged as having costly Jacobians (as a family of difference derivatives is): the
    continuation then corrects by chord iterations with the last point's Jacobian."""

    costly_jacobian = True


@pytest.mark.parametrize("field, n, kind, at", [(subcritical, 2, PointKind.CYCLE_FOLD, -1.0),
                                               (with_oscillator, 4, PointKind.TORUS, C_TORUS)])
def test_chord_iterations_find_the_known_points_with_fewer_jacobians(field, n, kind, at):
    newton, chord = CountingToy(field, n), CostlyToy(field, n)
    branches = [branch_from_hopf(f, first_hopf(f), SHIFT - 2.0, SHIFT + 1.0) for f in (newton, chord)]
    for b in branches:
        assert b.complete
        (point,) = b.points_of(kind)
        assert point.status is PointStatus.LOCATED and point.p - SHIFT == pytest.approx(at, abs=1e-8)
    # Every cycle of the chord branch is a solution of the same discretisation to Newton's tolerance.
    if field is subcritical:
        for p in branches[1].points:
            r2 = p.amplitude[0] ** 2
            assert p.p - SHIFT == pytest.approx(r2 * r2 - 2 * r2, abs=1e-7)
    per_cycle = [f.jacobian_batches / len(b.points) for f, b in zip((newton, chord), branches)]
    assert per_cycle[1] < 0.7 * per_cycle[0]


def test_a_corrector_failure_at_the_window_boundary_ends_the_branch_and_says_so(monkeypatch):
    """When the corrector fails while the crossing of the window's edge is located, the branch ends on the
    accepted cycle just beyond the edge, with a message that says so; it never raises."""
    from bifurcation import continuation

    fam = ToyFamily(supercritical, 2)
    h = first_hopf(fam)

    def failing(self, k, s):
        raise RuntimeError(f"corrector failed at s = {s:.3g} after point {k}")

    monkeypatch.setattr(continuation.Branch, "point_at", failing)
    b = branch_from_hopf(fam, h, SHIFT - 1.0, SHIFT + 1.0)
    assert b.status is BranchStatus.COMPLETE and "crossing itself was not located" in str(b.message)
    assert b.points[-1].p > SHIFT + 1.0 and b.points[-2].p < SHIFT + 1.0
    for p in b.points:
        assert p.amplitude[0] == pytest.approx(np.sqrt(p.p - SHIFT), rel=1e-8)


def test_a_trivial_multiplier_split_into_a_pair_is_no_torus():
    """Beside a Hopf point the trivial multiplier and the one born there are both near +1; the discretisation can
    split them into 1 +- i eps (measured on the full geometry's subcritical onset at t0 = 0.25 m, where it was
    reported as two torus points 0.001 km/h from the Hopf point).  Both are real: no complex multiplier is left
    to cross the unit circle, and a genuine pair elsewhere is kept."""
    from bifurcation.cycles.multipliers import complex_outside, torus_test
    pair = np.array([-0.888 + 0.13j, -0.888 - 0.13j])
    for split in (np.array([1.0 + 3e-6j, 1.0 - 3e-6j]), np.array([1.000011 + 2e-6j, 1.000011 - 2e-6j])):
        rest, trivial = classify_multipliers(np.concatenate([split, pair]))
        assert trivial in split
        assert complex_outside(rest) == 0
        assert np.isclose(torus_test(rest), np.abs(pair[0]) - 1.0)      # the test reads the genuine pair
        assert sorted(rest.imag) == pytest.approx([-0.13, 0.0, 0.13])
    # A genuine pair near the unit circle away from +1 stays complex.
    rest, trivial = classify_multipliers(np.array([1.0 + 0j, 0.6 + 0.81j, 0.6 - 0.81j]))
    assert trivial == 1.0 and complex_outside(rest) == 2 and np.all(rest.imag != 0.0)


def test_cycle_at_reaches_a_far_speed_in_steps_where_one_newton_step_fails():
    """From the cycle of radius 0.18 to the one at mu = 1 (radius 1, known): one Newton solve does not get there,
    eight equal steps of the speed do, onto the exact cycle."""
    from bifurcation.cycles.branches import cycle_at
    from bifurcation.special_points import ConvergenceError
    fam = ToyFamily(supercritical, 2)
    b = branch_from_hopf(fam, first_hopf(fam), SHIFT - 1.0, SHIFT + 3.0)
    near = min(b.points, key=lambda p: abs(p.p - SHIFT - 0.05))
    with pytest.raises(ConvergenceError):
        cycle_at(fam, near, SHIFT + 1.0, halvings=0)
    far = cycle_at(fam, near, SHIFT + 1.0)
    assert far.p == pytest.approx(SHIFT + 1.0, abs=1e-12)
    assert far.amplitude[0] == pytest.approx(1.0, rel=1e-8) and far.period == pytest.approx(2 * np.pi / W, rel=1e-9)
