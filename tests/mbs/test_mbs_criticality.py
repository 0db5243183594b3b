"""Criticality of the multibody model's Hopf points, from Exudyn's right-hand side.

The first Lyapunov coefficient of the MBS comes from multilinear forms by finite differences (the MBS is known at
real states only); the reduced model's from Cauchy integrals on complex circles.  Two independent checks: with
every assumption on the two models are the same equations, so the coefficients must agree; with the full
geometry, the sign must say on which side of the Hopf point the continued branch of cycles leaves it (about half
a minute per case on 2 cores: slow suite).
"""

import numpy as np
import pytest

from axles.units import BAR, KMH
from mbs_shimmy import Fidelity
from mbs_shimmy.linearisation import MbsFamily
from mbs_shimmy.model import MbsModel
from bifurcation.continuation import ContinuationSettings
from bifurcation.cycles.branches import branch_from_hopf
from bifurcation.cycles.problem import CycleSettings
from bifurcation.equilibria.hopf import eigenvalues, find_hopf_points
from bifurcation.special_points import Criticality
from reduced_model.family import SpeedFamily
from reduced_model.model import Effects, ShimmyModel
from axles.pressures import TyrePressures

VMAX = 400.0 * KMH


@pytest.mark.parametrize("effects, pressure", [("", TyrePressures.uniform(1.5 * BAR)), ("all", TyrePressures.uniform(2.5 * BAR)),
                                               ("hcl,pt", TyrePressures(1.6 * BAR, 1.2 * BAR))])
def test_mbs_first_lyapunov_equals_the_reduced_models_with_every_assumption_on(effects, pressure):
    eff = Effects.parse(effects) if effects else Effects()
    reduced = SpeedFamily(ShimmyModel(effects=eff), pressures=pressure)
    mbs = MbsFamily(MbsModel(effects=eff, fidelity=Fidelity.reduced()), pressures=pressure)
    r = find_hopf_points(reduced, reduced.nominal, 0.0, VMAX)
    m = find_hopf_points(mbs, mbs.nominal, 0.0, VMAX)
    assert len(r) == len(m) > 0
    for a, b in zip(r, m):
        assert b.p == pytest.approx(a.p, rel=1e-9)
        assert b.first_lyapunov == pytest.approx(a.first_lyapunov, rel=1e-4)
        assert b.criticality is a.criticality


def _short_branch(family, hopf, others):
    settings = CycleSettings(continuation=ContinuationSettings(ds=0.02, ds_min=1e-6, ds_max=0.5, max_steps=4,
                                                               newton_tol=1e-7, newton_max_iter=8, max_turn=0.3))
    return branch_from_hopf(family, hopf, 0.0, VMAX, others=others, settings=settings)


@pytest.mark.slow
@pytest.mark.parametrize("pressure_bar, kept", [(1.5, ""), (2.5, "rigid_axle_mounts")])
def test_full_geometry_criticality_agrees_with_the_side_the_branch_leaves(pressure_bar, kept):
    """Supercritical: the small cycles exist where straight running is unstable and are stable; subcritical: the
    other side, unstable.  The side where straight running is unstable comes from the eigenvalues, the side of the
    cycles from the continued branch.  (The full axle has no Hopf point at 2.5 bar; with rigid mounts it has two.)"""
    fidelity = Fidelity.parse(kept) if kept else Fidelity.full()
    family = MbsFamily(MbsModel(fidelity=fidelity), pressures=TyrePressures.uniform(pressure_bar * BAR))
    points = find_hopf_points(family, family.nominal, 0.0, VMAX)
    assert points
    for h in points:
        assert h.criticality is not None
        delta = 1e-3 * h.p
        growth = [max(eigenvalues(family, h.p + s * delta, h.q).real) for s in (-1.0, 1.0)]
        unstable_side = 1.0 if growth[1] > growth[0] else -1.0
        branch = _short_branch(family, h, points)
        assert len(branch.points) >= 3, branch.message
        side = np.sign(branch.points[-1].p - h.p)
        expected = unstable_side if h.criticality is Criticality.SUPERCRITICAL else -unstable_side
        assert side == expected
        assert branch.points[1].stable == (h.criticality is Criticality.SUPERCRITICAL)
