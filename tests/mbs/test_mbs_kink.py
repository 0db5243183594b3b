"""The full geometry's Hopf points at the camber force's kink: its quadratic coefficient a against the cycles.

MF 6.1's cornering stiffness falls with |camber|, so the full geometry's right-hand side is once but not twice
differentiable at straight running, and l1 is no criticality there (:mod:`comparisons.studies.onset`).  The kink
coefficient a (:func:`bifurcation.equilibria.hopf.kink_coefficient`) is: a > 0 makes the cycles born at the Hopf
point unstable at vanishing amplitude.  Checked against the collocation, an independent method: a branch started at
1/40 of the default amplitude goes to the side a says, unstable or stable as a says, and where a > 0 it folds back
where the default branch's end segment locates a fold and where the amplitude equation with a and the default
branch's first cycle puts it.  On the paper's axle and on random plausible axles.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from axles.axle import paper_axle
from axles.pressures import TyrePressures
from axles.units import BAR, KMH, kmh
from bifurcation.cycles.branches import branch_from_hopf, cycle_diagram
from bifurcation.cycles.problem import CycleSettings
from bifurcation.equilibria.hopf import find_hopf_points
from bifurcation.special_points import Criticality, PointKind
from comparisons.api import family_of
from comparisons.studies.onset import JUMP_TOL_DEG, branch_onset
from mbs_shimmy.fidelity import Assumption, Fidelity
from mbs_shimmy.model import MbsModel

SMALL = 0.0005          # start amplitude (scaled) of the small branch: the default's 1/40


def _family(axle, fidelity=Fidelity.full(), bar=1.5):
    return family_of(MbsModel(params=axle.params, fidelity=fidelity, dims=axle.dims), TyrePressures.uniform(bar * BAR))


def _small_branch(family, hopf, steps=7):
    s = CycleSettings()
    s = dataclasses.replace(s, start_amplitude=SMALL, continuation=dataclasses.replace(
        s.continuation, ds=SMALL, ds_max=10 * SMALL, max_steps=steps))
    return branch_from_hopf(family, hopf, hopf.p - 1.0, hopf.p + 1.0, settings=s)


def _unstable_side(family, hopf) -> float:
    """+1 where straight running is unstable above the Hopf point's speed, -1 below."""
    from bifurcation.equilibria.hopf import eigenvalues
    h = 1e-3
    return 1.0 if eigenvalues(family, hopf.p + h, hopf.q)[0].real > 0.0 else -1.0


def test_a_is_computed_only_where_the_right_hand_side_has_a_kink():
    """Full geometry: a at every Hopf point, the same with a ten times smaller step (1e-6 relative).  Without the
    camber force the right-hand side is smooth there: no a, l1 decides."""
    family = _family(paper_axle())
    points = find_hopf_points(family, family.nominal, 0.0, 400 * KMH)
    assert len(points) == 2 and all(math.isfinite(h.kink) and h.kink_criticality is not None for h in points)
    from bifurcation.equilibria.hopf import kink_coefficient
    for h in points:
        A, x0 = family.linear_matrix(h.p, h.q), family.equilibrium(h.p, h.q)
        finer = kink_coefficient(family, x0, h.p, h.q, A, h.omega, h.eigenvector)
        from bifurcation.equilibria import normal_form
        again = normal_form.kink_coefficient(lambda X: family.rhs_and_jacobians(X, h.p, h.q, kink_rows=False)[1],
                                             x0, A, h.omega, h.eigenvector, step=1e-6)
        assert finer[0] == h.kink
        assert again[0] == pytest.approx(h.kink, rel=1e-5)
    smooth = _family(paper_axle(), Fidelity(frozenset({Assumption.NO_CAMBER_FORCE})))
    for h in find_hopf_points(smooth, smooth.nominal, 0.0, 400 * KMH):
        assert math.isnan(h.kink) and h.kink_criticality is None and h.criticality is not None


def _estimated_fold(family, hopf, first):
    """(dp, theta1 amplitude) of the small cycles' fold by the amplitude equation rho' = sigma' dp rho + a rho^2 +
    c rho^3 with c from the branch's ``first`` cycle: c = -(sigma' dp1 + a rho1) / rho1^2, the fold at
    rho_f = a / (2 |c|), dp_f = -a^2 / (4 |c| sigma') (:mod:`comparisons.studies.onset`'s docstring)."""
    from bifurcation.equilibria.hopf import primary_derivative
    from bifurcation.equilibria.normal_form import left_eigenvector
    A = family.linear_matrix(hopf.p, hopf.q)
    v = hopf.eigenvector / np.linalg.norm(hopf.eigenvector)
    w = left_eigenvector(A, hopf.omega, v)
    sigma_p = float(np.real(np.vdot(w, primary_derivative(family, hopf.p, hopf.q, A) @ v)))
    i = family.state_names.index("theta1")
    rho1 = float(first.amplitude[i]) / (2.0 * abs(v[i]))
    c = -(sigma_p * (first.p - hopf.p) + hopf.kink * rho1) / rho1 ** 2
    return -hopf.kink ** 2 / (4.0 * abs(c) * sigma_p), hopf.kink / abs(c) * abs(v[i])


def test_the_paper_axles_small_cycles_fold_where_three_methods_put_them():
    """HB1 at 1.5 bar: a > 0.  The default branch's end segment (between the Hopf point and its first cycle, at
    theta1 0.077 deg) locates a cycle fold 1.3e-5 km/h into the speeds of stable straight running at theta1 about
    0.01 deg; a branch started forty times smaller runs there with unstable cycles and folds back at the same
    place (speed to 1 %, amplitude to 3 %); the amplitude equation with a and the default branch's first cycle puts it there too (10 %,
    3 % measured).  Beyond it every cycle is stable: a soft onset in practice (:data:`JUMP_TOL_DEG`)."""
    family = _family(paper_axle())
    diagram = cycle_diagram(family, family.nominal, 0.0, 100 * KMH)
    hb1 = diagram.hopf[0]
    assert hb1.kink_criticality is Criticality.SUBCRITICAL
    onset = branch_onset(diagram, hb1)
    assert onset.criticality is Criticality.SUBCRITICAL and onset.soft and onset.jump_deg < JUMP_TOL_DEG
    branch = next(b for b in diagram.branches if b.start is not None and b.start.p == hb1.p)
    located = min((s for s in branch.special_points if s.kind is PointKind.CYCLE_FOLD), key=lambda s: s.p)
    assert located.data["end_segment"] and branch.points[0].stable
    small = _small_branch(family, hb1)
    side = _unstable_side(family, hb1)
    assert not small.points[0].stable and (small.points[0].p - hb1.p) * side < 0.0
    folds = [s for s in small.special_points if s.kind is PointKind.CYCLE_FOLD and not s.data.get("end_segment")]
    assert len(folds) == 1
    i = family.state_names.index("theta1")
    assert folds[0].p - hb1.p == pytest.approx(located.p - hb1.p, rel=0.01)
    # at a fold the speed is stationary along the curve and the amplitude is not: an amplitude is as good as the
    # located position along the curve (1.1 % apart measured), the speed much better (0.2 %)
    assert folds[0].data["amplitude"][i] == pytest.approx(located.data["amplitude"][i], rel=0.03)
    dp, theta1 = _estimated_fold(family, hb1, branch.points[0])
    assert dp == pytest.approx(located.p - hb1.p, rel=0.1)
    assert theta1 == pytest.approx(located.data["amplitude"][i], rel=0.1)
    assert all(p.stable for p in small.points if p.amplitude[i] > 2 * located.data["amplitude"][i])
    assert kmh(abs(located.p - hb1.p)) < 1e-4 and math.degrees(located.data["amplitude"][i]) < 0.02


@pytest.mark.parametrize("seed", [3, 11, 17])
def test_a_says_which_way_the_smallest_cycles_go_on_random_plausible_axles(seed, campaign_tool):
    """At the lowest Hopf point of a random plausible axle at 1.5 bar (draws until one has one): the small branch's
    first cycle is unstable and on the side of stable straight running where a > 0, stable and on the unstable side
    where a < 0."""
    rng = np.random.default_rng((42, seed))
    for k in range(12):
        axle = campaign_tool.draw_axle(rng, f"KINK-{seed}-{k}", t0=True)
        family = _family(axle)
        points = find_hopf_points(family, family.nominal, 0.0, 400 * KMH)
        if points:
            break
    else:
        pytest.fail("no drawn axle with a Hopf point")
    h = points[0]
    assert h.kink_criticality is not None
    first = _small_branch(family, h, steps=1).points[0]
    ahead = (first.p - h.p) * _unstable_side(family, h) > 0.0
    if h.kink > 0.0:
        assert not first.stable and not ahead
    else:
        assert first.stable and ahead


def test_the_kink_is_looked_for_at_the_equilibrium_not_at_zero():
    """Under brake slip the full geometry's steady state lies off x = 0 (toe and camber), where the camber force is
    smooth: the onset reads l1 there, not a kink it would find at x = 0 (where the braked axle never is)."""
    from types import SimpleNamespace
    from axles.braking import Braking
    from comparisons.api import Axle
    from comparisons.studies.onset import has_kink
    at = SimpleNamespace(p=100.0 * KMH)
    free = Axle.paper().mbs("full").problem(TyrePressures(1.5 * BAR, 1.5 * BAR))
    braked = Axle.paper().mbs("full").problem(TyrePressures(1.5 * BAR, 1.5 * BAR), braking=Braking.of_slip(0.05, 0.05))
    at.q = free.nominal
    assert has_kink(free, at)
    at.q = braked.nominal
    x = braked.equilibrium(at.p, at.q)
    assert np.max(np.abs(x)) > 1e-3 and not has_kink(braked, at)
    assert braked.twice_differentiable(np.zeros(braked.n), at.p, at.q) is False    # what x = 0 would have said
