"""Codimension-two points of cycles along torus and period-doubling curves, on constructed systems whose points
are known in closed form: the 1:1 and 1:2 strong resonances where a torus curve turns into a curve of neutral
saddle cycles (Kuznetsov 2004, sections 9.5 and 10.3), and fold-flip points on period-doubling curves."""

import numpy as np
import pytest
from test_cycle_curve_ends import FLIP_BETA, BautinWithBlock, CycleWithOscillator

from bifurcation.cycle_curves.curve import cycle_bifurcation_curve
from bifurcation.cycles.branches import branch_from_hopf
from bifurcation.equilibria.hopf import find_hopf_points
from bifurcation.special_points import PointKind, PointStatus
from axles.pressures import TyrePressures


def located(family, q, kind, lo, hi, near=None):
    """The point of ``kind`` on the branch of ``family``'s cycle (frequency W) at q, near speed ``near``."""
    (h,) = [h for h in find_hopf_points(family, q, family.SHIFT - 0.5, family.SHIFT + 0.5)
            if abs(h.omega - family.W) < 1e-9]
    points = branch_from_hopf(family, h, lo, hi).points_of(kind)
    if near is not None:
        points = [p for p in points if abs(p.p - near) < 1e-6]
    (point,) = points
    return point


class CycleWithBlock(CycleWithOscillator):
    """The supercritical cycle x' = mu x - W y - x r^2 (radius sqrt(mu), frequency W, mu = V - SHIFT, period
    T = 2 pi / W) with an attached linear block of damping a = mu - C, so that the torus (Neimark-Sacker) curve
    is the line V = SHIFT + C, r^2 = C, for every q.

    ``resonance`` 1: the block [[a, 1], [-q, a]], multipliers exp(T (a +- sqrt(-q))): on the curve kappa =
    cos(T sqrt(q)) for q > 0, cosh(T sqrt(-q)) for q < 0, through 1 (a Jordan pair at +1) at q = 0.
    ``resonance`` 2: the block rotating at W / 2 + q with a reflection coupling BETA r S(W t) to the cycle; in the
    frame turning with half the cycle's angle it is [[a + BETA r, -q], [q, a - BETA r]], so the multipliers are
    -exp(T (a +- sqrt(BETA^2 r^2 - q^2))): kappa = -cos(T sqrt(q^2 - BETA^2 C)), through -1 at q = BETA sqrt(C)."""

    param = "q"
    BETA = 0.8

    def __init__(self, resonance: int):
        self.resonance = resonance

    def rhs(self, X, V, q):
        X = np.asarray(X)
        x, y, u, v = X
        a = V - self.SHIFT - self.C
        if self.resonance == 1:
            block = [a * u + v, -q * u + a * v]
        else:
            turn = 0.5 * self.W + q
            block = [a * u - turn * v + self.BETA * (x * u + y * v), turn * u + a * v + self.BETA * (y * u - x * v)]
        return np.array([*CycleWithOscillator.rhs(self, X, V, q)[:2], *block])

    def kappa(self, q):
        T = 2 * np.pi / self.W
        if self.resonance == 1:
            return np.where(q > 0, np.cos(T * np.sqrt(np.abs(q))), np.cosh(T * np.sqrt(np.abs(q))))
        d = q * q - self.BETA ** 2 * self.C
        return -np.where(d > 0, np.cos(T * np.sqrt(np.abs(d))), np.cosh(T * np.sqrt(np.abs(d))))


@pytest.mark.parametrize("resonance, q_start, window, kind, q_star", [
    (1, 0.1, (-0.2, 0.2), PointKind.RESONANCE_1_1, 0.0),
    (2, 0.5, (0.3, 0.52), PointKind.RESONANCE_1_2, CycleWithBlock.BETA * np.sqrt(CycleWithBlock.C)),
])
def test_torus_curve_through_a_strong_resonance_is_flagged_there(resonance, q_start, window, kind, q_star):
    family = CycleWithBlock(resonance)
    torus = located(family, q_start, PointKind.TORUS, 0.0, family.SHIFT + 1.0, near=family.SHIFT + family.C)
    curve = cycle_bifurcation_curve(family, torus, *window, 0.0, family.SHIFT + 2.0)
    assert curve.complete and curve.qs.min() == pytest.approx(window[0])
    assert curve.qs.max() == pytest.approx(window[1])
    assert np.max(np.abs(curve.ps - family.SHIFT - family.C)) < 1e-9
    assert np.max(np.abs(curve.kappas - family.kappa(curve.qs))) < 1e-8
    (r,) = curve.special_points
    assert r.kind is kind and r.status is PointStatus.LOCATED
    assert r.q == pytest.approx(q_star, abs=1e-8) and r.p == pytest.approx(family.SHIFT + family.C, abs=1e-9)
    lo, hi = sorted(r.bracket)
    assert lo < hi
    # Past the resonance the points are neutral saddle cycles, and marked so.
    beyond = curve.qs < q_star
    assert np.array_equal(curve.neutral_saddle[np.abs(curve.qs - q_star) > 1e-6],
                          beyond[np.abs(curve.qs - q_star) > 1e-6])


def test_fold_flip_on_a_period_doubling_curve():
    """BautinWithBlock (flip): the cycle of radius r (V = SHIFT - q r^2 + r^4) has the multiplier
    -exp(T (q - 1.5 + FLIP_BETA r)), so its period-doubling curve is r = (1.5 - q) / FLIP_BETA; it touches the fold
    curve r^2 = q / 2, V = SHIFT - q^2 / 4, where the cycle's own radial multiplier passes +1: the fold-flip point
    q - 1.5 + FLIP_BETA sqrt(q / 2) = 0."""
    from scipy.optimize import brentq

    family = BautinWithBlock(flip=True)
    pd = located(family, 1.0, PointKind.PERIOD_DOUBLING, family.SHIFT - 3.0, family.SHIFT + 0.5)
    curve = cycle_bifurcation_curve(family, pd, 0.5, 1.3, family.SHIFT - 5.0, family.SHIFT + 1.0)
    assert curve.complete
    r = (1.5 - curve.qs) / FLIP_BETA
    assert np.max(np.abs(curve.ps - (family.SHIFT - curve.qs * r ** 2 + r ** 4))) < 1e-9
    q_ff = brentq(lambda b: b - 1.5 + FLIP_BETA * np.sqrt(b / 2), 0.01, 3.0)
    (ff,) = curve.special_points
    assert ff.kind is PointKind.FOLD_FLIP and ff.status is PointStatus.LOCATED
    assert ff.q == pytest.approx(q_ff, abs=1e-8) and ff.p == pytest.approx(family.SHIFT - q_ff ** 2 / 4,
                                                                                  abs=1e-9)


def test_cycle_curve_marks_the_points_that_miss_the_collocation_tolerance():
    """The curves keep their start's mesh, refined first where the start misses the tolerance: with the default
    tolerance every point meets it; with one far below the start's error estimate the start is re-meshed until it
    meets it; where the mesh may not grow (max_intervals), every point is marked as missing it."""
    from dataclasses import replace

    from bifurcation.cycles.problem import CycleSettings

    family = CycleWithBlock(2)
    torus = located(family, 0.5, PointKind.TORUS, 0.0, family.SHIFT + 1.0, near=family.SHIFT + family.C)
    error, intervals = torus.data["cycle"].error, torus.data["cycle"].orbit.intervals
    assert 0.0 < error < CycleSettings().tolerance
    cases = ((CycleSettings(), True, True),
             (replace(CycleSettings(), tolerance=0.01 * error), True, True),
             (replace(CycleSettings(), tolerance=0.01 * error, max_intervals=intervals), False, False))
    for settings, start_meets, meets in cases:
        curve = cycle_bifurcation_curve(family, torus, 0.45, 0.5, 0.0, family.SHIFT + 2.0, settings=settings)
        assert np.all(curve.tolerances == settings.tolerance) and np.all(curve.errors > 0.0)
        start = int(np.argmin(np.abs(curve.qs - torus.q) + np.abs(curve.ps - torus.p)))
        assert curve.meets_tolerance[start] == start_meets
        assert np.all(curve.meets_tolerance == meets)


class FlipWithCubic(CycleWithOscillator):
    """The supercritical cycle (radius r, r^2 = mu = V - SHIFT without the block) with a block rotating at half its
    angle and coupled by BETA r S(theta) (as in :class:`CycleWithBlock`), damping a = mu - C - (q - Q0) / 10: the
    multiplier -exp(T (a + BETA r)) is -1 on the period-doubling curve sqrt(mu) = (sqrt(BETA^2 + 4 C_q) - BETA) / 2,
    C_q = C + (q - Q0) / 10.  The block feeds back into the cycle, RHO |w|^2 into its radial rate and NU |w|^2 into
    its angular speed, and has its own cubic term SIGMA (q) |w|^2 w.  On the centre manifold (the half-angle frame,
    w = (xi, 0), r^2 = mu + RHO xi^2) xi' = (SIGMA + BETA RHO / (2 r)) xi^3: the normal-form coefficient with v1 of
    unit mean square is c = SIGMA + BETA RHO / (2 r) exactly (the angular feedback gives alpha != 0 but leaves c:
    it only turns w at order xi^2)."""

    param = "q"
    BETA, Q0, RHO, NU = 0.8, 0.4, 0.3, 0.2

    def sigma(self, q):
        return q - self.Q0

    def radius(self, q):
        return 0.5 * (np.sqrt(self.BETA ** 2 + 4 * (self.C + 0.1 * (q - self.Q0))) - self.BETA)

    def coefficient(self, q):
        return self.sigma(q) + self.BETA * self.RHO / (2 * self.radius(q))

    def rhs(self, X, V, q):
        X = np.asarray(X)
        x, y, u, v = X
        mu = V - self.SHIFT
        w2 = u * u + v * v
        grow, turn = mu - x * x - y * y + self.RHO * w2, self.W * (1 + self.NU * w2)
        a = mu - self.C - 0.1 * (q - self.Q0)
        half = 0.5 * turn
        s = self.sigma(q) * w2
        return np.array([grow * x - turn * y, turn * x + grow * y,
                         a * u - half * v + self.BETA * (x * u + y * v) + s * u,
                         half * u + a * v + self.BETA * (y * u - x * v) + s * v])


def test_period_doubling_coefficient_and_generalized_period_doubling_point():
    from scipy.optimize import brentq

    from bifurcation.cycle_curves.fold import FoldSystem
    from bifurcation.cycles.normal_forms import period_doubling_coefficient

    family = FlipWithCubic()
    q0 = 0.3
    pd = located(family, q0, PointKind.PERIOD_DOUBLING, 0.0, family.SHIFT + 1.0)
    assert pd.p == pytest.approx(family.SHIFT + family.radius(q0) ** 2, abs=1e-9)
    system = FoldSystem(family, pd.data["cycle"], 0.1, kind=PointKind.PERIOD_DOUBLING)
    U = system.start(pd.data["cycle"])
    assert period_doubling_coefficient(system, U) == pytest.approx(family.coefficient(q0), abs=1e-8)
    curve = cycle_bifurcation_curve(family, pd, -0.2, 0.4, 0.0, family.SHIFT + 2.0)
    assert curve.complete
    assert np.max(np.abs(curve.ps - family.SHIFT - family.radius(curve.qs) ** 2)) < 1e-9
    (gpd,) = curve.special_points
    q_star = brentq(family.coefficient, -0.2, 0.4)
    assert gpd.kind is PointKind.GENERALIZED_PERIOD_DOUBLING and gpd.status is PointStatus.LOCATED
    assert gpd.q == pytest.approx(q_star, abs=1e-8)
    assert gpd.p == pytest.approx(family.SHIFT + family.radius(q_star) ** 2, abs=1e-9)


class TorusWithCubic(CycleWithOscillator):
    """The cycle (r^2 = mu = V - SHIFT without the block) with an oscillator w = u + i v of frequency
    OMEGA + SIGMA2 |w|^2 and damping a = mu - C + GAMMA (r^2 - mu) + (q - Q0) |w|^2; the block feeds RHO |w|^2 into
    the cycle's radial rate.  The torus curve is V = SHIFT + C with theta = OMEGA T; on the centre manifold
    (r^2 = mu + RHO |w|^2) w' = i OMEGA w + (q - Q0 + GAMMA RHO + i SIGMA2) |w|^2 w, so with v of unit mean square
    (w = sqrt(2) xi) the normal-form coefficient is d = 2 (q - Q0 + GAMMA RHO + i SIGMA2): a Chenciner point at
    q = Q0 - GAMMA RHO."""

    param = "q"
    OMEGA, Q0, RHO, GAMMA, SIGMA2 = 0.7, 0.4, 0.3, 0.5, 0.2

    def coefficient(self, q):
        return 2 * (q - self.Q0 + self.GAMMA * self.RHO + 1j * self.SIGMA2)

    def rhs(self, X, V, q):
        X = np.asarray(X)
        x, y, u, v = X
        mu = V - self.SHIFT
        w2, r2 = u * u + v * v, x * x + y * y
        grow = mu - r2 + self.RHO * w2
        a = mu - self.C + self.GAMMA * (r2 - mu) + (q - self.Q0) * w2
        om = self.OMEGA + self.SIGMA2 * w2
        return np.array([grow * x - self.W * y, self.W * x + grow * y, a * u - om * v, om * u + a * v])


def test_neimark_sacker_coefficient_and_chenciner_point():
    from bifurcation.cycle_curves.torus import TorusSystem
    from bifurcation.cycles.normal_forms import neimark_sacker_coefficient

    family = TorusWithCubic()
    q0 = 0.35
    torus = located(family, q0, PointKind.TORUS, 0.0, family.SHIFT + 1.0)
    system = TorusSystem(family, torus.data["cycle"], 0.1)
    U = system.start(torus.data["cycle"])
    assert neimark_sacker_coefficient(system, U) == pytest.approx(family.coefficient(q0), abs=1e-8)
    curve = cycle_bifurcation_curve(family, torus, 0.15, 0.45, 0.0, family.SHIFT + 2.0)
    assert curve.complete and np.max(np.abs(curve.ps - family.SHIFT - family.C)) < 1e-9
    (ch,) = curve.special_points
    assert ch.kind is PointKind.CHENCINER and ch.status is PointStatus.LOCATED
    assert ch.q == pytest.approx(family.Q0 - family.GAMMA * family.RHO, abs=1e-8)


def test_resonance_between_the_last_curve_point_and_the_hopf_hopf_end(monkeypatch):
    """A torus curve's last computed point lies short of the Hopf-Hopf point where it ends; there kappa =
    cos(2 pi omega_2 / omega_1) of straight running.  A resonance value in that last stretch is located on the
    corrected curve, beyond the last point, like any other (issue 17).  The value is placed there on purpose (the
    real 1:4 lies elsewhere): the table of resonances is patched, not the locating code."""
    import bifurcation.cycle_curves.torus as torus
    from axles.units import BAR, KMH
    from bifurcation.cycles.branches import cycle_diagram
    from bifurcation.cycles.multipliers import classify_multipliers
    from reduced_model.family import SpeedFamily
    from reduced_model.model import Effects, ShimmyModel

    family = SpeedFamily(ShimmyModel(effects=Effects.parse("hcl,pt")), "pressure", pressures=TyrePressures.uniform(0.5 * BAR))
    diagram = cycle_diagram(family, 0.5 * BAR, 0.0, 400 * KMH)
    start = next(p for p in diagram.points_of(PointKind.TORUS) if p.data.get("end_segment"))
    window = (0.45 * BAR, 0.6 * BAR, 0.0, 400 * KMH)         # the stretch from 0.5 bar to the Hopf-Hopf end
    curve = cycle_bifurcation_curve(family, start, *window)
    side = next(i for i, e in enumerate(curve.end_points) if e is not None and e.kind is PointKind.HOPF_HOPF)
    hh, last = curve.end_points[side], (0 if side == 0 else -1)
    own = 2 * np.pi / curve.periods[last]
    w_own, w_other = sorted((hh.data["omega"], hh.data["omega2"]), key=lambda w: abs(w - own))
    kappa_end = np.cos(2 * np.pi * w_other / w_own)
    assert abs(curve.kappas[last] - kappa_end) < 1e-4          # the curve runs into that value
    target = 0.5 * (curve.kappas[last] + kappa_end)
    monkeypatch.setattr(torus, "RESONANCE_KAPPA", ((PointKind.RESONANCE_1_4, target),))
    again = cycle_bifurcation_curve(family, start, *window)
    (found,) = again.points_of(PointKind.RESONANCE_1_4)
    assert found.status is PointStatus.LOCATED and found.data["end_segment"]
    rest, _ = classify_multipliers(found.data["multipliers"])
    pair = rest[np.abs(rest.imag) > 1e-7]
    mu = pair[np.argmin(np.abs(np.abs(pair) - 1.0))]
    assert abs(abs(mu) - 1.0) < 1e-6 and abs(np.cos(np.angle(mu)) - target) < 1e-7
    assert found.data["cycle"].amplitude.max() < again.amplitudes[last].max()      # beyond the last point
