"""Left and right tyre pressures: equal ones give today's numbers, swapping mirrors the solution, asymmetric cycles
agree with simulation, one tyre's pressure as a continuation parameter."""

import json

import numpy as np
import pytest

from axles.units import BAR, KMH
from comparisons.cli.main import main
from bifurcation.cycles.branches import branch_from_hopf, cycle_at, cycle_diagram
from bifurcation.equilibria.hopf import find_hopf_points
from reduced_model.family import SpeedFamily
from reduced_model.model import ShimmyModel
from reduced_model.simulation import integrate
from reduced_model.trajectory import SpeedSchedule
from axles.pressures import TyrePressures

# The paper's axle carries the drag link (k2, c2) on the left wheel only, so it is not left-right symmetric; with the
# drag link taken out, (theta1, alpha1) <-> (theta2, alpha2) with psi kept maps solutions onto solutions of the
# axle with the two pressures swapped (eqs. 2.1-2.3 and 2.10-2.11 are symmetric in the wheels but for k2, c2).
SYMMETRIC = ShimmyModel().with_params(k2=0.0, c2=0.0)


def json_of(capsys, *args):
    assert main(list(args)) == 0
    return json.loads(capsys.readouterr().out)


def test_equal_left_right_give_todays_numbers(capsys):
    both = json_of(capsys, "hopf", "--pressure", "1.5", "--json")
    sides = json_of(capsys, "hopf", "--pressure-left", "1.5", "--pressure-right", "1.5", "--json")
    assert sides["hopf"] == both["hopf"]
    assert both["pressure_bar"] == 1.5 and sides["pressure_left_bar"] == sides["pressure_right_bar"] == 1.5
    asym = json_of(capsys, "hopf", "--pressure", "1.5", "--pressure-left", "1.2", "--json")
    assert "pressure_bar" not in asym and (asym["pressure_left_bar"], asym["pressure_right_bar"]) == (1.2, 1.5)
    assert [h["speed_kmh"] for h in asym["hopf"]] != [h["speed_kmh"] for h in both["hopf"]]


def test_pressure_family_moves_both_tyres_together():
    assert TyrePressures.uniform(1.5e5).moved("pressure", 2.0e5) == TyrePressures(2.0e5, 2.0e5)
    moved = TyrePressures(1.6e5, 1.2e5).moved("pressure", 2.0e5)
    assert (moved.right, moved.left) == pytest.approx((2.2e5, 1.8e5))
    assert TyrePressures(1.6e5, 1.2e5).moved("pressure_left", 1.0e5) == TyrePressures(1.6e5, 1.0e5)
    assert TyrePressures(1.6e5, 1.2e5).moved("pressure_right", 1.2e5).alike     # equal again
    assert TyrePressures(1.6e5, 1.2e5).value("pressure") == 1.4e5
    assert TyrePressures(1.6e5, 1.2e5).value("pressure_left") == 1.2e5


def test_swapping_pressures_mirrors_the_solution():
    a = SpeedFamily(SYMMETRIC, pressures=TyrePressures(1.5 * BAR, 1.2 * BAR))
    b = SpeedFamily(SYMMETRIC, pressures=TyrePressures(1.2 * BAR, 1.5 * BAR))
    ha, hb = find_hopf_points(a, a.nominal, 0.0, 400 * KMH), find_hopf_points(b, b.nominal, 0.0, 400 * KMH)
    assert len(ha) == len(hb) > 0
    assert [h.p for h in ha] == pytest.approx([h.p for h in hb], rel=1e-10)
    # the yaw branch near its Hopf point (a narrow speed window keeps the continuation short)
    ba = branch_from_hopf(a, ha[0], ha[0].p - 3 * KMH, ha[0].p + 8 * KMH)
    bb = branch_from_hopf(b, hb[0], hb[0].p - 3 * KMH, hb[0].p + 8 * KMH)
    assert len(ba.points) > 3 and len(bb.points) > 3
    for ba, bb in ((ba, bb),):
        # the same uniform mesh for both: max|x_i| over mesh nodes is then the same estimate of the same orbit
        pa = ba.points[len(ba.points) // 2]
        pb = min(bb.points, key=lambda p: abs(p.p - pa.p))
        pa, pb = cycle_at(a, pa, pa.p, intervals=60), cycle_at(b, pb, pa.p, intervals=60)
        assert pb.period == pytest.approx(pa.period, rel=1e-6)
        assert pb.max_abs("theta1") == pytest.approx(pa.max_abs("theta2"), rel=1e-6)
        assert pb.max_abs("theta2") == pytest.approx(pa.max_abs("theta1"), rel=1e-6)
        assert pb.max_abs("psi") == pytest.approx(pa.max_abs("psi"), rel=1e-6)
        assert abs(pa.max_abs("theta1") - pa.max_abs("theta2")) > 1e-3 * pa.max_abs("theta1")  # really asymmetric


def test_asymmetric_cycle_agrees_with_a_long_simulation():
    """Right 1.5 bar, left 1.2 bar: the odd symmetry x(t + T/2) = -x(t) is lost once the trails differ (with
    pt), yet the trivial Floquet multiplier stays 1 and the orbit is what a long simulation settles on."""
    model = ShimmyModel().with_params()
    from reduced_model.model import Effects
    model = ShimmyModel(effects=Effects.parse("pt"))
    family = SpeedFamily(model, pressures=TyrePressures(1.5 * BAR, 1.2 * BAR))
    diagram = cycle_diagram(family, family.nominal, 0.0, 120 * KMH)
    branch = diagram.branches[0]
    point = max((p for p in branch.points if p.stable), key=lambda p: p.max_abs("theta1"))
    assert abs(point.trivial - 1.0) < 1e-8
    x = point.orbit.nodes
    half = len(x) // 2
    # no half-period odd symmetry: x(T/2) is not -x(0)
    assert np.max(np.abs(x[half] + x[0])) > 1e-4 * np.max(np.abs(x))
    traj = integrate(model, TyrePressures(1.5 * BAR, 1.2 * BAR), SpeedSchedule.constant(point.p), 30.0,
                    0.5 * point.orbit.nodes[0])
    tail = traj.t > traj.t[-1] - 3.0
    for name in ("theta1", "theta2", "psi"):
        assert np.max(np.abs(traj.state(name)[tail])) == pytest.approx(point.max_abs(name), rel=1e-3)


def test_curves_in_one_tyre_pressure(capsys):
    out = json_of(capsys, "curves", "--param", "pressure_left", "--range", "1.0", "2.5", "--pressure", "1.5",
                  "--vmax", "150", "--json")
    assert out["unit"] == "bar" and out["param"] == "pressure_left" and out["curves"]
    assert out["pressure_bar"] == 1.5
    # where the curves cross the operating line (left = 1.5 bar) they give the symmetric Hopf speeds
    both = [h["speed_kmh"] for h in json_of(capsys, "hopf", "--pressure", "1.5", "--vmax", "150", "--json")["hopf"]]
    crossings = []
    for c in out["curves"]:
        pts = np.array(c["points"])
        for (v0, q0), (v1, q1) in zip(pts[:-1], pts[1:]):
            if (q0 - 1.5) * (q1 - 1.5) < 0:
                crossings.append(v0 + (1.5 - q0) * (v1 - v0) / (q1 - q0))
    assert sorted(crossings) == pytest.approx(both, abs=0.05)


@pytest.mark.parametrize("args, fragment", [
    (["hopf", "--pressure-left", "1.2"], "give --pressure for the other"),
    (["hopf"], "--pressure BAR is required"),
    (["hopf", "--pressure", "1.5", "--pressure-right", "30"], "within [0.05, 20] bar"),
    (["hopf", "--pressure", "1.5", "--pressure-left", "-1"], "must be within [0.05, 20] bar"),
])
def test_bad_pressures(capsys, args, fragment):
    # Out-of-range numbers are refused by the option parser itself (SystemExit 2).
    with pytest.raises(SystemExit) if "-1" in args or "30" in args else _nothing():
        code = main(args)
        assert code == 2
    err = capsys.readouterr().err
    assert fragment in err and len(err.strip().splitlines()) == 1


class _nothing:
    def __enter__(self):
        return self

    def __exit__(self, *exc):
        return False
