"""The least damping ratio of the equilibrium (:mod:`bifurcation.equilibria.margins`) on families
whose damping ratios are known by hand, and its zero level against the Hopf points of the same family."""

import math

import numpy as np
import pytest

from axles.units import BAR, from_kmh
from bifurcation.equilibria.hopf import find_hopf_points
from bifurcation.equilibria.margins import MarginStatus, least_damped, margin_map, zero_level

W0 = 2.0        # rad/s, natural frequency of the oscillator whose damping is q - p
W1 = 5.0        # rad/s, a second oscillator of fixed damping ratio Z1
Z1 = 0.3


class OscillatorFamily:
    """x'' + (q - p) x' + W0^2 x = 0, y'' + 2 Z1 W1 y' + W1^2 y = 0 and a real mode r' = growth r:
    zeta = (q - p) / (2 W0) for the first oscillator, Z1 for the second; the real mode (slower than either
    oscillator's decay) must not count."""

    param = "q"
    primary, primary_scale, primary_min = "p", 1.0, 0.0
    n = 5
    state_names = ("x", "x_dot", "y", "y_dot", "r")
    nominal = 1.0

    def __init__(self, growth=-0.01):
        self.growth = growth

    def linear_matrix(self, p, q):
        A = np.zeros((5, 5))
        A[0, 1] = A[2, 3] = 1.0
        A[1, 0], A[1, 1] = -W0 ** 2, -(q - p)
        A[3, 2], A[3, 3] = -W1 ** 2, -2 * Z1 * W1
        A[4, 4] = self.growth
        return A

    def validate(self, q):
        pass


def expected_zeta(p, q):
    return min((q - p) / (2 * W0), Z1)


@pytest.mark.parametrize("p, q", [(0.0, 1.0), (0.7, 1.0), (1.0, 1.0), (1.8, 1.0), (0.2, 3.0), (0.1, 2.5)])
def test_the_least_damping_ratio_is_the_oscillators(p, q):
    family = OscillatorFamily()
    m = least_damped(family, p, q)
    zeta = expected_zeta(p, q)
    assert m.status is MarginStatus.OSCILLATORY
    assert m.damping_ratio == pytest.approx(zeta, abs=1e-12)
    w = W0 if zeta < Z1 else W1
    assert m.omega == pytest.approx(w * math.sqrt(1 - zeta ** 2), rel=1e-12)
    A = family.linear_matrix(p, q)
    assert np.linalg.norm(A @ m.eigenvector - m.eigenvalue * m.eigenvector) < 1e-12
    assert m.real_growth == pytest.approx(-0.01) and not m.divergent
    assert m.stable == (zeta > 0)
    bare = least_damped(family, p, q, vector=False)
    assert bare.eigenvector is None and bare.damping_ratio == pytest.approx(m.damping_ratio, abs=1e-14)


def test_a_growing_real_eigenvalue_is_a_divergence_not_a_damping_ratio():
    m = least_damped(OscillatorFamily(growth=0.5), 0.0, 1.0)
    assert m.damping_ratio == pytest.approx(0.25, abs=1e-12)
    assert m.divergent and not m.stable


def test_with_no_oscillation_the_margin_is_undefined():
    family = OscillatorFamily()
    family.linear_matrix = lambda p, q: np.diag([-1.0, -2.0, p - 3.0])
    m = least_damped(family, 1.0, 0.0)
    assert m.status is MarginStatus.NO_OSCILLATION and math.isnan(m.damping_ratio)
    assert m.real_growth == pytest.approx(-1.0)


def test_the_map_and_its_minimum():
    family = OscillatorFamily()
    p, q = np.linspace(0.0, 2.0, 21), np.array([0.5, 1.0, 1.5])
    mmap = margin_map(family, p, q)
    assert mmap.damping_ratio.shape == (3, 21)
    assert np.allclose(mmap.damping_ratio, [[expected_zeta(a, b) for a in p] for b in q], atol=1e-12)
    low = mmap.minimum()
    assert (low.p, low.q) == (2.0, 0.5) and low.damping_ratio == pytest.approx(-0.375, abs=1e-12)
    inside = mmap.minimum(p_max=1.0, q_min=1.0)
    assert (inside.p, inside.q) == (1.0, 1.0) and inside.damping_ratio == pytest.approx(0.0, abs=1e-12)
    assert mmap.undefined == 0 and mmap.minimum(p_min=5.0) is None


@pytest.mark.parametrize("q", [0.37, 1.0, 1.91])
def test_the_zero_level_is_the_hopf_point(q):
    family = OscillatorFamily()
    zeros = zero_level(family, q, np.linspace(0.0, 3.0, 7))
    assert zeros == pytest.approx((q,), rel=1e-10)
    (h,) = find_hopf_points(family, q, 0.0, 3.0, lyapunov=False)
    assert h.p == pytest.approx(zeros[0], rel=1e-10)
    assert h.omega == pytest.approx(W0, rel=1e-9)


def _unstable_pairs(family, p, q):
    lam = np.linalg.eigvals(family.linear_matrix(p, q))
    return int(np.sum((lam.real > 0) & (lam.imag > 1e-9)))


@pytest.mark.parametrize("effects, bar", [("", 1.5), ("", 2.5), ("all", 1.5), ("hcl,pt", 2.0)])
def test_the_zero_level_meets_the_reduced_models_hopf_points(effects, bar):
    """Every sign change of the least damping ratio along the speed is a Hopf point of ``find_hopf_points`` to 1e-6
    relative, and every Hopf point where the first pair becomes unstable (or the last stable) is one."""
    from reduced_model.family import SpeedFamily
    from reduced_model.model import Effects, ShimmyModel
    family = SpeedFamily(ShimmyModel(effects=Effects.parse(effects)), "pressure")
    q, vmax = bar * BAR, from_kmh(400)
    hopf = find_hopf_points(family, q, 0.0, vmax, lyapunov=False)
    zeros = zero_level(family, q, np.linspace(0.0, vmax, 201))
    assert zeros, "no zero level found"
    for z in zeros:
        nearest = min(hopf, key=lambda h: abs(h.p - z))
        assert abs(nearest.p - z) <= 1e-6 * nearest.p
    for h in hopf:
        below, above = (_unstable_pairs(family, h.p * (1 + s), q) for s in (-1e-4, 1e-4))
        if min(below, above) == 0:
            assert any(abs(h.p - z) <= 1e-6 * h.p for z in zeros), h.p
