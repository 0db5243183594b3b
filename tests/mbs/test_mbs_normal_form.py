"""Normal forms of the multibody model from the twin's exact derivatives (issue 30), and where they do not exist.

Without the camber force the full geometry is smooth at straight running: the twin's third derivative is its second
differentiated, and the first Lyapunov coefficient from its exact forms equals the one from differences of Exudyn's
right-hand side (an independent computation), on the paper's axle and on a random plausible one.  With the camber
force (the full geometry) MF 6.1's cornering stiffness has |camber|, zero at straight running: the second derivative
jumps there, the l1 of differences depends on their step, and the family says so.
"""

from __future__ import annotations

import numpy as np
import pytest

from axles.axle import paper_axle
from axles.pressures import TyrePressures
from axles.units import BAR, KMH
from bifurcation.equilibria.hopf import find_hopf_points
from bifurcation.equilibria.normal_form import DifferenceForms, first_lyapunov_coefficient
from mbs_shimmy.fidelity import Fidelity
from mbs_shimmy.linearisation import KINKED_FORMS, MbsFamily, TwinForms
from mbs_shimmy.model import MbsModel

SMOOTH = Fidelity.parse("no_camber_force")      # the full geometry but for its camber force


def _family(fidelity, axle=None, bar=1.5):
    axle = axle or paper_axle()
    model = MbsModel(axle.params, fidelity=fidelity, dims=axle.dims)
    return MbsFamily(model, pressures=TyrePressures.uniform(bar * BAR))


def _first_hopf(family, bar=1.5):
    return find_hopf_points(family, bar * BAR, 0.0, 400 * KMH, lyapunov=False)[0]


def test_twin_third_derivative_is_its_second_differentiated():
    family = _family(SMOOTH)
    L, q = family.layout, 1.5 * BAR
    twin = family._at(q).twin
    rng = np.random.default_rng(3)
    scales = family.state_scales(1.0)[L.x_to_y]
    y = 0.01 * rng.normal(size=family.n) * scales
    u, v, w = (rng.normal(size=family.n) * scales for _ in range(3))
    third = twin.third_derivative(y, 40 * KMH, u, v, w)
    h = 1e-4
    by_second = (twin.second_derivative(y + h * w, 40 * KMH, u, v)
                 - twin.second_derivative(y - h * w, 40 * KMH, u, v)) / (2 * h)
    np.testing.assert_allclose(third, by_second, rtol=0, atol=1e-6 * np.max(np.abs(third)))


@pytest.mark.parametrize("which", ["paper", "random"])
def test_first_lyapunov_from_the_twin_equals_the_differences_of_exudyn(which, campaign_tool):
    axle = paper_axle()
    if which == "random":
        axle = campaign_tool.draw_axle(np.random.default_rng((38, 1)), "FORMS-1", t0=True)
    family = _family(SMOOTH, axle)
    h = _first_hopf(family)
    x0 = np.zeros(family.n)
    A = family.linear_matrix(h.p, h.q)
    forms = family.multilinear_forms(x0, h.p, h.q)
    assert isinstance(forms, TwinForms) and family.lyapunov_forms == "twin"
    exact = first_lyapunov_coefficient(forms, A, h.omega, h.eigenvector)
    # Differences with steps of 20 % of the state scales: Exudyn's forces carry ~1e-10 of rounding, divided by h^3
    # in C; at the default 5 % it costs 1.3e-3 of l1 on the random axle (measured; 4.5e-6 and 2e-5 at 20 %)
    by_differences = first_lyapunov_coefficient(
        DifferenceForms(lambda x: family.rhs(x, h.p, h.q), x0, family.state_scales(1.0), relative_step=0.2), A,
        h.omega, h.eigenvector)
    assert exact == pytest.approx(by_differences, rel=1e-4)


def test_the_full_geometry_is_not_twice_differentiable_at_straight_running():
    """The camber force's |camber|: the jump of D^2 f across straight running stays as the offset shrinks (it
    shrinks tenfold without the camber force); l1 by differences then changes sign with the step, and the family
    falls back to differences and says why."""
    family = _family(Fidelity.full())
    h = _first_hopf(family)
    L = family.layout
    twin = family._at(h.q).twin
    z = (np.cos(1.7 * np.arange(family.n) + 0.3) * family.state_scales(1.0))[L.x_to_y]
    y0 = np.zeros(family.n)

    def jump(model_family, e):
        t = model_family._at(h.q).twin
        return np.max(np.abs(t.second_derivative(y0 + e * z, h.p, z, z) - t.second_derivative(y0 - e * z, h.p, z, z)))
    assert jump(family, 1e-7) > 0.5 * jump(family, 1e-5)
    smooth = _family(SMOOTH)
    assert jump(smooth, 1e-7) < 0.02 * jump(smooth, 1e-5)
    A = family.linear_matrix(h.p, h.q)
    l1 = [first_lyapunov_coefficient(DifferenceForms(lambda x: family.rhs(x, h.p, h.q), np.zeros(family.n),
                                                     family.state_scales(1.0), relative_step=step),
                                     A, h.omega, h.eigenvector) for step in (0.2, 0.005)]
    assert l1[0] < 0.0 < l1[1]
    forms = family.multilinear_forms(np.zeros(family.n), h.p, h.q)
    assert not isinstance(forms, TwinForms)
    assert family.lyapunov_forms == KINKED_FORMS == "differences, not twice differentiable"
    assert twin is not None
