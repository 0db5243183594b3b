"""Model equivalence on any axle: the MBS with every assumption of the reduced model on against the reduced model.

``pytest --axle FILE.toml tests/test_equivalence_axle.py`` runs these checks on an engineer's own axle (keep them in
your CI); without ``--axle`` they run on the paper's truck.  Pressures: the ends and the middle of the axle file's
pressure window, and an asymmetric pair.  Each check compares two independent computations: the reduced model's
equations (2.1)-(2.11) and Exudyn's kinematic tree with the user tyre elements.
"""

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from comparisons.axles.units import BAR, KMH, kmh
from mbs_shimmy import Fidelity, MbsFamily, MbsModel, simulate
from reduced_model.bifurcation.equilibria.hopf import hopf_points
from reduced_model.family import SpeedFamily
from reduced_model.model import Effects, ShimmyModel
from reduced_model.trajectory import SpeedSchedule

EIGEN_TOL = 1e-9        # relative
HOPF_TOL_KMH = 0.01
TRANSIENT_TOL = 1e-4    # of the amplitude of each state


def pressures(axle):
    lo, hi = axle.pressure_range_bar
    mid = 0.5 * (lo + hi)
    return [lo * BAR, mid * BAR, hi * BAR, (mid * BAR, max(lo, 0.8 * mid) * BAR)]


def _eigs(A):
    lam = np.linalg.eigvals(A)
    return lam[np.lexsort((lam.imag, lam.real))]


@pytest.mark.parametrize("effects", ["", "all"])
def test_eigenvalues_equal(axle, effects):
    for p in pressures(axle):
        mbs = MbsFamily(MbsModel(axle.params, Effects.parse(effects), Fidelity.reduced(), axle.dims), pressure=p)
        red = SpeedFamily(ShimmyModel(axle.params, Effects.parse(effects)), pressure=p)
        for kmh in (20, 60, 150, 300):
            a = _eigs(mbs.direct_linear_matrix(kmh * KMH, mbs.nominal))
            b = _eigs(red.linear_matrix(kmh * KMH, red.nominal))
            assert np.max(np.abs(a - b)) / np.max(np.abs(b)) < EIGEN_TOL, (p, kmh)


def test_hopf_speeds_equal(axle):
    found = 0
    for p in pressures(axle):
        mbs_family = MbsFamily(MbsModel(axle.params, Effects(), Fidelity.reduced(), axle.dims), pressure=p)
        red_family = SpeedFamily(ShimmyModel(axle.params), pressure=p)
        mbs = hopf_points(mbs_family, mbs_family.nominal, 0.0, 400 * KMH, lyapunov=False)
        red = hopf_points(red_family, red_family.nominal, 0.0, 400 * KMH, lyapunov=False)
        assert len(mbs) == len(red), p
        for h, r in zip(mbs, red):
            assert abs(kmh(h.speed) - kmh(r.speed)) < HOPF_TOL_KMH
            assert abs(h.omega - r.omega) < 1e-6 * r.omega
        found += len(red)
    if found == 0:
        pytest.skip("no Hopf point at any tested pressure of this axle: nothing to compare")


def test_transient_equal(axle):
    """2 s from a small yaw angle at 60 km/h, lowest and asymmetric pressures, against DOP853 at rtol 1e-12."""
    lo = axle.pressure_range_bar[0] * BAR
    for p in (lo, pressures(axle)[-1]):
        x0 = np.zeros(8)
        x0[0] = 0.01
        V = 60 * KMH
        traj = simulate(axle.params, Effects(), Fidelity.reduced(), p, SpeedSchedule.constant(V), x0, 2.0,
                        dims=axle.dims, poses=False)
        assert traj.complete
        model = ShimmyModel(axle.params)
        ref = solve_ivp(lambda t, x: model.rhs(x, V, p), (0.0, 2.0), x0, method="DOP853", rtol=1e-12, atol=1e-14,
                        dense_output=True)
        xr = ref.sol(traj.t).T
        amplitude = np.max(np.abs(xr), axis=0)
        assert np.all(np.max(np.abs(traj.x - xr), axis=0) <= TRANSIENT_TOL * amplitude + 1e-12)
