"""The `full_geometry` verify section's logic on small inputs (the section itself, on the paper's axle at 1.5 bar,
runs in the slow suite: a branch of the full geometry costs minutes).

The diagrams here are built by hand from the toolkit's own result types: a branch of stable and unstable cycles
with a cycle fold, Hopf points at its ends, so that every rule can be checked against an answer read off the
construction.
"""

import math
from types import SimpleNamespace

import numpy as np
import pytest

from axles.units import KMH
from comparisons.verify.orbit_checks import (
    LEFT_TOL,
    ORBIT_TOL,
    OrbitCheck,
    beyond_fold,
    bracket_special_point,
    check_orbit,
    decides_within,
    sample_orbits,
    undecided_sides,
)
from comparisons.verify.plan import bistable_windows as plan_windows
from comparisons.studies.kick import bistable_speeds, bistable_windows, stable_straight_running, stable_stretches
from comparisons.studies.limit_cycle import SteadyAmplitude
from bifurcation.cycles.problem import CycleBranch, CycleDiagram, CyclePoint
from bifurcation.equilibria.hopf import HopfPoint
from bifurcation.special_points import BranchStatus, PointKind, PointStatus, SpecialPoint
from reduced_model.family import SpeedFamily
from reduced_model.model import STATE_NAMES, ShimmyModel


def cycle(speed_kmh: float, theta1: float, stable: bool, hz: float = 6.0) -> CyclePoint:
    amplitude = np.zeros(len(STATE_NAMES))
    amplitude[0] = theta1
    orbit = SimpleNamespace(nodes=np.tile(amplitude, (4, 1)))
    multipliers = np.array([1.0] + [0.3 if stable else 3.0] + [0.1] * 6, complex)
    return CyclePoint(speed_kmh * KMH, 1.5e5, 1.0 / hz, amplitude, multipliers, stable=stable, orbit=orbit,
                      names=STATE_NAMES)


def hopf(speed_kmh: float, l1: float) -> HopfPoint:
    return HopfPoint(speed_kmh * KMH, 1.5e5, 2 * math.pi * 6.0, l1, np.zeros(8))


def subcritical_diagram() -> CycleDiagram:
    """Straight running unstable above 40 km/h (subcritical Hopf point there); the unstable cycles born at it
    run down to a fold at 30 km/h and turn back stable up to 80 km/h."""
    unstable = [cycle(v, 0.01 + 0.001 * (40 - v), False) for v in (39.0, 36.0, 33.0, 30.5)]
    stable = [cycle(v, 0.03 + 0.001 * (v - 30), True) for v in (30.5, 35.0, 45.0, 60.0, 80.0)]
    fold = SpecialPoint(PointKind.CYCLE_FOLD, 30.0 * KMH, 1.5e5, (0.0, 1.0), PointStatus.LOCATED,
                        {"amplitude": stable[0].amplitude, "cycle": cycle(30.0, 0.02, False)})
    branch = CycleBranch("speed", tuple(unstable + stable), (fold,), BranchStatus.COMPLETE, "left the window",
                         start=hopf(40.0, +1e-3))
    return CycleDiagram(1.5e5, 0.0, 100.0 * KMH, (hopf(40.0, +1e-3),), (branch,))


class StraightRunning:
    """A family whose straight running is stable below 40 km/h and unstable above (linear_matrix only)."""

    def linear_matrix(self, speed, q):
        return np.diag([speed - 40.0 * KMH, -1.0])


def test_bistable_window_of_a_subcritical_onset_counts_straight_running():
    d = subcritical_diagram()
    assert stable_stretches(d) == [(30.5 * KMH, 80.0 * KMH)]
    assert stable_straight_running(StraightRunning(), d) == [(0.0, 40.0 * KMH)]
    # Stable straight running and the stable cycles coexist from the fold's last computed cycle to the Hopf point.
    assert bistable_windows(d, StraightRunning()) == [(30.5 * KMH, 40.0 * KMH)]
    assert bistable_speeds(StraightRunning(), d) == [pytest.approx(35.25 * KMH)]
    # The plan asks for two stable cycles: one stretch alone is no window.
    assert bistable_windows(d) == [] and plan_windows(d) == []


def test_two_overlapping_stable_stretches_make_one_window():
    a = CycleBranch("speed", tuple(cycle(v, 0.02, True) for v in (50.0, 60.0, 70.0)), (), BranchStatus.COMPLETE, "")
    b = CycleBranch("speed", tuple(cycle(v, 0.05, s) for v, s in ((55.0, False), (65.0, True), (90.0, True))), (),
                    BranchStatus.COMPLETE, "")
    d = CycleDiagram(1.5e5, 0.0, 100.0 * KMH, (), (a, b))
    assert bistable_windows(d) == [(65.0 * KMH, 70.0 * KMH)]
    assert plan_windows(d) == [(65.0 * KMH, 70.0 * KMH)]
    assert bistable_windows(d, min_width=6.0 * KMH) == []


def run(theta1: float, hz: float = 6.0, settled: bool = True) -> SteadyAmplitude:
    return SteadyAmplitude(0.0, theta1, 0.0, settled, np.zeros(8), "", hz)


def test_stable_orbit_passes_only_within_its_tolerance_in_amplitude_and_frequency():
    c = cycle(50.0, 0.1, True)
    assert OrbitCheck(c, run(0.1 * (1 + 0.9 * ORBIT_TOL)), c.p).ok
    assert not OrbitCheck(c, run(0.1 * (1 + 1.1 * ORBIT_TOL)), c.p).ok
    assert not OrbitCheck(c, run(0.1, hz=6.0 * (1 + 1.1 * ORBIT_TOL)), c.p).ok
    assert not OrbitCheck(c, run(0.1, settled=False), c.p).ok
    assert not OrbitCheck(c, run(math.nan), c.p).ok


def test_unstable_orbit_passes_only_when_the_run_leaves_it():
    c = cycle(50.0, 0.1, False)
    assert OrbitCheck(c, run(0.0), c.p).ok                     # decayed to straight running
    assert OrbitCheck(c, run(0.3), c.p).ok                     # went to a larger cycle
    assert not OrbitCheck(c, run(0.1 * (1 + 0.5 * LEFT_TOL)), c.p).ok


def test_fold_is_bracketed_by_a_stable_cycle_and_a_run_past_it():
    d = subcritical_diagram()
    branch = d.branches[0]
    (fold,) = branch.special_points
    assert beyond_fold(branch, fold) < fold.p           # the branch's cycles lie above 30 km/h
    starts = []

    def settle(speed):
        def go(x0):
            starts.append((speed, x0[0]))
            return run(0.0 if speed < 30.0 * KMH else 0.03 + 0.001 * (speed / KMH - 30))
        return go

    checks = dict(bracket_special_point(settle, branch, fold))
    assert set(checks) == {"stable side", "past the fold"}
    assert checks["stable side"].cycle.p == pytest.approx(30.5 * KMH) and checks["stable side"].ok
    assert checks["past the fold"].speed < fold.p and checks["past the fold"].ok
    # Every run starts 2 % inside the orbit it checks.
    assert starts[0][1] == pytest.approx(0.98 * checks["stable side"].cycle.max_abs("theta1"))
    assert check_orbit(settle, branch.points[5]).ok


def slow_cycle(c: CyclePoint) -> CyclePoint:
    """The same cycle with its largest nontrivial multiplier at 0.999: a 12 s run cannot decide it."""
    return CyclePoint(c.p, c.q, c.period, c.amplitude, np.array([1.0, 0.999] + [0.1] * 6), stable=c.stable,
                      orbit=c.orbit, names=STATE_NAMES)


def test_a_fold_side_no_run_can_decide_is_named_not_run():
    d = subcritical_diagram()
    branch = d.branches[0]
    (fold,) = branch.special_points
    settle = lambda speed: (lambda x0: run(0.0 if speed < 30.0 * KMH else 0.03))   # noqa: E731
    assert undecided_sides(branch, fold) == []
    # The nearest stable cycle undecidable: the next decidable one along the branch brackets the fold instead.
    points = list(branch.points)
    points[4] = slow_cycle(points[4])            # the stable 30.5 km/h cycle
    nearer = CycleBranch("speed", tuple(points), branch.special_points, branch.status, branch.message,
                         start=branch.start)
    checks = dict(bracket_special_point(settle, nearer, fold))
    assert checks["stable side"].cycle.p == pytest.approx(35.0 * KMH) and undecided_sides(nearer, fold) == []
    # Every stable cycle next to it undecidable: no run on that side, and the side is named.
    points[5] = slow_cycle(points[5])
    points[6] = slow_cycle(points[6])
    none = CycleBranch("speed", tuple(points), branch.special_points, branch.status, branch.message,
                       start=branch.start)
    assert set(dict(bracket_special_point(settle, none, fold))) == {"past the fold"}
    assert undecided_sides(none, fold) == ["stable side"]


def test_orbits_are_sampled_by_stability_where_a_run_can_decide():
    branch = subcritical_diagram().branches[0]
    stable = sample_orbits(branch, 3, stable=True)
    assert [p.p / KMH for p in stable] == pytest.approx([30.5, 45.0, 80.0])
    assert len(sample_orbits(branch, 10, stable=False)) == 4
    # Next to a Hopf point (|mu| near 1) a 12 s run cannot tell: such an orbit is not sampled.
    slow = cycle(40.5, 0.001, True)
    slow = CyclePoint(slow.p, slow.q, slow.period, slow.amplitude, np.array([1.0, 0.999] + [0.1] * 6),
                      stable=True, orbit=slow.orbit, names=STATE_NAMES)
    assert not decides_within(slow, 12.0) and decides_within(branch.points[5], 12.0)


def _kick(status):
    from comparisons.studies.kick import Attractor, KickThreshold
    return KickThreshold(60.0 * KMH, Attractor("straight running", 0.0, 0.0), Attractor("cycle of branch 1", 0.1, 0.05),
                         0.03, status, 0.04, 0.0408, None, None, 9)


def test_figure_of_both_models_branches_with_their_kicks(tmp_path):
    from comparisons.figures.cycle_plots import kick_marks, plot_cycle_diagram, plot_model_branches
    from comparisons.studies.kick import KickStatus
    found, not_left = _kick(KickStatus.FOUND), _kick(KickStatus.NOT_LEFT)
    # Only a bracketed threshold is drawn, at its speed and at the geometric middle of its bracket.
    ((v, a, text),) = kick_marks([found, not_left])
    assert v == pytest.approx(60.0) and a == pytest.approx(np.degrees(np.sqrt(0.04 * 0.0408)))
    assert text == f"kick {a:.2f} deg"
    path = tmp_path / "both.png"
    d = subcritical_diagram()
    plot_model_branches([("reduced model", d, "C0", [found]), ("full geometry, MBS", d, "C3")], str(path),
                        title="test")
    assert path.stat().st_size > 10_000
    one = tmp_path / "one.png"
    plot_cycle_diagram(d, SpeedFamily(ShimmyModel()), str(one), kicks=[found])
    assert one.stat().st_size > 10_000


@pytest.mark.slow
def test_section_on_the_paper_axle_at_1_5_bar(tmp_path):
    """The whole section at one case (a full-geometry branch: about 1-3 minutes on 2 cores)."""
    from comparisons.verify.context import Context
    from comparisons.verify.full_geometry import full_geometry_section
    from comparisons.verify.plan import Case, CaseKind, Plan
    from comparisons.verify.report import CheckStatus
    plan = Plan((Case(1.5, 1.5, CaseKind.PAPER, "figure 4a"),), ())
    section = full_geometry_section(Context(out=str(tmp_path), quick=False, plan=plan, recordings=False))
    rows = {r.cells["what"]: r for r in section.rows}
    assert not [r for r in section.rows if r.status is CheckStatus.FAIL]
    assert rows["HB1"].cells["criticality"] == rows["HB2"].cells["criticality"] == "supercritical"
    assert rows["HB1"].cells["speed_kmh"] == pytest.approx(39.2273, abs=1e-3)
    assert {r.status for w, r in rows.items() if w.startswith("HB1,") or w.startswith("HB2,")} == {CheckStatus.PASS}
    stable = [r for r in section.rows if r.cells["what"].endswith("stable orbit")
              and not r.cells["what"].endswith("unstable orbit")]
    assert len(stable) >= 3 and all(r.status is CheckStatus.PASS for r in stable)
    assert all(r.cells["theta1_diff"] <= ORBIT_TOL and r.cells["frequency_diff"] <= ORBIT_TOL for r in stable)
    assert "bistable window: none" in rows and "supercritical" in rows["bistable window: none"].note
    assert section.figures == ("full_geometry_1.5bar.png",) and (tmp_path / section.figures[0]).stat().st_size


def test_ramps_through_a_subcritical_window_start_on_straight_running():
    """Below the window straight running is the state (its stable stretch reaches lower), above it the cycle:
    the ramp up leaves straight running through the Hopf point, the ramp down the cycle through the fold (where
    each jumps is information: a ramp's jump speed is not well posed)."""
    from axles.axle import AxleData
    from comparisons.verify.full_jumps import full_jump_setup
    from comparisons.verify.jump_experiments import ramps
    from comparisons.verify.plan import BistableCase
    from reduced_model.modes import Mode
    d = subcritical_diagram()
    (window,) = bistable_windows(d, StraightRunning())
    setup = full_jump_setup(BistableCase(AxleData(), 1.5, 30.5, 40.0, "test", d), StraightRunning(), d, window)
    assert (setup.low, setup.high) == pytest.approx((30.0, 40.0))        # the fold S1 and the Hopf point
    assert (setup.below_mode, setup.above_mode) == (Mode.NONE, Mode.YAW)
    assert (setup.v_lo, setup.v_hi) == pytest.approx((10.0, 60.0))
    up, down = ramps(setup, 1.0)
    assert (up.before, up.after, up.edge) == (Mode.NONE, Mode.YAW, pytest.approx(40.0))
    assert (down.before, down.after, down.edge) == (Mode.YAW, Mode.NONE, pytest.approx(30.0))


def test_the_plans_bistable_case_on_another_axle_is_named_by_what_differs():
    from axles.axle import AxleData
    from comparisons.verify.full_geometry_rows import Where
    from comparisons.verify.plan import BistableCase
    where = Where.of_bistable(BistableCase(AxleData().with_overrides({"t0": 0.25}), 1.5, math.nan, math.nan, "fig 9a"))
    assert where.label == "1.5 bar, t0 = 0.25" and where.pressures.right == where.pressures.left == pytest.approx(1.5e5)
    assert where.family.model.params.t0 == 0.25 and where.reduced_family.model.params.t0 == 0.25


# slow (30 s idle): the same kick, bracketed by two runs, is checked in CI by
# tests/studies/test_kick.py::test_kick_in_the_bistable_window_is_bracketed_by_two_runs
@pytest.mark.slow
def test_jumps_section_gives_the_reduced_models_kick(tmp_path):
    """verify's bistable jumps (full mode) carry the reduced model's kick, bracketed by two of its runs."""
    from axles.axle import AxleData
    from comparisons.verify.context import Context
    from comparisons.verify.cycles import _kick_rows
    from comparisons.verify.jump_experiments import jump_setup
    from comparisons.verify.plan import BistableCase, Plan
    from comparisons.verify.report import CheckStatus
    case = BistableCase(AxleData().with_overrides({"t0": 0.25}), 1.5, math.nan, math.nan, "figures 9a-11")
    setup = jump_setup(case, True)
    (row,) = _kick_rows(Context(out=str(tmp_path), quick=False, plan=Plan((), ()), recordings=False), setup)
    assert row.status is CheckStatus.PASS, row.note
    assert setup.low < float(row.cells["run"].split()[2]) < setup.high     # in the middle of the window
    stays = float(row.note.split("theta1 of ")[1].split(" deg")[0])
    leaves = float(row.note.split("deg stays on ")[1].split(", ")[1].split(" deg")[0])
    assert stays < row.cells["kick_deg"] < leaves and leaves / stays < 1.03


def test_a_window_too_narrow_to_resolve_gets_no_ramps_and_no_kick(tmp_path):
    """Next to a degenerate Hopf point the fold lies within a hair of it (the full geometry at t0 = 0.25 m: 6e-5
    km/h at 3.56 km/h): the window is reported, but no ramp or kick can resolve it."""
    from axles.axle import AxleData
    from comparisons.verify.context import Context
    from comparisons.verify.full_geometry_rows import MIN_WINDOW_KMH, Where, window_rows
    d = subcritical_diagram()
    branch = d.branches[0]
    near = 40.0 - 0.4 * MIN_WINDOW_KMH
    points = [c for c in branch.points if not c.stable] + [cycle(near, 0.03, True), cycle(80.0, 0.05, True)]
    narrow = CycleDiagram(d.q, d.p_min, d.p_max, d.hopf, (CycleBranch("speed", tuple(points), branch.special_points,
                                                                     branch.status, branch.message,
                                                                     start=branch.start),))
    ((a, b),) = bistable_windows(narrow, StraightRunning())
    assert (b - a) / KMH < MIN_WINDOW_KMH
    rows, recordings, found = window_rows(Context(out=str(tmp_path), quick=False), StraightRunning(),
                                          Where("test", AxleData(), 1.5e5, 1.5), narrow)
    (row,) = rows
    assert row.cells["what"].startswith("bistable window") and "neither is run" in row.note
    assert recordings == [] and found == []


def test_where_l1_is_not_well_posed_the_criticality_column_is_the_branchs():
    """The full geometry's camber force puts a kink at straight running: l1's sign is no criticality there, and the
    Hopf row's criticality comes from its cycle branch, or is left undetermined without one."""
    import types

    from bifurcation.special_points import Criticality
    from comparisons.studies.onset import BranchOnset, onset_criticality
    hopf = types.SimpleNamespace(criticality=Criticality.SUBCRITICAL)
    stable = BranchOnset(Criticality.SUPERCRITICAL, "the cycles born there are stable")
    assert onset_criticality(hopf, stable, kinked=True) == (Criticality.SUPERCRITICAL, "branch")
    assert onset_criticality(hopf, None, kinked=True) == (None, "branch")
    assert onset_criticality(hopf, stable, kinked=False) == (Criticality.SUBCRITICAL, "l1")
    assert stable.text == "its branch: the cycles born there are stable (supercritical by its branch)"


def test_an_end_segment_fold_belongs_to_its_own_hopf_point():
    """A branch from HB1 (a < 0: no fold of its own) to HB2 (a > 0: the kink's fold in its end segment, a hundredth
    of a degree): HB1 reads supercritical, HB2 subcritical with that fold as its jump (soft in practice), though
    the fold's amplitude is below HB1's first cycle too.  A fold in HB1's own end segment just short of its first
    cycle in amplitude, but farther from it in speed (the first cycle turned back), is HB1's."""
    import types

    from bifurcation.special_points import Criticality, PointKind
    from comparisons.studies.onset import branch_onset
    names = ("theta1", "theta1_dot", "theta2", "psi")

    def cycle(p, deg, stable=True):
        amp = np.radians([deg, 0.0, 0.0, 0.0])
        return types.SimpleNamespace(p=p, amplitude=amp, stable=stable, names=names)

    def fold(p, deg):
        c = cycle(p, deg)
        return types.SimpleNamespace(kind=PointKind.CYCLE_FOLD, p=p, data={"amplitude": c.amplitude, "cycle": c,
                                                                           "end_segment": True})

    def hopf(p, a):
        return types.SimpleNamespace(p=p, kink=a, kink_criticality=(Criticality.SUBCRITICAL if a > 0
                                                                    else Criticality.SUPERCRITICAL))
    hb1, hb2 = hopf(10.0, -1e-4), hopf(25.0, 2e-4)
    points = (cycle(10.001, 0.08), cycle(15.0, 5.0), cycle(24.999, 0.06))
    branch = types.SimpleNamespace(start=hb1, end=hb2, points=points, special_points=(fold(25.00001, 0.002),))
    diagram = types.SimpleNamespace(branches=(branch,))
    first, second = branch_onset(diagram, hb1), branch_onset(diagram, hb2)
    assert first.criticality is Criticality.SUPERCRITICAL and first.soft
    assert second.criticality is Criticality.SUBCRITICAL and second.soft and second.jump_deg == pytest.approx(0.002)
    assert "made by the kink" in second.detail and "a jump below 0.05 deg" in second.detail
    hb1 = hopf(10.0, 3e-4)
    turned = types.SimpleNamespace(start=hb1, end=None, points=(cycle(9.99998, 0.03), cycle(10.01, 0.2)),
                                   special_points=(fold(9.99997, 0.025),))
    own = branch_onset(types.SimpleNamespace(branches=(turned,)), hb1)
    assert own.criticality is Criticality.SUBCRITICAL and own.jump_deg == pytest.approx(0.025)
