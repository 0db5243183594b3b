"""Error control of the collocation, Hopf ends by the defining system, user points and bounded steps.

Known answers come from normal-form oscillators (r' = r g(r^2, mu), theta' = w: circles of radius sqrt(root of g)
and period 2 pi / w, exactly) and from independent integration of the shimmy model over one period.
"""

import json

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from test_cycles_toy import SHIFT, ToyFamily, W, first_hopf, supercritical

from axles.units import KMH, kmh
from comparisons.cli.main import main
from bifurcation.cycles import collocation as col
from bifurcation.cycles import mesh_adaptation
from bifurcation.cycles.branches import branch_from_hopf, cycle_at, cycle_diagram
from bifurcation.cycles.problem import CycleSettings
from bifurcation.equilibria.hopf import find_hopf_points
from bifurcation.special_points import BranchStatus
from reduced_model.family import SpeedFamily
from reduced_model.model import Effects, ShimmyModel


def circle(r, period, phase, N, degree=4):
    return col.orbit_from_function(
        lambda tau: r * np.column_stack([np.cos(2 * np.pi * tau + phase), np.sin(2 * np.pi * tau + phase)]),
        period, col.uniform_mesh(N), degree)


@pytest.mark.parametrize("N", [4, 8, 16])
def test_error_estimate_tracks_the_true_error_of_a_collocated_circle(N):
    """Collocate the known cycle of the supercritical normal form at mu = 1 on N intervals and compare the
    estimate with the distance to the exact circle (the error at interior points, where maxima are read)."""
    family = ToyFamily(supercritical, 2)
    h = first_hopf(family)
    period = 2 * np.pi / W
    near = cycle_at(family, branch_from_hopf(family, h, 0.0, SHIFT + 1.2).points[-1], SHIFT + 1.0,
                    intervals=N)
    orbit = near.orbit
    tau, x = orbit.sample(64)
    phase = np.arctan2(orbit.nodes[0, 1], orbit.nodes[0, 0])
    # The exact circle with the same phase at tau = 0 (a mesh point, where the error is superconvergent).
    exact = np.column_stack([np.cos(2 * np.pi * tau + phase), np.sin(2 * np.pi * tau + phase)])
    true = np.max(np.abs(x - exact))
    estimate = np.max(mesh_adaptation.error_estimate(orbit))
    assert 0.3 * true <= estimate <= 3.0 * true
    assert mesh_adaptation.relative_error(orbit, np.ones(2)) == pytest.approx(estimate / np.max(orbit.maxima()), rel=1e-12)


def test_error_estimate_converges_at_order_m_plus_1():
    e = [np.max(mesh_adaptation.error_estimate(circle(1.0, 1.0, 0.3, N))) for N in (8, 16, 32)]
    assert np.log2(e[0] / e[1]) == pytest.approx(5.0, abs=0.15)
    assert np.log2(e[1] / e[2]) == pytest.approx(5.0, abs=0.15)


def test_mesh_grows_to_a_tight_tolerance_and_marks_points_that_cannot_reach_it():
    family = ToyFamily(supercritical, 2)
    h = first_hopf(family)
    tight = branch_from_hopf(family, h, 0.0, SHIFT + 2.0, settings=CycleSettings(tolerance=1e-11))
    assert tight.complete and all(p.meets_tolerance for p in tight.points)
    assert max(p.orbit.intervals for p in tight.points) > 40
    last = tight.points[-1]
    assert np.max(last.amplitude) == pytest.approx(np.sqrt(last.p - SHIFT), rel=1e-10)
    capped = branch_from_hopf(family, h, 0.0, SHIFT + 2.0,
                              settings=CycleSettings(tolerance=1e-11, min_intervals=4, max_intervals=6))
    assert capped.complete and not capped.points[-1].meets_tolerance
    assert capped.points[-1].error > 1e-11 and capped.points[-1].orbit.intervals == 6


def isola(X, V):
    """g = mu (1 - mu) - r^2: cycles r^2 = mu (1 - mu) between Hopf points at mu = 0 and mu = 1."""
    x, y = X[0], X[1]
    mu = V - SHIFT
    g = mu * (1.0 - mu) - (x * x + y * y)
    return np.array([g * x - W * y, W * x + g * y])


def test_branch_ends_at_the_hopf_point_of_the_defining_system_even_when_not_listed():
    family = ToyFamily(isola, 2)
    h0, h1 = find_hopf_points(family, 0.0, SHIFT - 0.5, SHIFT + 1.5)
    listed = branch_from_hopf(family, h0, 0.0, SHIFT + 3.0, others=(h1,))
    assert listed.status is BranchStatus.COMPLETE and listed.end is h1
    alone = branch_from_hopf(family, h0, 0.0, SHIFT + 3.0)      # h1 not given: found by its defining system
    assert alone.end is not None and alone.end.p == pytest.approx(SHIFT + 1.0, abs=1e-9)
    assert alone.end.omega == pytest.approx(W, abs=1e-9)
    mid = [p for p in listed.points if abs(p.p - SHIFT - 0.5) < 0.3]
    assert all(np.max(p.amplitude) == pytest.approx(np.sqrt((p.p - SHIFT) * (1 + SHIFT - p.p)), rel=1e-8)
               for p in mid)


@pytest.fixture(scope="module")
def trail025():
    family = SpeedFamily(ShimmyModel().with_params(t0=0.25))
    return family, cycle_diagram(family, 1.5e5, 0.0, 400 * KMH)


def test_user_points_are_the_continuations_own_orbits(trail025):
    family, d = trail025
    pts = d.branches[0].points
    targets = (pts[10].p, pts[40].p, 183 * KMH)
    d2 = cycle_diagram(family, 1.5e5, 0.0, 400 * KMH, at=targets)
    for k in (10, 40):
        u = min(d2.branches[0].user_points, key=lambda x: abs(x.p - pts[k].p))
        assert u.p == pytest.approx(pts[k].p, abs=1e-10)
        assert np.max(np.abs(u.amplitude - pts[k].amplitude)) < 1e-8
        assert abs(u.period - pts[k].period) < 1e-8
        assert np.max(np.abs(u.multipliers - pts[k].multipliers)) < 1e-8
    # 183 km/h lies between T1 and S1 on the yaw branch (stable and unstable cycle) and on the tramp branch.
    at183 = [[p for p in b.user_points if abs(kmh(p.p) - 183) < 1e-9] for b in d2.branches]
    assert [len(a) for a in at183] == [2, 1]
    assert sorted(p.stable for p in at183[0]) == [False, True] and at183[1][0].stable


def test_max_step_makes_the_output_denser_and_moves_no_special_point(trail025):
    family, d = trail025
    b = d.branches[1]                       # the tramp branch, with S2 and T2
    others = tuple(h for h in d.hopf if h is not b.start)
    for bd in [branch_from_hopf(family, b.start, 0.0, 400 * KMH, others=others, max_step=5 * KMH)]:
        speeds = np.array([kmh(p.p) for p in bd.points])
        assert len(bd.points) > len(b.points) and np.max(np.abs(np.diff(speeds))) <= 5.0 + 1e-9
        for s in b.special_points:
            (t,) = [x for x in bd.special_points if x.kind is s.kind]
            assert t.p == pytest.approx(s.p, abs=1e-6 * KMH)


def test_hard_case_at_walking_pace_meets_its_tolerance():
    """hcl,pt at 0.25 bar: the tramp branch runs down to 0.5 km/h, where the orbit is far from harmonic (40 fixed
    intervals left a return error of 2.5e-4 rad).  The adapted orbit closes on itself under DOP853 integration."""
    family = SpeedFamily(ShimmyModel(effects=Effects.parse("hcl,pt")))
    d = cycle_diagram(family, 0.25e5, 0.0, 400 * KMH)
    assert d.complete
    low = min((b.points[-1] for b in d.branches), key=lambda p: p.p)
    assert kmh(low.p) == pytest.approx(0.5, abs=1e-9) and low.meets_tolerance
    assert low.orbit.intervals > 40
    x0 = low.orbit.nodes[0]
    sol = solve_ivp(lambda t, x: family.rhs(x, low.p, low.q), (0, low.period), x0, method="DOP853",
                    rtol=1e-12, atol=1e-14)
    assert np.max(np.abs(sol.y[:, -1] - x0)) < 1e-7
    assert all(p.meets_tolerance for b in d.branches for p in b.points)


def test_cli_at_a_single_speed(capsys):
    assert main(["cycles", "--pressure", "1.5", "--vmin", "60", "--vmax", "60", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    (entry,) = out["at"]
    (orbit,) = entry["orbits"]
    assert entry["speed_kmh"] == 60 and orbit["speed_kmh"] == pytest.approx(60, abs=1e-9)
    assert {"period_s", "frequency_hz", "max_theta1_deg", "max_theta2_deg", "max_psi_deg", "multipliers",
            "stable", "error_estimate", "meets_tolerance"} <= set(orbit)
    assert orbit["frequency_hz"] == pytest.approx(1 / orbit["period_s"]) and len(orbit["multipliers"]) == 8
    assert orbit["stable"] and out["all_meet_tolerance"]
    branch = out["branches"][0]
    assert branch["points"][0]["kind"] == "hopf" and branch["points"][-1]["kind"] == "hopf"
    assert branch["points"][0]["speed_kmh"] == pytest.approx(branch["from_hopf_kmh"])
    assert branch["points"][0]["largest_multiplier_abs"] == pytest.approx(1.0, abs=1e-9)
    # The located orbit lies between its neighbours on the branch.
    cycles = [p for p in branch["points"] if p["kind"] == "cycle"]
    k = next(i for i, p in enumerate(cycles) if p["speed_kmh"] > 60)
    lo, hi = sorted((cycles[k - 1]["max_theta2_deg"], cycles[k]["max_theta2_deg"]))
    assert lo <= orbit["max_theta2_deg"] <= hi


@pytest.mark.parametrize("args, fragment", [
    (["--at", "500"], "outside the window"),
    (["--at", "0.1"], "at least 0.5 km/h"),
    (["--at", "60,x"], "separated by commas"),
    (["--vmin", "60", "--vmax", "60", "--at", "70"], "differs"),
    (["--tolerance", "0"], "must be positive"),
    (["--max-step", "-1"], "must be positive"),
])
def test_cli_bad_speeds_exit_2(args, fragment, capsys):
    try:
        code = main(["cycles", "--pressure", "1.5", *args])
    except SystemExit as exc:      # argparse's own errors
        code = exc.code
    assert code == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and fragment in err[0]


def test_orbits_near_a_hopf_end_follow_the_square_root_law():
    """2.5 bar: the branch returns to HB2 (70.5006 km/h); the orbits asked for between its last computed cycle
    and HB2 (from that cycle shrunk towards HB2, then Newton) obey amp^2 proportional to the distance to HB2."""
    family = SpeedFamily(ShimmyModel())
    speeds = (70.45 * KMH, 70.49 * KMH, 70.5 * KMH)
    d = cycle_diagram(family, 2.5e5, 0.0, 400 * KMH, at=speeds)
    (b,) = d.branches
    assert kmh(b.end.p) == pytest.approx(70.5006, abs=1e-4)
    assert kmh(b.points[-1].p) < 70.45
    at = {round(kmh(p.p), 6): p for p in b.user_points}
    assert set(at) == {70.45, 70.49, 70.5}
    amp2 = {v: p.max_abs("theta1") ** 2 for v, p in at.items()}
    ratio = amp2[70.49] / amp2[70.5]
    assert ratio == pytest.approx((kmh(b.end.p) - 70.49) / (kmh(b.end.p) - 70.5), rel=0.02)
