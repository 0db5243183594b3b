"""Hopf curves of the multibody model in (speed, pressure): the real axle's shimmy-free boundary.

The curve's fold in pressure is the highest pressure with a Hopf point: checked against eigenvalue scans just
below and above it (an independent computation of the same boundary), and, with every assumption on, against
the reduced model's fold.
"""

import json
import subprocess
import sys

import numpy as np
import pytest

from axles.units import BAR, KMH
from mbs_shimmy import Fidelity
from mbs_shimmy.linearisation import MbsFamily
from mbs_shimmy.model import MbsModel
from bifurcation.equilibria.hopf import eigenvalues
from bifurcation.equilibria.hopf_curves import hopf_diagram
from bifurcation.special_points import PointKind, PointStatus
from bifurcation.cycle_curves.curve import cycle_bifurcation_curve
from bifurcation.cycles.branches import cycle_diagram
from comparisons.api import family_of
from reduced_model.family import SpeedFamily
from reduced_model.model import ShimmyModel
from axles.pressures import TyrePressures

WINDOW = (0.5 * BAR, 3.5 * BAR)
VMAX = 400.0 * KMH


def _folds(family):
    diagram = hopf_diagram(family, *WINDOW, 0.0, VMAX)
    assert diagram.complete
    return sorted(diagram.points_of(PointKind.HOPF_FOLD), key=lambda p: -p.q)


def _unstable_somewhere(family, pressure):
    speeds = np.linspace(1.0, 150.0, 300) * KMH
    return any(eigenvalues(family, v, pressure)[0].real > 0.0 for v in speeds)


def test_mbs_with_every_assumption_on_has_the_reduced_models_folds():
    reduced = _folds(SpeedFamily(ShimmyModel(), "pressure", pressures=TyrePressures.uniform(1.5 * BAR)))
    mbs = _folds(MbsFamily(MbsModel(fidelity=Fidelity.reduced()), param="pressure", pressures=TyrePressures.uniform(1.5 * BAR)))
    assert len(mbs) == len(reduced) == 2
    for a, b in zip(reduced, mbs):
        assert b.q == pytest.approx(a.q, rel=1e-7)
        assert b.p == pytest.approx(a.p, rel=1e-6)


def test_full_geometry_shimmy_free_boundary_from_the_curves_command():
    """``shimmy curves --model mbs``: the fold of the full geometry's Hopf curve, checked by eigenvalue scans
    0.01 bar below (an unstable speed) and above it (stable at every speed).  Over 1.8-2.5 bar, around the
    boundary: the whole 0.5-3.5 bar has the same fold (docs/results.md) at twice the cost."""
    proc = subprocess.run([sys.executable, "-m", "comparisons.cli", "curves", "--param", "pressure", "--range", "1.8",
                           "2.5", "--model", "mbs", "--fidelity", "full", "--vmax", "150", "--json"],
                          capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr
    out = json.loads(proc.stdout)
    assert out["model"] == "mbs" and out["fidelity"] == "full" and out["unit"] == "bar"
    boundary_bar = max(s["value"] for s in out["special_points"] if s["kind"] == "hopf_fold")
    family = MbsFamily(MbsModel(fidelity=Fidelity.full()), param="pressure", pressures=TyrePressures.uniform(1.5 * BAR))
    assert _unstable_somewhere(family, (boundary_bar - 0.01) * BAR)
    assert not _unstable_somewhere(family, (boundary_bar + 0.01) * BAR)


def _full(pressure):
    return family_of(MbsModel(fidelity=Fidelity.full()), TyrePressures.uniform(pressure), "pressure")


def _kink_folds(pressure, vmin, vmax):
    """The cycle folds on the full geometry's branches at ``pressure`` in the speed window."""
    diagram = cycle_diagram(_full(pressure), pressure, vmin, vmax)
    return [p for b in diagram.branches for p in b.points_of(PointKind.CYCLE_FOLD)]


def _kink_fold_curve(pressure, speeds, largest_deg, window, curve_speeds, rel):
    """The full geometry's one kink fold at ``pressure`` in the speed window ``speeds`` (its cycle below
    ``largest_deg``) and its curve over the pressure ``window``: complete, leaving the window at both ends, and at
    three of its pressures the one-parameter branch's own fold at the curve's speed to ``rel``.  (fold, curve)."""
    (start,) = _kink_folds(pressure, *speeds)
    assert start.status is PointStatus.LOCATED and np.degrees(start.data["cycle"].amplitude[0]) < largest_deg
    curve = cycle_bifurcation_curve(_full(pressure), start, *window, *curve_speeds)
    assert curve.complete and all(str(m).startswith("left the window") for m in curve.messages)
    assert curve.qs.min() == pytest.approx(window[0]) and curve.qs.max() == pytest.approx(window[1])
    for k in (1, len(curve.ps) // 2, len(curve.ps) - 2):
        (fold,) = _kink_folds(curve.qs[k], *speeds)
        assert fold.p == pytest.approx(curve.ps[k], rel=rel)
    return start, curve


def test_a_fold_made_by_the_kink_is_followed_across_the_window_through_the_one_parameter_folds():
    """The full geometry's yaw onset at 1.3 bar is hard by the camber kink: a cycle fold 0.012 deg from the Hopf
    point.  Its fold curve once ended after one step each way, its amplitude being below the end threshold from the
    start; it now runs across 1.25-1.35 bar (the kink coefficient keeps its sign there), and at three of its
    pressures the one-parameter branch's own fold lies at the curve's speed, within the branches' tolerance of 1e-7
    (measured 2e-13 to 5e-9 relative)."""
    _kink_fold_curve(1.3 * BAR, (30 * KMH, 45 * KMH), 0.05, (1.25 * BAR, 1.35 * BAR), (20 * KMH, 60 * KMH), 1e-7)


def test_the_smallest_kink_fold_is_followed_and_passes_through_its_one_parameter_folds():
    """The fold beside the 1.5 bar branch's upper Hopf point (91.79 km/h, max|theta1| 0.0019 deg, kink coefficient
    1.8e-4) stalled after 8 points at 1.5031 bar: its Newton steps stopped at 1e-7 to 5e-7 (weighted) with the
    residual at its rounding floor, below which they never fall (ContinuationSettings.floor_tol now accepts them
    there).  It now crosses 1.45-1.6 bar, and at three of its pressures the one-parameter branch's fold lies at
    the curve's speed; the branch's first fold at 1.5 bar lies on the same curve, as its own curve
    (CycleCurve.passes), and the lower Hopf point's fold does not."""
    start, curve = _kink_fold_curve(1.5 * BAR, (80 * KMH, 100 * KMH), 0.003, (1.45 * BAR, 1.6 * BAR),
                                    (60 * KMH, 120 * KMH), 1e-6)
    assert curve.passes(start)
    lower = _kink_folds(1.5 * BAR, 30 * KMH, 45 * KMH)
    assert lower and not any(curve.passes(p) for p in lower)
