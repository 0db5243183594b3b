"""The compiled solver stage (:mod:`mbs_shimmy.compiled_stage`) against the Python path it is compiled from.

Both evaluate the same functions (numba compiles the Python ones, no fastmath), so they must agree to rounding at
every state and for every switch the stage reads: the tyre element's switches in all combinations, each geometry
and layout switch, each set of pressure effects, unequal pressures, a speed ramp, and a state outside the load
table, where the stage hands back to Python.
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from axles.braking import FREE_ROLLING, Braking
from axles.units import BAR
from mbs_shimmy.fidelity import ELEMENT_ASSUMPTIONS, Assumption, Fidelity
from mbs_shimmy.evaluator import constant_speed
from mbs_shimmy.model import MbsModel
from mbs_shimmy.load_table import LoadTable
from reduced_model.model import Effects
from axles.pressures import TyrePressures

# the switches the tyre elements read (ElementFlags), the load dependence and the camber terms
ELEMENT_SWITCHES = (Assumption.FIXED_STATIC_LOAD_ARMS, Assumption.SLIP_HEADING_ONLY, Assumption.LOAD_TRAMP_ONLY,
                    Assumption.LATERAL_STIFFNESS_TRAMP_ONLY, Assumption.SEPARATE_LATERAL_SPRING,
                    Assumption.CONSTANT_LOAD, Assumption.NO_CAMBER_FORCE)
OTHER_SWITCHES = tuple(a for a in Assumption if a not in ELEMENT_SWITCHES and a is not Assumption.SMALL_ANGLES)


def _states(system, count, seed, amplitude=0.004):
    """Random states (q, q' as Exudyn passes them: lists of floats) written into the system's current
    configuration; the slip angles and rates up to 0.05 rad, 2 rad/s."""
    rng = np.random.default_rng(seed)
    m = system.layout.n_mech
    for _ in range(count):
        y = np.concatenate([rng.uniform(-amplitude, amplitude, m), rng.uniform(-0.1, 0.1, m),
                            rng.uniform(-0.05, 0.05, 2)])
        system.set_state(y)
        yield [float(v) for v in y[:m]] + [0.0, 0.0], [float(v) for v in y[m:]]


def _compare(fidelity, effects=Effects.parse("all"), pressures=TyrePressures.uniform(1.5 * BAR), acceleration=None,
             count=12, seed=0, braking=FREE_ROLLING):
    """Compiled against Python at ``count`` random states; returns how many the compiled stage evaluated."""
    system = MbsModel(effects=effects, fidelity=fidelity).system(pressures, constant_speed(20.0), acceleration,
                                                                  braking=braking)
    forces = system.forces
    assert forces.stage is not None
    used = 0
    for t, (q, qd) in enumerate(_states(system, count, seed)):
        compiled = forces.compiled(0.1 * t, q, qd)
        python = forces.evaluate(0.1 * t, q, qd, python=True)
        if compiled is None:
            continue
        used += 1
        assert all(isinstance(v, float) for v in compiled)
        np.testing.assert_allclose(compiled, python, rtol=1e-12, atol=1e-9)
        assert forces.evaluate(0.1 * t, q, qd) == compiled
    return used


@pytest.mark.parametrize("on", [c for k in range(len(ELEMENT_SWITCHES) + 1)
                                for c in itertools.combinations(ELEMENT_SWITCHES, k)],
                         ids=lambda c: ",".join(a.value for a in c) or "full")
def test_every_element_switch_combination(on):
    assert _compare(Fidelity(frozenset(on)), count=6, seed=len(on)) >= 5


@pytest.mark.parametrize("braking", [Braking.of_slip(0.06, 0.0), Braking.of_slip(-0.04, 0.1),
                                     Braking.of_force(2500.0, 1000.0)], ids=str)
@pytest.mark.parametrize("names", ["", "all"])
def test_braking_runs_compiled(braking, names):
    """Under braking (and driving) the compiled stage carries the combined slip and the brake force (issue 32),
    with and without the camber terms and the load dependence."""
    effects = Effects.parse(names) if names else Effects()
    for fidelity in (Fidelity.full(), Fidelity(frozenset({Assumption.NO_CAMBER_FORCE, Assumption.CONSTANT_LOAD}))):
        assert _compare(fidelity, effects=effects, braking=braking, count=6, seed=3) >= 5


@pytest.mark.parametrize("switch", OTHER_SWITCHES, ids=lambda a: a.value)
def test_each_geometry_switch(switch):
    assert _compare(Fidelity(frozenset({switch}))) >= 10


@pytest.mark.parametrize("names", ["", "hcl", "pt", "rl", "vs", "hcl,pt", "pt,rl", "hcl,rl", "all"])
def test_each_pressure_effect_set_and_unequal_pressures(names):
    assert _compare(Fidelity.full(), effects=Effects.parse(names) if names else Effects(),
                    pressures=TyrePressures(1.2 * BAR, 2.6 * BAR)) >= 10


def test_speed_ramp_and_rigid_layouts():
    """A braking ramp (the spin-up moments and the d'Alembert force), with the tree's layouts without the lateral
    mounts, the steering gear or the bounce."""
    assert _compare(Fidelity.full(), acceleration=lambda t: -1.5 - t) >= 10
    rigid = (Assumption.RIGID_AXLE_MOUNTS, Assumption.RIGID_STEERING_GEAR, Assumption.RIGID_VERTICAL_MOUNTS)
    for k in (2, 3):
        for on in itertools.combinations(rigid, k):
            assert _compare(Fidelity(frozenset(on)), acceleration=lambda t: 2.0, count=6) >= 5


def _rolled(system, fraction: float) -> np.ndarray:
    """The state at rest rolled (psi) until the right wheel carries ``fraction`` of its static load (bisection on
    the Python path's load)."""
    forces, m = system.forces, system.layout.n_mech
    y = np.zeros(2 * m + 2)

    def load(psi):
        y[forces.i_psi] = psi
        system.set_state(y)
        states = []
        forces.evaluate(0.0, [float(v) for v in y[:m]] + [0.0, 0.0], [0.0] * (m + 2), states, python=True)
        return min(s.vertical_force for s in states) - fraction * forces.tyres[0].static_load
    lo, hi = 0.0, 0.2 if load(0.2) < 0.0 else -0.2
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if load(mid) > 0.0 else (lo, mid)
    y[forces.i_psi] = hi
    return y


@pytest.mark.parametrize("names", ["", "all"])
def test_a_lifted_wheel_runs_compiled(names):
    """A wheel lifted off the road (zero load: no grip, a and sigma at 1 % of the load, which with hcl and rl
    differ from the static wheel's): the compiled stage evaluates it and equals the Python path."""
    effects = Effects.parse(names) if names else Effects()
    system = MbsModel(effects=effects, fidelity=Fidelity.full()).system(TyrePressures.uniform(1.5 * BAR),
                                                                         constant_speed(20.0))
    forces = system.forces
    m = system.layout.n_mech
    y = _rolled(system, -0.2)           # rolled far enough to lift the right wheel, the left within the table
    y[2 * m] = 0.01
    y[2 * m + 1] = -0.02
    system.set_state(y)
    q, qd = [float(v) for v in y[:m]] + [0.0, 0.0], [float(v) for v in y[m:]]
    states = []
    python = forces.evaluate(0.0, q, qd, states, python=True)
    assert min(s.vertical_force for s in states) <= 0.0
    assert max(s.vertical_force for s in states) < 3.0 * forces.tyres[0].static_load
    compiled = forces.compiled(0.0, q, qd)
    assert compiled is not None
    np.testing.assert_allclose(compiled, python, rtol=1e-12, atol=1e-9)


def test_a_load_below_the_table_is_evaluated_in_python():
    """A wheel carrying 5e-7 of its static load, below the load table (1e-6): the properties come from the
    reduced model's formulas directly; the compiled stage declines and :meth:`evaluate` gives the Python path's
    forces."""
    system = MbsModel(fidelity=Fidelity.full()).system(TyrePressures.uniform(1.5 * BAR), constant_speed(20.0))
    forces = system.forces
    m = system.layout.n_mech
    y = _rolled(system, 5e-7)
    y[2 * m] = 0.01
    system.set_state(y)
    q, qd = [float(v) for v in y[:m]] + [0.0, 0.0], [float(v) for v in y[m:]]
    states = []
    python = forces.evaluate(0.0, q, qd, states, python=True)
    assert 0.0 < min(s.vertical_force for s in states) < LoadTable.RANGE[0] * forces.tyres[0].static_load
    assert forces.compiled(0.0, q, qd) is None
    assert forces.evaluate(0.0, q, qd) == python


def test_a_wheel_near_lift_off_is_in_the_table():
    """A wheel carrying 1 % of its static load (near lift-off, where orbits of the full geometry at high speed
    pass): inside the load table, so the compiled stage evaluates it, equal to the Python path, whose
    interpolated properties equal the direct formulas to 1e-10."""
    system = MbsModel(fidelity=Fidelity.full()).system(TyrePressures.uniform(1.5 * BAR), constant_speed(20.0))
    forces = system.forces
    m = system.layout.n_mech
    y = _rolled(system, 0.01)
    y[2 * m] = 0.01
    system.set_state(y)
    q, qd = [float(v) for v in y[:m]] + [0.0, 0.0], [float(v) for v in y[m:]]
    states = []
    python = forces.evaluate(0.0, q, qd, states, python=True)
    load = min(s.vertical_force for s in states)
    assert 0.009 < load / forces.tyres[0].static_load < 0.011
    compiled = forces.compiled(0.0, q, qd)
    assert compiled is not None
    np.testing.assert_allclose(compiled, python, rtol=1e-12, atol=1e-9)
    table = forces.tyres[0].table
    pick = list(table.columns)
    np.testing.assert_allclose(np.array(table.values(load))[pick], np.array(table.direct(load))[pick], rtol=1e-10)


def test_first_order_kinematics_stay_in_python():
    """small_angles has no compiled stage: evaluate is the Python path."""
    for fidelity in (Fidelity.reduced(), Fidelity(frozenset(ELEMENT_ASSUMPTIONS + (Assumption.SMALL_ANGLES,)))):
        system = MbsModel(fidelity=fidelity).system(TyrePressures.uniform(1.5 * BAR), constant_speed(20.0))
        assert system.forces.stage is None
