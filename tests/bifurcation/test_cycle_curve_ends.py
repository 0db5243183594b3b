"""Curves of cycle folds and torus points end at codimension-two points of straight running that are located by
their own test functions on the Hopf curves, not extrapolated: they must agree with the independent Hopf-curve
continuation (:func:`bifurcation.equilibria.hopf_curves.hopf_diagram`) to 1e-6 in both parameters."""

import numpy as np
import pytest

from axles.units import BAR, KMH, kmh
from bifurcation.cycle_curves.curve import cycle_bifurcation_curve
from bifurcation.cycles.branches import cycle_diagram
from bifurcation.derivatives import ComplexStepDerivatives
from bifurcation.equilibria.hopf_curves import hopf_diagram
from bifurcation.special_points import PointKind, PointStatus
from reduced_model.family import SpeedFamily
from reduced_model.model import Effects, ShimmyModel
from axles.pressures import TyrePressures


def test_figure8_tramp_curves_end_at_the_located_hopf_hopf_and_bautin_points():
    family = SpeedFamily(ShimmyModel(), "t0", pressures=TyrePressures.uniform(1.5 * BAR))
    lo, hi, vmin, vmax = 0.12, 0.26, 100 * KMH, 300 * KMH
    cycles = cycle_diagram(family, 0.25, vmin, vmax)
    hopf = hopf_diagram(family, lo, hi, vmin, vmax)
    (hh,) = hopf.points_of(PointKind.HOPF_HOPF)
    dh2 = max(hopf.points_of(PointKind.GENERALIZED_HOPF), key=lambda p: p.q)
    s2 = min(cycles.points_of(PointKind.CYCLE_FOLD), key=lambda p: p.p)
    t2 = min(cycles.points_of(PointKind.TORUS), key=lambda p: p.p)
    for start, target in ((t2, hh), (s2, dh2)):
        curve = cycle_bifurcation_curve(family, start, lo, hi, vmin, vmax)
        (end,) = [p for p in curve.end_points if p is not None]
        assert end.kind is target.kind and end.status is PointStatus.LOCATED
        assert kmh(end.p) == pytest.approx(kmh(target.p), abs=1e-6)
        assert end.q == pytest.approx(target.q, abs=1e-6 * target.q)
        assert (end.p, end.q) in curve.ends and "located" in " ".join(map(str, curve.messages))


def _crossings(a_speeds, a_values, b_speeds, b_values, q_scale):
    """Intersections of two polylines in (V, q / q_scale)."""
    P = np.column_stack([a_speeds, a_values / q_scale])
    Q = np.column_stack([b_speeds, b_values / q_scale])
    hits = []
    for i in range(len(P) - 1):
        for j in range(len(Q) - 1):
            M = np.column_stack([P[i + 1] - P[i], Q[j] - Q[j + 1]])
            if abs(np.linalg.det(M)) < 1e-300:
                continue
            s, t = np.linalg.solve(M, Q[j] - P[i])
            if 0.0 <= s <= 1.0 and 0.0 <= t <= 1.0:
                hits.append(P[i] + s * (P[i + 1] - P[i]))
    return hits


@pytest.mark.slow
def test_figure18_torus_curves_do_not_meet_again_down_to_0_05_bar():
    """The paper's HH2 (T1 and T2 meeting again below HH1): continued from 0.25 bar down to 0.05 bar, T1 and T2
    both leave the window at 0.05 bar with amplitudes of about 2 deg, never cross, and meet only at HH1."""
    family = SpeedFamily(ShimmyModel(effects=Effects.parse("hcl,pt")), "pressure")
    lo, hi, vmin, vmax = 0.05 * BAR, 0.6 * BAR, 50 * KMH, 400 * KMH
    cycles = cycle_diagram(family, 0.25 * BAR, vmin, vmax)
    t1, t2 = sorted(cycles.points_of(PointKind.TORUS), key=lambda p: -p.p)
    curves = [cycle_bifurcation_curve(family, t, lo, hi, vmin, vmax) for t in (t1, t2)]
    for c in curves:
        assert c.complete and c.qs.min() == pytest.approx(lo, rel=1e-9)
        low = int(np.argmin(c.qs))
        assert np.degrees(c.amplitudes[low][0]) > 1.5
        (end,) = [p for p in c.end_points if p is not None]
        assert end.kind is PointKind.HOPF_HOPF and end.q / BAR == pytest.approx(0.532, abs=5e-4)
    (end0,), (end1,) = ([p for p in c.end_points if p is not None] for c in curves)
    assert end0.p == pytest.approx(end1.p, abs=1e-9) and end0.q == pytest.approx(end1.q, abs=1e-9)
    a, b = curves
    hits = _crossings(kmh(a.ps), a.qs, kmh(b.ps), b.qs, BAR)
    # The only common point is HH1, the shared end.
    assert all(abs(h[1] - 0.532) < 1e-3 for h in hits)


class ComplexStepFamily(ComplexStepDerivatives):
    """What the cycle code needs from a family, for a vector field rhs(X, V, q) analytic in X."""

    n = 2
    nominal = 1.0
    param = "q"
    primary, primary_scale, primary_min = "p", 1.0, 0.0

    @property
    def state_names(self):
        return tuple(f"x{i}" for i in range(self.n))

    def state_scales(self, omega):
        return np.ones(self.n)

    def linear_matrix(self, V, q):
        return self.rhs(1j * 1e-30 * np.eye(self.n), V, q).imag / 1e-30

    def jacobian(self, x, V, q):
        return self.rhs(np.asarray(x, float)[:, None] + 1j * 1e-30 * np.eye(self.n), V, q).imag / 1e-30

    def equilibrium(self, V, q):
        return np.zeros(self.n)

    def validate(self, q):
        pass


class Bautin(ComplexStepFamily):
    """The generalized Hopf normal form r' = r (mu + beta r^2 - r^4), theta' = W with mu = V - SHIFT: cycles fold
    along mu = -beta^2 / 4 at r^2 = beta / 2 (beta > 0), a curve that ends at the Bautin point mu = beta = 0."""

    param = "beta"
    SHIFT, W = 3.0, 2.0

    def rhs(self, X, V, q):
        X = np.asarray(X)
        x, y = X[0], X[1]
        r2 = x * x + y * y
        g = V - self.SHIFT + q * r2 - r2 * r2
        return np.array([g * x - self.W * y, self.W * x + g * y])


def test_fold_curve_of_the_bautin_normal_form_by_the_minimally_augmented_system():
    from bifurcation.cycle_curves.fold import fold_curve
    from bifurcation.cycles.branches import branch_from_hopf
    from bifurcation.equilibria.hopf import find_hopf_points

    family = Bautin()
    (h,) = find_hopf_points(family, 2.0, family.SHIFT - 0.5, family.SHIFT + 0.5)
    (fold,) = branch_from_hopf(family, h, family.SHIFT - 3.0, family.SHIFT + 0.5).points_of(PointKind.CYCLE_FOLD)
    curve = fold_curve(family, fold, -0.5, 3.0, family.SHIFT - 5.0, family.SHIFT + 1.0)
    mu, beta = curve.ps - family.SHIFT, curve.qs
    assert np.max(np.abs(mu + beta ** 2 / 4)) < 1e-10
    assert np.max(np.abs(np.max(curve.amplitudes, axis=1) ** 2 - beta / 2)) < 1e-8
    assert curve.complete and beta.max() == pytest.approx(3.0, abs=1e-9)       # the window's edge
    (end,) = [p for p in curve.end_points if p is not None]
    assert end.kind is PointKind.GENERALIZED_HOPF
    assert end.p == pytest.approx(family.SHIFT, abs=1e-9) and abs(end.q) < 1e-9


FLIP_BETA = 0.8


class BautinWithBlock(Bautin):
    """The Bautin oscillator with a linear block attached whose damping a = beta - 1.5 depends on the second
    parameter: rotating at half the cycle's angle (``flip``), its multipliers are -exp(T (a +- FLIP_BETA r));
    as a plain oscillator at 3.1 rad/s, exp(T (a +- 3.1 i)).  Along the fold curve (r^2 = beta / 2, T = pi) they
    cross -1 where beta - 1.5 +- FLIP_BETA sqrt(beta / 2) = 0 (fold-flip), the unit circle at beta = 1.5
    (fold-Neimark-Sacker)."""

    n = 4

    def __init__(self, flip: bool):
        self.flip = flip

    def rhs(self, X, V, q):
        X = np.asarray(X)
        x, y, u, v = X
        a = q - 1.5
        if self.flip:
            half = 0.5 * self.W
            block = [a * u - half * v + FLIP_BETA * (x * u + y * v), half * u + a * v + FLIP_BETA * (y * u - x * v)]
        else:
            block = [a * u - 3.1 * v, 3.1 * u + a * v]
        return np.concatenate([Bautin.rhs(self, X[:2], V, q), block])


@pytest.mark.parametrize("flip", [True, False])
def test_fold_flip_and_fold_neimark_sacker_points_on_a_fold_curve(flip):
    from scipy.optimize import brentq

    from bifurcation.cycle_curves.fold import fold_curve
    from bifurcation.cycles.branches import branch_from_hopf
    from bifurcation.equilibria.hopf import find_hopf_points

    family = BautinWithBlock(flip)
    (h,) = [h for h in find_hopf_points(family, 1.0, family.SHIFT - 0.5, family.SHIFT + 0.5)
            if abs(h.omega - family.W) < 1e-9]
    branch = branch_from_hopf(family, h, family.SHIFT - 3.0, family.SHIFT + 0.5)
    (fold,) = branch.points_of(PointKind.CYCLE_FOLD)
    curve = fold_curve(family, fold, 0.3, 2.5, family.SHIFT - 5.0, family.SHIFT + 1.0)
    if flip:
        expected = sorted(brentq(lambda b, s=s: b - 1.5 + s * FLIP_BETA * np.sqrt(b / 2), 0.01, 3.0) for s in (1, -1))
        found = curve.points_of(PointKind.FOLD_FLIP)
    else:
        expected = [1.5]
        found = curve.points_of(PointKind.FOLD_NEIMARK_SACKER)
    assert sorted(p.q for p in found) == pytest.approx(expected, abs=1e-9)
    assert all(p.status is PointStatus.LOCATED for p in found)
    assert all(p.p == pytest.approx(family.SHIFT - p.q ** 2 / 4, abs=1e-9) for p in found)
    assert len(curve.special_points) == len(expected)


class CycleWithOscillator(ComplexStepFamily):
    """The supercritical cycle (radius sqrt(mu), frequency W) with an attached oscillator of frequency q and
    damping mu - C: its torus curve is the line V = SHIFT + C for every q (multipliers exp(T (mu - C +- i q)),
    T = 2 pi / W), on which the critical angle T q passes the strong resonances 1:4 at q = W / 4 and 1:3 at W / 3."""

    param = "omega2"
    n = 4
    SHIFT, W, C = 3.0, 2.0, 0.3

    def rhs(self, X, V, q):
        X = np.asarray(X)
        x, y, u, v = X
        mu = V - self.SHIFT
        r2 = x * x + y * y
        a = mu - self.C
        return np.array([mu * x - self.W * y - x * r2, self.W * x + mu * y - y * r2, a * u - q * v, q * u + a * v])


def test_torus_curve_and_strong_resonances_of_a_known_torus_curve():
    from bifurcation.cycles.branches import branch_from_hopf
    from bifurcation.equilibria.hopf import find_hopf_points

    family = CycleWithOscillator()
    (h,) = [h for h in find_hopf_points(family, 0.8, family.SHIFT - 0.2, family.SHIFT + 0.2)
            if abs(h.omega - family.W) < 1e-9]
    (torus,) = branch_from_hopf(family, h, 0.0, family.SHIFT + 1.0).points_of(PointKind.TORUS)
    curve = cycle_bifurcation_curve(family, torus, 0.3, 0.9, 0.0, family.SHIFT + 2.0)
    assert curve.complete and curve.qs.min() == pytest.approx(0.3) and curve.qs.max() == pytest.approx(0.9)
    assert np.max(np.abs(curve.ps - family.SHIFT - family.C)) < 1e-10
    (r3,) = curve.points_of(PointKind.RESONANCE_1_3)
    (r4,) = curve.points_of(PointKind.RESONANCE_1_4)
    assert r3.q == pytest.approx(family.W / 3, abs=1e-9) and r4.q == pytest.approx(family.W / 4, abs=1e-9)
    assert r3.status is PointStatus.LOCATED and r4.status is PointStatus.LOCATED


@pytest.mark.slow
def test_switching_from_the_hopf_hopf_point_gives_the_torus_curves_of_figure_8():
    """From HH alone (no one-parameter branch at t0 = 0.25 m): the two torus curves born there, which are the
    T1 and T2 curves through the torus points of the 0.25 m branches (same exit on the edge t0 = 0.26 m)."""
    from bifurcation.cycle_curves.switching import torus_curves_from_hopf_hopf

    family = SpeedFamily(ShimmyModel(), "t0", pressures=TyrePressures.uniform(1.5 * BAR))
    lo, hi, vmin, vmax = 0.12, 0.26, 100 * KMH, 300 * KMH
    (hh,) = hopf_diagram(family, lo, hi, vmin, vmax).points_of(PointKind.HOPF_HOPF)
    switched = torus_curves_from_hopf_hopf(family, hh, lo, hi, vmin, vmax)
    cycles = cycle_diagram(family, 0.25, vmin, vmax)
    from_branches = [cycle_bifurcation_curve(family, t, lo, hi, vmin, vmax)
                     for t in cycles.points_of(PointKind.TORUS)]
    assert len(switched) == 2

    def exit_speed(curve):
        return curve.ps[int(np.argmax(curve.qs))]

    assert sorted(exit_speed(c) for c in switched) == pytest.approx(sorted(exit_speed(c) for c in from_branches),
                                                                   abs=1e-6 * KMH)
    for c in switched:
        (end,) = [p for p in c.end_points if p is not None]
        assert end.p == pytest.approx(hh.p, abs=1e-9) and end.q == pytest.approx(hh.q, abs=1e-9)


class CuspOfCycles(ComplexStepFamily):
    """r' = r g, g = mu + beta rho - rho^3, rho = r^2 - 1: cycles fold along (mu, beta) = (-2 rho^3, 3 rho^2), a
    curve with a cusp of cycles at mu = beta = 0 (rho = 0, r = 1)."""

    param = "beta"
    SHIFT, W = 3.0, 2.0

    def rhs(self, X, V, q):
        X = np.asarray(X)
        x, y = X[0], X[1]
        rho = x * x + y * y - 1.0
        g = V - self.SHIFT + q * rho - rho ** 3
        return np.array([g * x - self.W * y, self.W * x + g * y])


def test_cusp_of_cycles_on_the_fold_curve():
    from bifurcation.cycle_curves.fold import fold_curve
    from bifurcation.cycles.branches import branch_from_hopf
    from bifurcation.equilibria.hopf import find_hopf_points

    family = CuspOfCycles()
    (h,) = find_hopf_points(family, 0.75, family.SHIFT - 1.0, family.SHIFT + 1.0)
    folds = branch_from_hopf(family, h, family.SHIFT - 1.0, family.SHIFT + 1.0).points_of(PointKind.CYCLE_FOLD)
    curve = fold_curve(family, folds[0], -0.5, 1.5, family.SHIFT - 2.0, family.SHIFT + 2.0)
    rho = np.max(curve.amplitudes, axis=1) ** 2 - 1.0
    assert np.max(np.abs(curve.ps - family.SHIFT + 2 * rho ** 3)) < 1e-8
    assert np.max(np.abs(curve.qs - 3 * rho ** 2)) < 1e-8
    (cusp,) = curve.special_points
    assert cusp.kind is PointKind.CUSP_OF_CYCLES and cusp.status is PointStatus.LOCATED
    assert abs(cusp.p - family.SHIFT) < 1e-9 and abs(cusp.q) < 1e-9
    # Through the cusp the curve reaches the other fold's side: both ends on the edge beta = 1.5.
    assert all("left the window" in str(m) for m in curve.messages)


@pytest.mark.slow
def test_codimension_two_points_of_cycles_in_figure_8():
    """Located along figure 8's curves, and each confirmed on the one-parameter branch at its t0 (README)."""
    family = SpeedFamily(ShimmyModel(), "t0", pressures=TyrePressures.uniform(1.5 * BAR))
    lo, hi, vmin, vmax = 0.12, 0.26, 100 * KMH, 300 * KMH
    cycles = cycle_diagram(family, 0.25, vmin, vmax)
    found = {}
    for start in cycles.special_points:
        for p in cycle_bifurcation_curve(family, start, lo, hi, vmin, vmax).special_points:
            found[p.kind] = p
    expected = {PointKind.FOLD_NEIMARK_SACKER: (155.4292, 0.160037), PointKind.RESONANCE_1_3: (160.4234, 0.174372),
                PointKind.RESONANCE_1_4: (147.7994, 0.142204), PointKind.CHENCINER: (160.0095, 0.173143)}
    assert set(found) == set(expected)
    for kind, (V, t0) in expected.items():
        assert kmh(found[kind].p) == pytest.approx(V, abs=1e-3) and found[kind].q == pytest.approx(t0, abs=1e-5)
        on_branch = cycle_diagram(family, found[kind].q, vmin, vmax)
        base = PointKind.CYCLE_FOLD if kind is PointKind.FOLD_NEIMARK_SACKER else PointKind.TORUS
        p = min(on_branch.points_of(base), key=lambda p: abs(p.p - found[kind].p))
        assert p.p == pytest.approx(found[kind].p, abs=1e-6)
        mu = p.data["multipliers"]
        pair = mu[np.abs(mu.imag) > 1e-3]
        angle = {PointKind.RESONANCE_1_3: 2 * np.pi / 3, PointKind.RESONANCE_1_4: np.pi / 2}.get(kind)
        if angle is None:    # fold-Neimark-Sacker, Chenciner: a complex pair on the unit circle
            assert np.min(np.abs(np.abs(pair) - 1.0)) < 1e-6
        else:
            assert np.min(np.abs(np.abs(np.angle(pair)) - angle)) < 1e-6


def test_a_curve_ends_where_its_amplitude_model_puts_zero_within_four_steps():
    """amp^2 affine along the curve near a smooth generalized Hopf point, amp itself where f has a kink at the
    equilibrium (tried second, on a piecewise smooth family); a zero further than four steps ahead is no end yet."""
    from bifurcation.cycle_curves.bordered import END_STEPS, end_steps
    assert END_STEPS == 4.0
    assert end_steps(1.0, 0.9, False, False) == []                          # amp^2's zero 5.3 steps on
    assert end_steps(1.0, 0.8, False, False) == pytest.approx([1.0 / (1.0 - 0.64)])
    # the kink's fold of figure 18 before its end: amp^2's zero 3.6 steps on, amp's 6.6
    assert end_steps(4.15, 3.52, False, True) == pytest.approx([1.0 / (1.0 - (3.52 / 4.15) ** 2)])
    assert end_steps(1.0, 0.5, False, True) == pytest.approx([1.0 / (1.0 - 0.25), 2.0])
    # through zero (the collocation's orbits shifted by half a period): each model's zero at once
    assert end_steps(1.0, 0.5, True, True) == pytest.approx([1.0 / 1.25, 1.0 / 1.5])
