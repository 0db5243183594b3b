"""``shimmy figures --model mbs``: the MBS's figures beside the reduced model's.  Cheap: the pairing of two models'
shimmy windows on made-up windows, the registry and the command's refusals; the MBS figures themselves are slow
(each continues the full geometry on Exudyn's twin)."""

import json
from types import SimpleNamespace

import matplotlib.image
import numpy as np
import pytest

from axles.units import from_kmh
from comparisons import figures
from comparisons.cli.main import main
from comparisons.figures.model_differences import compare_windows, stability_difference
from comparisons.windows import ShimmyWindow, ShimmyWindows
from mbs_shimmy.fidelity import Fidelity


def window(mode, low_kmh, high_kmh, open_low=False, open_high=False):
    point = SimpleNamespace()
    return ShimmyWindow(mode, from_kmh(low_kmh), from_kmh(high_kmh), None if open_low else point,
                        None if open_high else point, (point,))


def windows(*items):
    return ShimmyWindows("", 0.0, from_kmh(400.0), tuple(items))


def test_windows_pair_by_mode_and_overlap_and_the_rest_are_in_one_model_only():
    reduced = windows(window("yaw", 26.63, 97.13), window("tramp", 192.98, 345.89))
    full = windows(window("yaw", 39.23, 91.79), window("yaw", 350.0, 400.0, open_high=True))
    found = compare_windows(reduced, full)
    assert [(d.mode, d.reference is not None, d.other is not None) for d in found] == [
        ("yaw", True, True), ("tramp", True, False), ("yaw", False, True)]
    onset, end = found[0].shifts
    assert onset == pytest.approx(from_kmh(39.23 - 26.63)) and end == pytest.approx(from_kmh(91.79 - 97.13))
    names = ("the reduced model", "the full geometry")
    assert found[0].text(names).endswith("(onset +12.60 km/h, end -5.34 km/h)")
    assert found[1].text(names) == "tramp window 192.98-345.89 km/h: in the reduced model only"
    assert found[2].text(names).endswith("in the full geometry only")
    # an open end has no shift
    assert compare_windows(windows(window("yaw", 10, 50, open_low=True)), windows(window("yaw", 20, 60)))[0] \
        .shifts[0] is None


def test_a_window_of_another_mode_is_not_paired_even_where_it_overlaps():
    found = compare_windows(windows(window("yaw", 40, 90)), windows(window("tramp", 50, 80)))
    assert [(d.reference is None, d.other is None) for d in found] == [(False, True), (True, False)]
    assert compare_windows(windows(), windows()) == ()


def test_stability_difference_from_counts_of_unstable_eigenvalues():
    a = np.array([[0, 1, 2], [0, 0, 1]])
    b = np.array([[1, 0, 2], [0, 2, 0]])
    only_a, only_b = stability_difference(a, b)
    np.testing.assert_array_equal(only_a, [[True, False, False], [False, True, False]])
    np.testing.assert_array_equal(only_b, [[False, True, False], [False, False, True]])


def test_every_figure_of_the_mbs_is_drawn_or_explained():
    full = Fidelity.full()
    assert set(figures.available_figures(full)) >= {3, 4, 5, 8, 9, 17, 18}
    for n in figures.PAPER_TITLES:
        reason = figures.unavailable_reason(n, full)
        assert (reason is None) == (n in figures.available_figures(full))
        assert reason is None or reason.strip()
    assert figures.unavailable_reason(9, full) is None
    assert figures.unavailable_reason(2, full).startswith("drawn for the reduced model only")
    name = figures.registry.beside_file_name(figures.BESIDE[5], full)
    assert name == "fig05_pressure_hopf_curves_mbs_full.png"


def test_a_figure_the_mbs_does_not_have_is_refused_with_exit_4(tmp_path, capsys):
    code = main(["figures", "--model", "mbs", "--fidelity", "full", "--out", str(tmp_path), "--only", "2"])
    assert code == 4 and "reduced model only" in capsys.readouterr().err and not list(tmp_path.iterdir())


def test_fidelity_without_the_mbs_is_refused(tmp_path, capsys):
    code = main(["figures", "--fidelity", "full", "--out", str(tmp_path), "--only", "3"])
    err = capsys.readouterr().err
    assert code == 2 and "--model mbs" in err and len(err.strip().splitlines()) == 1


@pytest.mark.slow
def test_mbs_figures_beside_the_reduced_model(tmp_path, capsys):
    """Figures 3, 4 and 5 for the full geometry (about 2 min): drawn, complete, with the windows of both models."""
    code = main(["figures", "--model", "mbs", "--fidelity", "full", "--only", "3,4,5", "--out", str(tmp_path),
                 "--json", "--jobs", "1"])
    out = json.loads(capsys.readouterr().out)
    assert code == 0 and out["fidelity"] == "full"
    made = {f["number"]: f for f in out["figures"]}
    for n, f in made.items():
        assert f["path"].endswith(f"_mbs_full.png") and f["complete"], n
        assert np.std(matplotlib.image.imread(f["path"])[..., :3]) > 0.05, n
    # each model's yaw window at 1.5 bar is paired; the numbers are the models' own Hopf points
    yaw = [x for x in made[4]["notes"] if x.startswith("(a) yaw window: the reduced model")]
    assert len(yaw) == 1 and "(onset +" in yaw[0]
    assert any("orbits checked on Exudyn" in x for x in made[4]["notes"])
    assert any(x.startswith("the full geometry (MBS): highest fold") for x in made[5]["notes"])


@pytest.mark.slow
def test_figure_18_for_the_full_geometry(tmp_path, capsys):
    """Figure 18 beside the reduced model (about 3 min): the reduced model's S1 ends at its DH and T1, T2 at its
    HH1; the full geometry's S curve from its fold at 0.3 bar has every point on Exudyn within 1e-7 and cycles far
    smaller than the reduced model's (a kink's fold: thousandths of a degree), and it ends at its generalized Hopf
    point, located there (it stopped 0.007 bar short by step underflow until Newton's steps at the residual's
    rounding floor were accepted: ContinuationSettings.floor_tol)."""
    code = main(["figures", "--model", "mbs", "--fidelity", "full", "--only", "18", "--out", str(tmp_path),
                 "--json", "--jobs", "1"])
    (fig,) = json.loads(capsys.readouterr().out)["figures"]
    assert code == 0 and fig["complete"]
    assert np.std(matplotlib.image.imread(fig["path"])[..., :3]) > 0.05
    notes = fig["notes"]
    assert any(n.startswith("the reduced model: S1 (cycle_fold, born at DH)") and "generalized Hopf point located"
               in n for n in notes)
    assert sum(n.startswith("the reduced model: T") and "(torus, born at HH1)" in n for n in notes) == 2
    (mbs_s1,) = [n for n in notes if n.startswith("the full geometry (MBS): S1 (cycle_fold, from")]
    assert "left the window" in mbs_s1 and "ends at the generalized Hopf point located at" in mbs_s1
    top = float(mbs_s1.rsplit("max|theta1| ", 1)[1].split("-")[1].split(" ")[0])
    assert top < 0.05
    (check,) = [n for n in notes if n.startswith("the full geometry (MBS): S1:") and "Exudyn" in n]
    checked, total = check.split(": ", 1)[1].split(" critical")[0].split(" of ")
    assert checked == total and int(total) > 10
