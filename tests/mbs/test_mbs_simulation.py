"""Simulation of the multibody model: step convergence, an independent integrator, poses, faults, bad input."""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from axles.units import BAR, KMH
from mbs_shimmy import Fidelity
from mbs_shimmy import forces as forces_module
from mbs_shimmy.linearisation import MbsFamily
from mbs_shimmy.model import MbsModel
from mbs_shimmy.simulation import DEFAULT_STEP, convergence, extended_states, integrate
from reduced_model.model import Effects
from axles.parameters import YANG2024, ParameterError
from reduced_model.trajectory import SimulationStatus, SpeedSchedule
from axles.pressures import TyrePressures


def _x0(**values):
    from reduced_model.model import STATE_NAMES
    x = np.zeros(8)
    for k, v in values.items():
        x[STATE_NAMES.index(k)] = v
    return x


def test_default_step_converged_at_100_kmh():
    """The benchmark case (1.5 bar, 100 km/h, full geometry): halving the default step changes nothing above
    1e-4 of each state's amplitude."""
    kwargs = dict(effects=Effects(), fidelity=Fidelity.full(), pressures=TyrePressures.uniform(1.5 * BAR),
                  schedule=SpeedSchedule.constant(100 * KMH), x0=_x0(theta1=0.01), duration=3.0, poses=False,
                  output_interval=2 * DEFAULT_STEP)
    coarse = integrate(step=DEFAULT_STEP, **kwargs)
    fine = integrate(step=DEFAULT_STEP / 2, **kwargs)
    c = convergence(coarse, fine)
    assert c.converged and c.max_relative_difference < 1e-4
    assert c.step == pytest.approx(DEFAULT_STEP)
    assert "fixed step 0.001 s" in coarse.integrator


def test_full_simulation_matches_independent_integrator():
    """Exudyn's RK44 on the tree against scipy's DOP853 on the same Exudyn-evaluated right-hand side
    (mass matrix of the current configuration, all forces): checks the solver path, not the model."""
    V, p = 60 * KMH, 1.5 * BAR
    x0 = _x0(theta1=0.05, theta2_dot=1.0, psi=0.01)
    family = MbsFamily(MbsModel(fidelity=Fidelity.full()))
    L = family.layout
    # the axle's lateral travel, its bounce and the gear, too
    x0 = np.concatenate([x0, [0.001, 0.0, -0.002, 0.05, 0.002, -0.1]])
    ref = solve_ivp(lambda t, y: family.rhs_mbs(y, V, p), (0.0, 0.6), x0[L.x_to_y], method="DOP853",
                    rtol=1e-10, atol=1e-12, dense_output=True)
    traj = integrate(fidelity=Fidelity.full(), pressures=TyrePressures.uniform(p), schedule=SpeedSchedule.constant(V), x0=x0, duration=0.6,
                    poses=False)
    xr = ref.sol(traj.t).T[:, L.y_to_x]
    xs = extended_states(traj)
    assert np.all(np.max(np.abs(xs - xr), axis=0) <= 1e-4 * np.max(np.abs(xr), axis=0))


def test_poses_and_contact_forces_in_extra():
    V = 80 * KMH
    traj = integrate(fidelity=Fidelity.full(), pressures=TyrePressures.uniform(2.0 * BAR), schedule=SpeedSchedule.constant(V),
                    x0=_x0(theta1=0.03, psi=0.005), duration=0.2)
    n = len(traj.t)
    bodies = traj.extra["bodies"]
    assert set(bodies) == {"axle", "knuckle_right", "knuckle_left", "wheel_right", "wheel_left"}
    for b in bodies.values():
        assert b["position"].shape == (n, 3) and b["quaternion_xyzw"].shape == (n, 4)
        assert np.allclose(np.linalg.norm(b["quaternion_xyzw"], axis=1), 1.0)
    for side in ("right", "left"):
        # wheel centre l outboard of the kingpin point, contact on the road, vertical force near the static load
        d = bodies[f"wheel_{side}"]["position"] - bodies[f"knuckle_{side}"]["position"]
        assert np.allclose(np.linalg.norm(d, axis=1), YANG2024.l)
        contact = traj.extra["contact"][side]
        assert np.allclose(contact["point"][:, 2], 0.0)
        assert contact["force"].shape == (n, 3)
        assert np.all(np.abs(contact["force"][:, 2] - YANG2024.Fz) < 0.5 * YANG2024.Fz)
    assert traj.extra["links"]["tie_rod"].shape == (n, 2, 3)
    assert traj.extra["links"]["drag_link"].shape == (n, 2, 3)
    assert np.allclose(traj.extra["travel"], V * traj.t)
    # the wheels spin at V/R: the wheel's rotation about its axis advances by V/R per second
    q0, q1 = bodies["wheel_right"]["quaternion_xyzw"][[0, 10]]
    angle = 2 * math.acos(min(1.0, abs(float(np.dot(q0, q1)))))
    assert angle == pytest.approx(V / YANG2024.R * (traj.t[10] - traj.t[0]), rel=0.05)


def test_speed_changes_matter_only_without_quasi_steady_assumption():
    ramp = SpeedSchedule.ramp(100 * KMH, 20 * KMH, 1.0)
    base = dict(pressures=TyrePressures.uniform(1.5 * BAR), x0=_x0(theta1=0.01), duration=1.0, poses=False)
    steady = Fidelity.full().assumed | {Fidelity.parse("quasi_steady_speed").single()}
    a = integrate(fidelity=Fidelity(steady), schedule=ramp, **base)
    b = integrate(fidelity=Fidelity.full(), schedule=ramp, **base)
    assert np.max(np.abs(a.x - b.x)) > 1e-6      # braking loads the knuckles
    c = integrate(fidelity=Fidelity(steady), schedule=SpeedSchedule.constant(60 * KMH), **base)
    d = integrate(fidelity=Fidelity.full(), schedule=SpeedSchedule.constant(60 * KMH), **base)
    assert np.array_equal(c.x, d.x)


def test_divergence_is_reported_with_time_and_state():
    """Steering nearly free (k1 = k2 = 1 N m/rad, no dampers): the wheels fall over within a second."""
    params = YANG2024.replace(k1=1.0, k2=1.0, c1=0.0, c2=0.0, c4=0.0)
    traj = integrate(params, Effects(), Fidelity.full(), TyrePressures.uniform(1.5 * BAR), SpeedSchedule.constant(100 * KMH),
                    _x0(theta1=0.1), 5.0, poses=False)
    assert traj.status is SimulationStatus.DIVERGED and not traj.complete
    assert "diverged at t = " in str(traj.message) and "theta1 = " in str(traj.message)
    stop = float(str(traj.message).split("t = ")[1].split(" s")[0])
    assert 0.0 < stop < 5.0 and traj.t[-1] == pytest.approx(stop, abs=2e-3)
    assert len(traj.x) == len(traj.t) == len(traj.speed) and np.max(np.abs(traj.x[:, 0])) > 0.5


def test_solver_failure_keeps_partial_trajectory(monkeypatch):
    original = forces_module.AxleForces.evaluate

    def failing(self, t, q, qd, states=None, **options):
        if t > 0.05:
            raise FloatingPointError("tyre force not finite")
        return original(self, t, q, qd, states, **options)

    monkeypatch.setattr(forces_module.AxleForces, "evaluate", failing)
    traj = integrate(duration=0.2, poses=False)
    assert traj.status is SimulationStatus.SOLVER_FAILED
    assert "t = 0.05" in str(traj.message) and "FloatingPointError: tyre force not finite" in str(traj.message)
    assert "last stored t = 0.049" in str(traj.message)
    assert 0.04 < traj.t[-1] <= 0.05 and traj.x.shape == (len(traj.t), 8)


@pytest.mark.parametrize("kwargs,match", [
    (dict(duration=0.0), "duration"),
    (dict(duration=-1.0), "duration"),
    (dict(method="RK5"), "unknown integrator"),
    (dict(step=0.0), "step"),
    (dict(step=math.nan), "step"),
    (dict(x0=np.zeros(5)), "initial state"),
    (dict(x0=np.full(8, np.inf)), "initial state"),
    (dict(pressures=TyrePressures.uniform(0.0)), "pressure must be positive"),
    (dict(output_interval=1e-4), "output interval"),
])
def test_bad_input(kwargs, match):
    with pytest.raises(ParameterError, match=match):
        integrate(**{"duration": 0.1, "poses": False, **kwargs})


def test_benchmark_step_keeps_1e4_accuracy():
    """The benchmark's setting (RK67, h = 1/240 s) over its whole 10 s run at 1.5 bar, 100 km/h, full geometry:
    within 1e-4 of each state's amplitude of the run at h/4, and the differences shrink at the method's order."""
    from mbs_shimmy.simulation import FAST_METHOD, FAST_STEP
    kwargs = dict(effects=Effects(), fidelity=Fidelity.full(), pressures=TyrePressures.uniform(1.5 * BAR),
                  schedule=SpeedSchedule.constant(100 * KMH), x0=_x0(theta1=0.01), duration=10.0, poses=False,
                  method=FAST_METHOD, output_interval=FAST_STEP)
    runs = [integrate(step=FAST_STEP / k, **kwargs) for k in (1, 2, 4)]
    coarse, middle = convergence(runs[0], runs[2]), convergence(runs[1], runs[2])
    assert coarse.max_relative_difference < 1e-4
    # RK67 is sixth order: h -> h/2 cuts the error ~64x, so (h vs h/4) / (h/2 vs h/4) is about 65
    assert 30 < coarse.max_relative_difference / middle.max_relative_difference < 130


def test_quaternions_of_rotation_matrices_in_every_branch_of_shepperds_method():
    """Against scipy's rotations (an independent implementation): random rotations, and half turns about x, y and
    z, where the trace is -1 and each of the other three branches must serve."""
    from scipy.spatial.transform import Rotation

    from mbs_shimmy.geometry import quaternions_xyzw
    rotations = Rotation.concatenate([Rotation.random(200, random_state=3),
                                      Rotation.from_rotvec(np.array([[math.pi, 0, 0], [0, math.pi, 0], [0, 0, math.pi],
                                                                     [3.1, 0.1, 0], [0, 3.1, 0.1], [0.1, 0, 3.1]]))])
    q = quaternions_xyzw(rotations.as_matrix())
    assert np.allclose(np.linalg.norm(q, axis=1), 1.0)
    assert np.allclose(Rotation.from_quat(q).as_matrix(), rotations.as_matrix(), atol=1e-12)
