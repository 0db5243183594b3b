"""``--fidelity reduced`` reproduces the reduced equations for any axle (issue 9, item 3): random Table 1 entries,
random values of every chosen dimension including the new geometry (kingpin inclination, roll axis, mounts,
Ackermann arms, steering gear), all pressure effects and unequal left/right pressures.  The new elements' switches
are on in ``reduced``, so their dimensions must not enter; the MBS side is Exudyn's, the reduced side
:class:`reduced_model.model.ShimmyModel`."""

import dataclasses

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from axles.units import BAR, KMH, kmh
from axles.dimensions import AxleDimensions
from mbs_shimmy import Fidelity
from mbs_shimmy.linearisation import MbsFamily
from mbs_shimmy.model import MbsModel
from mbs_shimmy.simulation import integrate
from bifurcation.equilibria.hopf import find_hopf_points
from reduced_model.family import SpeedFamily
from reduced_model.model import Effects, ShimmyModel
from axles.parameters import YANG2024
from reduced_model.trajectory import SpeedSchedule
from axles.pressures import TyrePressures

SCALED = ("I1", "I2", "I3", "k1", "k2", "k3", "k4", "c1", "c2", "c3", "c4", "R", "L", "l", "gamma", "a0", "sigma0",
          "t0", "f")


def random_axle(seed):
    rng = np.random.default_rng(seed)
    params = YANG2024.replace(**{n: getattr(YANG2024, n) * rng.uniform(0.75, 1.3) for n in SCALED})
    dims = AxleDimensions(**{f.name: float(rng.uniform(*f.metadata["plausible"]))
                             for f in dataclasses.fields(AxleDimensions)})
    # a rigid wheel has I2 <= 2 x its diametral inertia
    dims = dims.replace(wheel_diametral_inertia=max(dims.wheel_diametral_inertia, 0.55 * params.I2))
    return params, dims, TyrePressures(rng.uniform(1.3, 2.8) * BAR, rng.uniform(1.3, 2.8) * BAR)


def _eigs(A):
    lam = np.linalg.eigvals(A)
    return lam[np.lexsort((lam.imag, lam.real))]


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_reduced_fidelity_reproduces_the_reduced_equations_for_any_axle(seed):
    params, dims, pressure = random_axle(seed)
    effects = Effects.parse("all")
    mbs = MbsFamily(MbsModel(params, effects, Fidelity.reduced(), dims), pressures=pressure)
    red = SpeedFamily(ShimmyModel(params, effects), pressures=pressure)
    assert mbs.n == 8
    for v_kmh in (20, 90, 250):
        a = _eigs(mbs.direct_linear_matrix(v_kmh * KMH, red.nominal))
        b = _eigs(red.linear_matrix(v_kmh * KMH, red.nominal))
        assert np.max(np.abs(a - b) / np.abs(b)) < 1e-9, (v_kmh, a, b)
    hm = find_hopf_points(mbs, red.nominal, 0.0, 400 * KMH, lyapunov=False)
    hr = find_hopf_points(red, red.nominal, 0.0, 400 * KMH, lyapunov=False)
    assert len(hm) == len(hr)
    for h, r in zip(hm, hr):
        assert abs(kmh(h.p) - kmh(r.p)) < 0.01


def test_reduced_fidelity_transient_for_another_axle():
    params, dims, pressure = random_axle(4)
    effects = Effects.parse("all")
    V = 70 * KMH
    x0 = np.zeros(8)
    x0[0], x0[4] = 0.01, -0.004
    traj = integrate(params, effects, Fidelity.reduced(), pressure, SpeedSchedule.constant(V), x0, 2.0, dims=dims,
                    poses=False)
    model = ShimmyModel(params, effects)
    ref = solve_ivp(lambda t, x: model.rhs(x, V, pressure), (0.0, 2.0), x0, method="DOP853", rtol=1e-12,
                    atol=1e-14, dense_output=True)
    xr = ref.sol(traj.t).T
    assert np.all(np.max(np.abs(traj.x - xr), axis=0) <= 1e-4 * np.max(np.abs(xr), axis=0))
