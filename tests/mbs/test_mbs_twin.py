"""The compiled twin (:mod:`mbs_shimmy.twin`) against Exudyn, the model it is generated from.

At random states of the full geometry and of each element switch on, on the paper's axle and on random plausible
axles (``tools/verify_campaign.py``'s draws): the twin's right-hand side equals Exudyn's to 1e-10 relative (it
does to about 1e-14), and its Jacobian equals Exudyn's five-point differences (step 1e-4) to 1e-10 relative of the
largest entry.

That holds where the right-hand side is smooth.  With the load dependence on (``constant_load`` off) the tyre
properties come from a load table interpolated by cubic pieces, continuous at the nodes but with a derivative that
jumps there by about 1e-8 relative; the nodes are 0.33 % of load apart, and a step of 1e-4 m in the bounce moves
the load by about as much, so the differences average two pieces while the twin (like Exudyn's own stage) is on
one.  There the check is 5e-9 relative: with ``constant_load`` on, the same states agree to 1e-11.  The element
switches are therefore checked with ``constant_load`` on (Jacobian to 1e-10) and the full geometry both ways.
"""

from __future__ import annotations

import numpy as np
import pytest

from axles.axle import paper_axle
from axles.pressures import TyrePressures
from axles.units import BAR
from mbs_shimmy.fidelity import ELEMENT_ASSUMPTIONS, Assumption, Fidelity
from mbs_shimmy.evaluator import MbsEvaluator, speed_is_time
from mbs_shimmy.model import MbsModel
from mbs_shimmy.twin import twin_of

FULL = Fidelity.full()
SWITCHES = (FULL,) + tuple(Fidelity(frozenset({a})) for a in ELEMENT_ASSUMPTIONS)


def _states(layout, count, seed, amplitude=0.004):
    rng = np.random.default_rng(seed)
    m = layout.n_mech
    for _ in range(count):
        yield np.concatenate([rng.uniform(-amplitude, amplitude, m), rng.uniform(-0.1, 0.1, m),
                              rng.uniform(-0.05, 0.05, 2)])


def _check(axle, fidelity, count=3, seed=0, jacobian_tol=1e-10):
    system = MbsModel(params=axle.params, fidelity=fidelity, dims=axle.dims).system(TyrePressures.uniform(1.5 * BAR),
                                                                                    speed_is_time)
    exudyn, twin = MbsEvaluator(system), twin_of(system)
    assert twin is not None, f"the twin must cover {fidelity.label}"
    checked = 0
    for k, y in enumerate(_states(system.layout, count, seed)):
        speed = (5.0, 20.0, 33.0)[k % 3]
        f, J, Jv, ok = twin.rhs_and_jacobian(y, speed)
        assert ok
        fe = exudyn.rhs(y, speed)
        assert np.max(np.abs(f - fe)) <= 1e-10 * np.max(np.abs(fe))
        Je = exudyn.jacobian(y, speed)
        assert np.max(np.abs(J - Je)) <= jacobian_tol * np.max(np.abs(Je))
        h = 1e-3
        dv = (exudyn.rhs(y, speed + h) - exudyn.rhs(y, speed - h)) / (2 * h)
        np.testing.assert_allclose(Jv, dv, rtol=0, atol=1e-8 * np.max(np.abs(dv)))
        checked += 1
    return checked


def test_twin_covers_the_exact_kinematics_only():
    """small_angles runs a Python user function with coordinate connectors: the twin declines it."""
    with_small_angles = Fidelity(frozenset(ELEMENT_ASSUMPTIONS) | {Assumption.SMALL_ANGLES})
    for fidelity in (Fidelity.reduced(), with_small_angles):
        system = MbsModel(fidelity=fidelity).system(TyrePressures.uniform(1.5 * BAR), speed_is_time)
        assert twin_of(system) is None


@pytest.mark.parametrize("fidelity", SWITCHES, ids=lambda f: f.label)
def test_twin_equals_exudyn_on_the_paper_axle(fidelity):
    """Each element switch on (and none), with the load table out of the way: Jacobian to 1e-10."""
    assert _check(paper_axle(), Fidelity(fidelity.assumed | {Assumption.CONSTANT_LOAD})) == 3


def test_twin_equals_exudyn_with_the_load_table():
    assert _check(paper_axle(), FULL, jacobian_tol=5e-9) == 3


@pytest.mark.parametrize("number", (1, 2))
def test_twin_equals_exudyn_on_random_plausible_axles(number, campaign_tool):
    axle = campaign_tool.draw_axle(np.random.default_rng((30, number)), f"TWIN-{number}", t0=True)
    assert _check(axle, FULL, count=2, seed=number, jacobian_tol=5e-9) == 2
    switch = Fidelity(SWITCHES[1 + 3 * number].assumed | {Assumption.CONSTANT_LOAD})
    assert _check(axle, switch, count=2, seed=number) == 2


def _rolled(system, fraction, seed=7):
    """A state rolled (psi, by bisection) until the least loaded wheel carries ``fraction`` of its static load
    (negative: lifted off the road), and that load fraction computed by the Python forces."""
    forces, m = system.forces, system.layout.n_mech
    y = next(_states(system.layout, 1, seed))

    def load(psi):
        y[forces.i_psi] = psi
        system.set_state(y)
        states = []
        forces.evaluate(0.0, [float(v) for v in y[:m]] + [0.0, 0.0], [0.0] * (m + 2), states, python=True)
        return min(s.vertical_force for s in states) / forces.tyres[0].static_load - fraction
    lo, hi = 0.0, 0.2 if load(0.2) < 0.0 else -0.2
    for _ in range(50):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if load(mid) > 0.0 else (lo, mid)
    return y.copy(), load(hi) + fraction       # load() leaves y rolled to hi


@pytest.mark.parametrize("names", ["", "all"])
def test_twin_equals_exudyn_with_a_lifted_wheel(names):
    """A wheel lifted off the road (no grip; with hcl and rl its contact and relaxation lengths are those at 1 % of
    the load): the twin covers it (no difference fallback) and equals Exudyn.  The state: rolled until the right
    wheel's load is -20 % of the static one, about 4 mm off the road, far beyond the differences' 1e-4 step."""
    from reduced_model.model import Effects
    system = MbsModel(effects=Effects.parse(names) if names else Effects(), fidelity=FULL).system(
        TyrePressures.uniform(1.5 * BAR), speed_is_time)
    exudyn, twin = MbsEvaluator(system), twin_of(system)
    y, fraction = _rolled(system, -0.2)
    assert fraction <= -0.2 + 1e-9
    for speed in (5.0, 33.0):
        f, J, Jv, ok = twin.rhs_and_jacobian(y, speed)
        assert ok
        fe = exudyn.rhs(y, speed)
        assert np.max(np.abs(f - fe)) <= 1e-10 * np.max(np.abs(fe))
        Je = exudyn.jacobian(y, speed)
        assert np.max(np.abs(J - Je)) <= 5e-9 * np.max(np.abs(Je))


def test_only_states_about_a_lift_off_are_near_the_kink():
    """The band whose Jacobians are differenced (:meth:`mbs_shimmy.twin.Twin._near_kink`): a wheel carrying
    within 2 % of its static load of zero, lifted or not; a wheel lifted by 20 % of it or loaded normally keeps its
    exact Jacobian.  The twin's load output is the Python forces' load (to rounding), and a batch of more states
    than one mapped call takes (:data:`mbs_shimmy.twin.CHUNK`) equals the states one by one."""
    from mbs_shimmy.twin import CHUNK
    system = MbsModel(fidelity=FULL).system(TyrePressures.uniform(1.5 * BAR), speed_is_time)
    twin = twin_of(system)
    fractions = (-0.2, -0.015, 0.015, 0.3)
    states = [_rolled(system, f) for f in fractions]
    Y = np.array([y for y, _ in states])
    f, J, Jv, ok, near = twin.rhs_and_jacobians(Y, 20.0)
    assert ok.all()
    assert near.tolist() == [False, True, True, False]
    _, _, x = twin._batch("f", Y, 20.0)[0]
    np.testing.assert_allclose(np.min(x[2:], axis=0), [load for _, load in states], rtol=1e-9, atol=1e-12)
    big = np.concatenate([Y] * (CHUNK // 2 + 3))             # more than two chunks
    fb, okb = twin.rhs_batch(big, 20.0, pad=True)
    assert len(big) > 2 * CHUNK and okb.all()
    # to rounding: the batch may be the first evaluation of the compiled library instead of the virtual machine
    np.testing.assert_allclose(fb, np.concatenate([f] * (CHUNK // 2 + 3)), rtol=1e-12, atol=1e-12 * np.abs(f).max())


def test_one_graph_serves_every_axle_and_pressure(campaign_tool):
    """The graph takes the axle's numbers as an input: another pressure and a random plausible axle of the same
    fidelity evaluate the same graph with other numbers (and equal Exudyn, the tests above)."""
    axle = campaign_tool.draw_axle(np.random.default_rng((30, 1)), "TWIN-1", t0=True)
    twins = [twin_of(MbsModel(params=a.params, fidelity=FULL, dims=a.dims).system(TyrePressures.uniform(p * BAR),
                                                                                  speed_is_time))
             for a, p in ((paper_axle(), 1.5), (paper_axle(), 2.5), (axle, 1.5))]
    assert twins[1].graph is twins[0].graph and twins[2].graph is twins[0].graph
    assert not np.array_equal(twins[0].numbers, twins[1].numbers)
    assert not np.array_equal(twins[0].numbers, twins[2].numbers)


def test_a_compiled_library_equals_the_virtual_machine():
    """twin_library's path (C generated by CasADi, compiled, loaded) on a small function with the twin's kinds
    of operations; skipped without a C compiler (the twin then stays in the virtual machine)."""
    import casadi as ca

    from mbs_shimmy import twin_library
    if twin_library.compiler() is None:
        pytest.skip("no C compiler")
    x, p = ca.SX.sym("x", 3), ca.SX.sym("p", 2)
    f = ca.vertcat(ca.sin(x[0]) * p[0], ca.atan(x[1] / p[1]), ca.sqrt(x[2] ** 2 + p[0]))
    fn = ca.Function("small", [x, p], [f, ca.jacobian(f, x)], {"cse": True})
    built = twin_library.compiled([fn])
    assert built is not None
    X, P = np.array([0.3, -1.2, 2.0]), np.array([1.7, 0.4])
    for a, b in zip(fn(X, P), built["small"](X, P)):
        np.testing.assert_array_equal(np.asarray(a), np.asarray(b))
    assert twin_library.compiled([fn], cached_only=True) is not None     # now on disk


@pytest.mark.slow
def test_the_compiled_twin_equals_exudyn():
    """The full geometry's twin compiled to C (what a continuation evaluates once past
    twin_library.COMPILE_AFTER states; compiling takes about 10 s without the disk cache) equals Exudyn."""
    from mbs_shimmy import twin_library
    if twin_library.compiler() is None:
        pytest.skip("no C compiler")
    system = MbsModel(fidelity=FULL).system(TyrePressures.uniform(1.5 * BAR), speed_is_time)
    graph = twin_of(system).graph
    graph._compile(cached_only=False)
    assert graph.is_compiled
    assert _check(paper_axle(), FULL, jacobian_tol=5e-9) == 3


def test_twin_second_derivative_is_its_jacobian_differentiated():
    """d/de J(y + e v) u from the twin against central differences of the twin's Jacobian and of Exudyn's rhs."""
    system = MbsModel(fidelity=FULL).system(TyrePressures.uniform(1.5 * BAR), speed_is_time)
    twin, exudyn = twin_of(system), MbsEvaluator(system)
    rng = np.random.default_rng(5)
    y = next(_states(system.layout, 1, 5))
    u, v = rng.normal(size=len(y)) * 0.01, rng.normal(size=len(y)) * 0.01
    second = twin.second_derivative(y, 20.0, u, v)
    h = 1e-5
    by_twin = (twin.rhs_and_jacobian(y + h * v, 20.0)[1] - twin.rhs_and_jacobian(y - h * v, 20.0)[1]) @ u / (2 * h)
    np.testing.assert_allclose(second, by_twin, rtol=0, atol=1e-7 * np.max(np.abs(second)))
    # Exudyn: f(y + a u + b v) mixed difference
    a = 1e-3

    def fe(du, dv):
        return exudyn.rhs(y + du * u + dv * v, 20.0)
    mixed = (fe(a, a) - fe(a, -a) - fe(-a, a) + fe(-a, -a)) / (4 * a * a)
    np.testing.assert_allclose(second, mixed, rtol=0, atol=1e-4 * np.max(np.abs(second)))


def test_an_orbit_off_exudyns_equations_is_polished_on_them():
    """The first cycle of the full geometry's yaw branch (continued on the twin) has an Exudyn residual below the
    tolerance; the same orbit with its period 1e-4 too long is far above it, and the check polishes it back onto
    Exudyn's collocation equations at the same speed."""
    import dataclasses

    from axles.units import KMH
    from bifurcation.cycles.branches import start_at_hopf
    from bifurcation.cycles.collocation import Orbit
    from bifurcation.equilibria.hopf import find_hopf_points
    from comparisons.api import family_of
    from comparisons.studies.exudyn_check import RESIDUAL_TOL, checked_on_exudyn, exudyn_residual

    family = family_of(MbsModel(fidelity=FULL), TyrePressures.uniform(1.5 * BAR))
    hopf = find_hopf_points(family, 1.5 * BAR, 30 * KMH, 50 * KMH)[0]
    problem, u0, _ = start_at_hopf(family, hopf)
    point = problem.point(u0)
    assert family.derivatives == "twin and differences"      # twin on the cycle, differences at straight running
    good = checked_on_exudyn(family, point)
    assert good.passed and not good.polished
    o = point.orbit
    off = dataclasses.replace(point, orbit=Orbit(o.mesh, o.nodes, o.period * (1 + 1e-4), o.degree))
    assert exudyn_residual(family, off) > 100 * RESIDUAL_TOL
    fixed = checked_on_exudyn(family, off)
    assert fixed.polished and fixed.passed and fixed.point.p == point.p
    assert abs(fixed.point.period - point.period) < 1e-8 * point.period
