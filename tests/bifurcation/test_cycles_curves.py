"""Two-parameter curves of cycle folds and torus points (figures 8 and 18): they must end where the amplitude
vanishes, at the Hopf-Hopf and generalized Hopf points that the Hopf-curve continuation finds independently."""

import pytest

from axles import paper_reference as paper
from axles.units import BAR, KMH
from comparisons.verify.context import agrees_to_printed_digits
from bifurcation.cycle_curves.curve import cycle_bifurcation_curve
from bifurcation.cycles.branches import cycle_diagram
from bifurcation.equilibria.hopf_curves import hopf_diagram
from bifurcation.special_points import PointKind
from reduced_model.family import SpeedFamily
from reduced_model.model import Effects, ShimmyModel
from axles.pressures import TyrePressures


def codim2(diagram, kind):
    return sorted(diagram.points_of(kind), key=lambda p: p.q)


def zero_amplitude_end(curve):
    ends = [e for e in curve.ends if e is not None]
    assert len(ends) == 1 and curve.complete
    return ends[0]


@pytest.mark.slow    # 35 s; in CI: T2 and S2 by test_cycle_curve_ends.py, HH and DH1/DH2 digits by test_hopf.py
def test_figure8_curves_end_at_the_hopf_hopf_and_bautin_points():
    """t0 at 1.5 bar: T1 and T2 are born at the Hopf-Hopf point HH, S1 and S2 at DH1 and DH2."""
    family = SpeedFamily(ShimmyModel(), "t0", pressures=TyrePressures.uniform(1.5 * BAR))
    lo, hi, vmin, vmax = 0.12, 0.26, 100 * KMH, 300 * KMH
    cycles = cycle_diagram(family, 0.25, 0.0, 400 * KMH)
    hopf = hopf_diagram(family, lo, hi, vmin, vmax)
    (hh,) = codim2(hopf, PointKind.HOPF_HOPF)
    dh1, dh2 = codim2(hopf, PointKind.GENERALIZED_HOPF)
    s1, s2 = sorted(cycles.points_of(PointKind.CYCLE_FOLD), key=lambda p: -p.p)
    t1, t2 = sorted(cycles.points_of(PointKind.TORUS), key=lambda p: -p.p)
    for start, target in ((t1, hh), (t2, hh), (s1, dh1), (s2, dh2)):
        curve = cycle_bifurcation_curve(family, start, lo, hi, vmin, vmax)
        V, t0 = zero_amplitude_end(curve)
        assert t0 == pytest.approx(target.q, abs=5e-6)
        assert V == pytest.approx(target.p, abs=0.01 * KMH)
        # The other end is on the window's top edge t0 = 0.26 m.
        assert max(curve.qs) == pytest.approx(hi, abs=1e-9)
    assert agrees_to_printed_digits(paper.SECTION4["t0_hopf_hopf_1.5bar_m"], hh.q)
    assert agrees_to_printed_digits(paper.SECTION4["t0_dh1_1.5bar_m"], dh1.q)
    assert agrees_to_printed_digits(paper.SECTION4["t0_dh2_1.5bar_m"], dh2.q)


@pytest.mark.slow    # 15-30 s; in CI the torus curves at 0.5 bar by tests/cli/test_cycles_cli.py
def test_figure18_torus_and_fold_curves_in_the_pressure_plane():
    """Extended model with half contact length and trail effects (the paper's green curves): T1 and T2 are born
    at HH1 (paper: 0.53 bar), S1 at the generalized Hopf point DH of HB3."""
    family = SpeedFamily(ShimmyModel(effects=Effects.parse("hcl,pt")), "pressure")
    lo, hi, vmin, vmax = 0.2 * BAR, 0.6 * BAR, 100 * KMH, 300 * KMH
    hopf = hopf_diagram(family, lo, hi, vmin, vmax)
    (hh1,) = codim2(hopf, PointKind.HOPF_HOPF)
    (dh,) = codim2(hopf, PointKind.GENERALIZED_HOPF)
    assert hh1.q / BAR == pytest.approx(paper.SECTION5["hcl,pt"]["hopf_hopf_bar"], abs=0.005)
    cycles = cycle_diagram(family, 0.25 * BAR, vmin, vmax)
    (s1,) = cycles.points_of(PointKind.CYCLE_FOLD)
    t1, t2 = sorted(cycles.points_of(PointKind.TORUS), key=lambda p: -p.p)
    for start, target in ((t1, hh1), (t2, hh1), (s1, dh)):
        curve = cycle_bifurcation_curve(family, start, lo, hi, vmin, vmax)
        V, p = zero_amplitude_end(curve)
        assert p == pytest.approx(target.q, abs=2e-4 * BAR)
        assert V == pytest.approx(target.p, abs=0.02 * KMH)
        assert min(curve.qs) == pytest.approx(lo, rel=1e-9)
    assert hh1.q / BAR == pytest.approx(0.532, abs=5e-4) and dh.q / BAR == pytest.approx(0.2884, abs=5e-4)
