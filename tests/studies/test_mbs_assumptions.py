"""What the reduced model's assumptions are worth (issue 4, items 6-7 with ``--fidelity full``).

The numbers asserted here are the multibody model's computed Hopf speeds with one assumption dropped and with
all dropped (section 3 model, Table 1, the dimensions of :class:`axles.dimensions.AxleDimensions`).  They are results,
listed in the README; a change of the model that moves them must update both.
"""

import json

import numpy as np
import pytest

from axles.pressures import TyrePressures
from comparisons import assumption_shifts as shifts
from axles.units import BAR, KMH, kmh
from comparisons.cli.main import main
from mbs_shimmy import Fidelity
from comparisons.studies.assumption_study import assumption_study, match_hopf, study_fidelities
from mbs_shimmy.linearisation import MbsFamily
from mbs_shimmy.model import MbsModel
from bifurcation.equilibria.hopf import HopfPoint, find_hopf_points
from reduced_model.model import Effects

# Hopf speeds (km/h) of the MBS, section 3 model; the reduced model has 26.630, 97.128, 192.983, 345.889 at
# 1.5 bar and 46.143, 70.501 at 2.5 bar.
COMPUTED = {
    1.5: {"small_angles": [26.7123, 97.0031, 193.4276, 344.9754],
          "fixed_static_load_arms": [26.4909, 97.0879, 189.8798, 348.7015],
          "uncoupled_inertia": [26.2132, 99.3014, 202.5059, 333.0922],
          "slip_heading_only": [32.6377, 97.8254],
          "load_tramp_only": [26.8668, 94.8023, 179.8043, 380.3522],
          "lateral_stiffness_tramp_only": [26.8727, 95.7051, 184.8643, 365.5915],
          "constant_load": [26.6301, 97.1280, 192.9828, 345.8892],
          "quasi_steady_speed": [26.6301, 97.1280, 192.9828, 345.8892],
          "separate_lateral_spring": [26.1076, 95.4905, 171.2039, 377.7018],
          "full": [39.2273, 91.7933],
          "no_kingpin_inclination": [37.3341, 93.6744],
          "roll_axis_at_wheel_centre": [35.5744, 103.4046],
          "rigid_axle_mounts": [25.7288, 88.0097, 304.4984, 357.4489],
          "parallel_steering_arms": [39.2056, 91.8517],
          "rigid_steering_gear": [],
          "no_axle_roll_steer": [34.3527, 101.7914],
          "no_camber_force": [40.3524, 90.3964],
          "rigid_vertical_mounts": [39.5458, 91.3485],
          "massless_links": [47.2985, 77.2011]},
    2.5: {"small_angles": [46.4705, 70.1101],
          "fixed_static_load_arms": [45.6054, 70.9895],
          "uncoupled_inertia": [44.1379, 74.0966],
          "slip_heading_only": [],
          "load_tramp_only": [48.5512, 65.8754],
          "lateral_stiffness_tramp_only": [47.7810, 67.6239],
          "constant_load": [46.1426, 70.5006],
          "quasi_steady_speed": [46.1426, 70.5006],
          "separate_lateral_spring": [44.6456, 70.4751],
          "full": [],
          "no_kingpin_inclination": [],
          "roll_axis_at_wheel_centre": [],
          "rigid_axle_mounts": [45.4849, 59.7046],
          "parallel_steering_arms": [],
          "rigid_steering_gear": [],
          "no_axle_roll_steer": [],
          "no_camber_force": [],
          "rigid_vertical_mounts": [],
          "massless_links": []},
}


@pytest.mark.parametrize("pressure", [1.5, 2.5])
@pytest.mark.parametrize("name,fidelity", study_fidelities())
def test_hopf_speeds_without_each_assumption(pressure, name, fidelity):
    points = find_hopf_points(MbsFamily(MbsModel(fidelity=fidelity)), pressure * BAR, 0.0, 400 * KMH, lyapunov=False)
    assert [kmh(h.p) for h in points] == pytest.approx(COMPUTED[pressure][name], abs=1e-3)


@pytest.mark.parametrize("name", ["constant_load", "quasi_steady_speed", "parallel_steering_arms"])
def test_nonlinear_assumptions_move_no_hopf_point(name):
    """Ackermann arms are a new element: measured on the full geometry with massless links (its tie-rod stays along
    y at straight running, so its lever about both kingpins, and k1, are unchanged; the rod's ball masses would
    move with the angled arms)."""
    base, without = ((Fidelity.reduced(), Fidelity.reduced().without(name)) if name != "parallel_steering_arms"
                     else (Fidelity.parse(f"{name},massless_links"), Fidelity.parse("massless_links")))
    reduced = find_hopf_points(MbsFamily(MbsModel(fidelity=base)), 1.5 * BAR, 0.0, 400 * KMH, lyapunov=False)
    dropped = find_hopf_points(MbsFamily(MbsModel(fidelity=without)), 1.5 * BAR, 0.0, 400 * KMH, lyapunov=False)
    assert np.max(np.abs(np.array([h.p for h in dropped]) - [h.p for h in reduced])) < 1e-6


def test_full_geometry_with_large_trail():
    """t0 = 0.25 m (figure 9 of the paper): the full geometry (with the new elements) moves all three Hopf points
    up."""
    from axles.parameters import YANG2024
    family = MbsFamily(MbsModel(params=YANG2024.replace(t0=0.25), fidelity=Fidelity.full()))
    assert [kmh(h.p) for h in find_hopf_points(family, 1.5 * BAR, 0.0, 400 * KMH, lyapunov=False)] == \
        pytest.approx([3.5605, 194.6488, 224.4958], abs=1e-3)


def _hopf(kmh, hz):
    return HopfPoint(p=kmh * KMH, q=0.0, omega=2 * np.pi * hz, first_lyapunov=float("nan"),
                     eigenvector=np.zeros(8))


def test_match_hopf_pairs_modes_and_leaves_vanished_ones_open():
    reduced = [_hopf(26.6, 5.3), _hopf(97.1, 6.6), _hopf(193.0, 10.6), _hopf(345.9, 13.2)]
    mbs = [_hopf(32.5, 5.4), _hopf(96.3, 6.5), _hopf(250.0, 30.0)]
    rows = match_hopf(reduced, mbs)
    pairs = [(None if r.reduced_speed is None else round(shifts.reduced_kmh(r), 6),
              None if r.mbs_speed is None else round(shifts.mbs_kmh(r), 6)) for r in rows]
    assert pairs[:2] == [(26.6, 32.5), (97.1, 96.3)]
    assert (193.0, None) in pairs and (345.9, None) in pairs and (None, 250.0) in pairs
    assert shifts.shift_kmh(rows[0]) == pytest.approx(5.9) and shifts.shift_kmh(rows[2]) is None


def test_study_without_cycles():
    study = assumption_study(MbsModel().params, Effects(), TyrePressures.uniform(1.5 * BAR), cycles=False)
    names = [r.assumption for r in study.rows]
    assert names == [n for n, _ in study_fidelities()]
    full = study.rows[names.index("full")]
    assert [shifts.mbs_kmh(h) for h in full.hopf if shifts.mbs_kmh(h) is not None] == pytest.approx(COMPUTED[1.5]["full"], abs=1e-3)
    assert shifts.peak_theta1_shift_deg(full) is None
    # an element's row: full geometry (mbs side) against full geometry without it (reference side)
    for name in ("rigid_axle_mounts", "no_axle_roll_steer"):
        row = study.rows[names.index(name)]
        assert sorted(shifts.reduced_kmh(h) for h in row.hopf if shifts.reduced_kmh(h) is not None) == pytest.approx(
            COMPUTED[1.5][name], abs=1e-3)
        assert sorted(shifts.mbs_kmh(h) for h in row.hopf if shifts.mbs_kmh(h) is not None) == pytest.approx(
            COMPUTED[1.5]["full"], abs=1e-3)
    uncoupled = study.rows[names.index("uncoupled_inertia")]
    assert [shifts.shift_kmh(h) for h in uncoupled.hopf] == pytest.approx(
        [a - b for a, b in zip(COMPUTED[1.5]["uncoupled_inertia"], [26.6301, 97.1280, 192.9828, 345.8892])],
        abs=1e-3)


def test_cli_json(capsys):
    assert main(["assumptions", "--pressure", "2.5", "--no-cycles", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["pressure_bar"] == 2.5
    names = [r["assumption"] for r in out["rows"]]
    # the fidelity rows, then the paper's no-longitudinal-slip assumption dropped at the two planned braking levels
    assert names[-3] == study_fidelities()[-1][0] and "full" in names
    assert names[-2:] == ["no_longitudinal_slip (brake slip 0.05)",
                          "no_longitudinal_slip (brake slip right 0.05 / left 0)"]
    braked = out["rows"][-2]["hopf"]
    assert braked[0]["reduced_kmh"] == pytest.approx(46.143, abs=1e-3) and braked[0]["shift_kmh"] < -5.0
    for row in out["rows"]:
        assert set(row) == {"assumption", "hopf", "peak_theta1_shift_deg", "mbs_peak", "reference_peak"}
        assert row["mbs_peak"] is row["reference_peak"] is row["peak_theta1_shift_deg"] is None
        for h in row["hopf"]:
            assert set(h) == {"reduced_kmh", "mbs_kmh", "shift_kmh"}
    assert out["reduced_peak"] is None


@pytest.mark.parametrize("argv,message", [
    (["assumptions", "--pressure", "0"], "must be within [0.05, 20] bar"),
    (["assumptions", "--pressure", "2", "--effects", "nope"], "unknown effect"),
    (["assumptions", "--pressure", "2", "--set", "k4=-3", "--no-cycles"], "k4 = -3 N/m is outside its physical range"),
    (["assumptions"], "required"),
])
def test_cli_bad_input(argv, message, capsys):
    with pytest.raises(SystemExit) as exc:
        code = main(argv)
        raise SystemExit(code)
    assert exc.value.code == 2
    assert message in capsys.readouterr().err


# The continued peak cycle of each row's own model (max|theta1| deg, km/h): the MBS variant, or for an element's row
# the full geometry without that element; None: no Hopf point, so no cycle born at one.  Every one is a stable yaw
# cycle on a branch that completed.  The reduced model's: 9.8538 deg at 48.14 km/h (1.5 bar), 3.4490 deg at 56.64 km/h
# (2.5 bar, paper 3.45 deg at 56.34 km/h, a flat maximum); the full geometry's 6.9510 deg at 56.25 km/h (1.5 bar).
REDUCED_PEAK = {1.5: (9.8538, 48.14), 2.5: (3.4490, 56.64)}
PEAKS = {
    1.5: {"small_angles": (10.0448, 47.98), "fixed_static_load_arms": (9.9134, 48.03),
          "uncoupled_inertia": (10.1094, 48.15), "slip_heading_only": (8.8908, 52.64),
          "load_tramp_only": (9.6226, 47.81), "lateral_stiffness_tramp_only": (9.6923, 48.04),
          "constant_load": (9.2504, 50.07), "quasi_steady_speed": (9.8538, 48.14),
          "separate_lateral_spring": (10.0237, 47.45), "full": (6.9510, 56.25),
          "no_kingpin_inclination": (7.5443, 55.13), "roll_axis_at_wheel_centre": (8.9336, 54.67),
          "rigid_axle_mounts": (9.1280, 44.18), "parallel_steering_arms": (6.9576, 56.35), "rigid_steering_gear": None,
          "no_axle_roll_steer": (9.0745, 53.44), "no_camber_force": (6.7123, 56.85),
          "rigid_vertical_mounts": (6.8373, 56.60), "massless_links": (3.9104, 59.18)},
    2.5: {"small_angles": (3.4339, 56.68), "fixed_static_load_arms": (3.6039, 56.47),
          "uncoupled_inertia": (4.1723, 56.57), "slip_heading_only": None, "load_tramp_only": (2.5109, 56.36),
          "lateral_stiffness_tramp_only": (2.8487, 56.58), "constant_load": (3.1338, 56.88),
          "quasi_steady_speed": (3.4490, 56.64), "separate_lateral_spring": (3.7629, 55.66), "full": None,
          "no_kingpin_inclination": None, "roll_axis_at_wheel_centre": None, "rigid_axle_mounts": (1.8586, 51.90),
          "parallel_steering_arms": None, "rigid_steering_gear": None, "no_axle_roll_steer": None,
          "no_camber_force": None, "rigid_vertical_mounts": None, "massless_links": None},
}


@pytest.mark.slow
@pytest.mark.parametrize("pressure", [1.5, 2.5])
def test_continued_peak_of_every_row(pressure):
    """The limit-cycle column of the docs' table: each side's largest cycle from its own continued branches (the
    reduced model's, each MBS variant's on Exudyn), and the shift MBS minus reference, each at its own speed."""
    from comparisons.studies.assumption_study import ELEMENTS
    from comparisons.studies.cycle_peak import PeakStatus
    study = assumption_study(MbsModel().params, Effects(), TyrePressures.uniform(pressure * BAR), cycles=True)
    theta, speed = REDUCED_PEAK[pressure]
    assert np.degrees(study.peak_theta1) == pytest.approx(theta, abs=5e-4)
    assert kmh(study.peak_speed) == pytest.approx(speed, abs=0.02)
    full = next(r for r in study.rows if r.assumption == "full").peak_mbs
    for row in study.rows:
        own = row.peak_reference if row.assumption in ELEMENTS else row.peak_mbs
        expected = PEAKS[pressure][row.assumption]
        if expected is None:
            assert own.status is PeakStatus.NO_CYCLE and own.theta1 == 0.0, row.assumption
        else:
            assert own.status is PeakStatus.FOUND, row.assumption
            assert all(b.complete for b in own.branches) and own.mode == "yaw" and own.stable, row.assumption
            assert np.degrees(own.theta1) == pytest.approx(expected[0], abs=5e-4), row.assumption
            assert kmh(own.speed) == pytest.approx(expected[1], abs=0.02), row.assumption
        # an element's row: full geometry (MBS side) against full geometry without it; the others: the reduced model
        assert (row.peak_mbs is full) if row.assumption in ELEMENTS else (row.peak_reference is study.reduced_peak)
        assert shifts.peak_theta1_shift_deg(row) == pytest.approx(
            np.degrees(row.peak_mbs.theta1 - row.peak_reference.theta1), abs=1e-12)


@pytest.mark.parametrize("dims,expected", [
    ({"drag_link_inclination": 0.0}, [45.4482, 80.8357]),           # the gear's compliance alone (no roll steer)
    ({"steering_gear_compliance": 0.0}, [56.0316, 88.7625]),         # roll steer alone (rigid gear)
    ({"drag_link_inclination": 0.0, "steering_gear_compliance": 0.0}, []),
])
def test_steering_gear_row_split_into_compliance_and_roll_steer(dims, expected):
    """The `rigid_steering_gear` row holds two effects; at 1.5 bar, on the geometry of issue 9 (the freedoms of
    issue 18 out), each alone makes the yaw mode unstable."""
    from axles.dimensions import DEFAULT_DIMENSIONS
    from mbs_shimmy.fidelity import ISSUE_18
    family = MbsFamily(MbsModel(fidelity=Fidelity(ISSUE_18), dims=DEFAULT_DIMENSIONS.replace(**dims)))
    points = find_hopf_points(family, 1.5 * BAR, 0.0, 400 * KMH, lyapunov=False)
    assert [kmh(h.p) for h in points] == pytest.approx(expected, abs=1e-3)
