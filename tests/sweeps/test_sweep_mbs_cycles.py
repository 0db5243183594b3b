"""``shimmy sweep --compute cycles --mbs full``: the full geometry's own cycle branches and criticality per sample,
against ``shimmy cycles --model mbs`` and ``shimmy hopf --model mbs`` as independent routes."""

from __future__ import annotations

import dataclasses
import json
import math

import pyarrow.parquet as pq

from axles.units import from_kmh
from comparisons.cli.main import main
from comparisons.sweeps.sample import cycle_columns
from bifurcation.cycles.branches import cycle_diagram
from bifurcation.cycles.problem import CycleSettings
from reduced_model.family import SpeedFamily
from reduced_model.model import ShimmyModel
from axles.pressures import TyrePressures

VMAX_KMH = 39.3      # just past the full geometry's first Hopf point at 1.5 bar (39.23 km/h): a short branch


def _cli_json(capsys, argv: list[str]) -> dict:
    code = main(argv)
    out = capsys.readouterr().out
    assert code == 0, out
    return json.loads(out)


def test_mbs_cycle_columns_equal_shimmy_cycles_and_shimmy_hopf(capsys, tmp_path):
    out = tmp_path / "c.parquet"
    _cli_json(capsys, ["sweep", "--vary", "pressure=1.5:2.5:2", "--compute", "cycles", "--mbs", "full",
                       "--vmax", str(VMAX_KMH), "--workers", "1", "--out", str(out), "--json"])
    rows = {r["pressure"]: r for r in pq.read_table(out).to_pylist()}
    assert all(r["status"] == "ok" for r in rows.values()), [r["error"] for r in rows.values()]
    r = rows[1.5]
    direct = _cli_json(capsys, ["cycles", "--model", "mbs", "--fidelity", "full", "--pressure", "1.5",
                                "--vmax", str(VMAX_KMH), "--json"])
    assert direct["fidelity"] == "full" and len(direct["branches"]) == len(r["mbs_full_cycle_status"]) == 1
    b = direct["branches"][0]
    assert r["mbs_full_cycle_status"] == [b["status"]] == ["complete"] and r["mbs_full_cycles_complete"]
    assert r["mbs_full_cycles_message"] is None
    assert math.isclose(r["mbs_full_cycle_from_kmh"][0], b["from_hopf_kmh"], rel_tol=1e-12)
    assert r["mbs_full_cycle_to_kmh"] == [b["to_hopf_kmh"]] == [None]
    peak = b["peak"]["theta1"]
    assert math.isclose(r["mbs_full_cycle_peak_theta1_deg"][0], peak["max_deg"], rel_tol=1e-9)
    assert math.isclose(r["mbs_full_cycle_peak_kmh"][0], peak["speed_kmh"], rel_tol=1e-9)
    assert math.isclose(r["mbs_full_cycle_peak_hz"][0], peak["frequency_hz"], rel_tol=1e-9)
    # the peak cycle's max |psi| is the orbit's, at the same speed: the CLI's cycle at that speed has it
    at_peak = min((p for p in b["points"] if p["kind"] == "cycle"), key=lambda p: abs(p["speed_kmh"] -
                                                                                       peak["speed_kmh"]))
    assert math.isclose(r["mbs_full_cycle_peak_psi_deg"][0], at_peak["max_psi_deg"], rel_tol=1e-9)
    assert r["mbs_full_cycle_mode"] == ["yaw"] and r["mbs_full_peak_yaw_theta1_deg"] == peak["max_deg"]
    assert r["mbs_full_peak_tramp_theta1_deg"] is None
    # criticality per Hopf point, against shimmy hopf (a separate process-free route to the same Hopf points)
    hopf = _cli_json(capsys, ["hopf", "--model", "mbs", "--fidelity", "full", "--pressure", "1.5",
                              "--vmax", str(VMAX_KMH), "--json"])["hopf"]
    assert len(hopf) == len(r["mbs_full_hopf_kmh"]) == 1
    assert math.isclose(r["mbs_full_hopf_kmh"][0], hopf[0]["speed_kmh"], rel_tol=1e-12)
    assert math.isclose(r["mbs_full_hopf_l1"][0], hopf[0]["first_lyapunov"], rel_tol=1e-9)
    # the full geometry has a kink at straight running: the criticality is its branch's, which locates the fold
    # of the small unstable cycles the kink makes (a > 0: shimmy hopf's kink criticality) against l1's sign, and
    # that fold is a jump of a hundredth of a degree: a soft onset in practice
    assert hopf[0]["criticality"] == "supercritical"
    assert r["mbs_full_hopf_criticality"] == [hopf[0]["kink_criticality"]] == ["subcritical"]
    assert r["mbs_full_hopf_criticality_by"] == ["branch"]
    assert math.isclose(r["mbs_full_hopf_kink"][0], hopf[0]["kink_coefficient"], rel_tol=1e-9)
    assert r["mbs_full_hopf_onset"] == ["soft"] and 0.005 < r["mbs_full_hopf_jump_deg"][0] < 0.02
    # at 2.5 bar the full geometry runs straight below 39.3 km/h: no branch, nothing missing
    calm = rows[2.5]
    assert calm["mbs_full_hopf_kmh"] == [] and calm["mbs_full_cycle_status"] == [] and calm["mbs_full_cycles_complete"]
    assert calm["mbs_full_peak_yaw_theta1_deg"] is None
    # the reduced model's cycles are in the same rows, under their own names
    assert r["cycle_status"] == ["complete"] and r["cycle_from_kmh"][0] < r["mbs_full_cycle_from_kmh"][0]


def test_a_branch_that_stops_is_marked_and_gives_no_mode_peak():
    """A branch cut short (3 continuation steps) is marked with its status, the sample's cycles are incomplete
    with the reason, and the mode's peak amplitude is null (the branch's largest cycle is only a lower bound)."""
    family = SpeedFamily(ShimmyModel(), pressures=TyrePressures.uniform(1.5e5))
    short = CycleSettings(continuation=dataclasses.replace(CycleSettings().continuation, max_steps=3))
    diagram = cycle_diagram(family, family.nominal, 0.0, from_kmh(60.0), settings=short)
    assert diagram.branches and not diagram.complete
    cols = cycle_columns("x_", family, diagram)
    assert cols["x_cycle_status"][0] == "max_steps" and cols["x_cycles_complete"] is False
    assert "stopped (max_steps)" in cols["x_cycles_message"]
    assert cols["x_cycle_mode"][0] == "yaw" and cols["x_cycle_peak_theta1_deg"][0] > 0.0
    assert cols["x_peak_yaw_theta1_deg"] is None
    whole = cycle_columns("x_", family, cycle_diagram(family, family.nominal, 0.0, from_kmh(60.0)))
    assert whole["x_cycles_complete"] and whole["x_peak_yaw_theta1_deg"] == max(whole["x_cycle_peak_theta1_deg"])


def test_a_continuation_that_raises_keeps_the_hopf_points_and_marks_the_cycles_unknown(monkeypatch):
    """A cycle continuation of the MBS that raises (as the toolkit's boundary location can) fails its cycles, not
    the sample: the Hopf points and their l1 stay, the branch lists are null (unknown), not empty (none)."""
    import numpy as np

    from axles.axle import AxleData
    from comparisons.sweeps import sample
    from mbs_shimmy.linearisation import MbsFamily

    real = sample._cycle_diagram

    def diagram(family, vmax):
        if isinstance(family, MbsFamily):
            raise RuntimeError("corrector failed at s = 0.38 after point 82")
        return real(family, vmax)

    monkeypatch.setattr(sample, "_cycle_diagram", diagram)
    task = sample.SweepTask(axle=AxleData(), effects=(), pressure_right_bar=1.5, pressure_left_bar=1.5,
                            names=("pressure",), compute=("cycles",), mbs=("full",), vmax_kmh=VMAX_KMH)
    (row,) = sample.evaluate_batch(task, 0, 0, np.array([[1.5]])).to_pylist()
    assert row["status"] == "ok" and row["cycles_complete"]
    assert row["mbs_full_cycles_complete"] is False and row["mbs_full_cycle_status"] is None
    assert row["mbs_full_cycles_message"] == "cycle continuation failed: RuntimeError: corrector failed at s = 0.38 " \
                                             "after point 82"
    assert row["mbs_full_peak_yaw_theta1_deg"] is None
    # no branch: the criticality is the kink coefficient's (a > 0 on this axle), the onset unknown
    assert len(row["mbs_full_hopf_kmh"]) == 1 and row["mbs_full_hopf_criticality"] == ["subcritical"]
    assert row["mbs_full_hopf_criticality_by"] == ["kink"] and row["mbs_full_hopf_onset"] == [None]


def test_bistable_windows_anywhere_on_the_branches_end_at_their_folds_torus_and_hopf_points():
    """The sweep's ``bistable_from_kmh``/``_to_kmh`` (read from the branches' stable stretches and straight
    running's stability) at figure 9a's t = 0.25 m, 1.5 bar: a window away from any onset, where the yaw branch's
    stable cycles (past its torus point T2) coexist with the tramp branch's (up to its fold S1).  Each end is a
    computed cycle next to a cycle fold, torus or Hopf point located on its own test function, on a step of its
    branch next to it (measured: 159.19 km/h after T2 at 157.38, 183.89 before S1 at 184.75)."""
    from comparisons.api import family_of
    from axles.parameters import YANG2024
    from axles.units import kmh
    from bifurcation.special_points import PointKind, PointStatus

    family = family_of(ShimmyModel(params=YANG2024.replace(t0=0.25)), TyrePressures.uniform(1.5e5), "pressure")
    diagram = cycle_diagram(family, family.nominal, from_kmh(100.0), from_kmh(300.0))
    cols = cycle_columns("x_", family, diagram)
    windows = list(zip(cols["x_bistable_from_kmh"], cols["x_bistable_to_kmh"]))
    assert diagram.complete and len(windows) == 1

    def next_to_a_located_point(end: float) -> bool:
        """``end`` is a computed cycle, and a located point lies on a step of its branch next to it (in branch
        order: a branch turns at its folds, so speed order would not do)."""
        for b in diagram.branches:
            speeds = [kmh(h.p) for h in (b.start,) if h is not None] + [kmh(p.p) for p in b.points] + \
                [kmh(h.p) for h in (b.end,) if h is not None]
            points = [kmh(p.p) for p in b.special_points if p.status is PointStatus.LOCATED
                      and p.kind in (PointKind.CYCLE_FOLD, PointKind.TORUS)] + speeds[:1] + speeds[-1:]
            for i in (i for i, v in enumerate(speeds) if v == end):
                steps = [speeds[j:j + 2] for j in (i - 1, i) if 0 <= j < len(speeds) - 1]
                if any(min(a, c) <= v <= max(a, c) for a, c in steps for v in points):
                    return True
        return False

    for lo, hi in windows:
        assert hi - lo > 0.5
        assert next_to_a_located_point(lo) and next_to_a_located_point(hi), (lo, hi)


def test_cycles_past_their_budget_are_unknown_not_none(monkeypatch):
    """Past :data:`~comparisons.sweeps.sample.CYCLES_BUDGET_S` a sample's cycles are unknown (null lists, not
    complete, the message says where the branch was), its Hopf points kept."""
    import numpy as np

    from axles.axle import AxleData
    from comparisons.sweeps import sample

    monkeypatch.setattr(sample, "CYCLES_BUDGET_S", 0.0)
    task = sample.SweepTask(axle=AxleData(), effects=(), pressure_right_bar=1.5, pressure_left_bar=1.5,
                            names=("pressure",), compute=("cycles",), mbs=("full",), vmax_kmh=VMAX_KMH)
    (row,) = sample.evaluate_batch(task, 0, 0, np.array([[1.5]])).to_pylist()
    for c in ("", "mbs_full_"):
        assert row[f"{c}cycles_complete"] is False and row[f"{c}cycle_status"] is None
        assert row[f"{c}bistable_from_kmh"] is None and row[f"{c}bistable_to_kmh"] is None
        assert "over the budget of 0 s: stopped on a branch at" in row[f"{c}cycles_message"]
    assert len(row["mbs_full_hopf_kmh"]) == 1
