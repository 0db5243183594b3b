"""Labels that never cover data: every figure kind of the verification report is drawn from made-up numbers
and each text artist (annotations, axis texts, legends) is measured by the renderer against the display
positions of the line data (segments filled in every 2 px) and against the other texts."""

from types import SimpleNamespace

import numpy as np
import pytest
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.legend import Legend
from matplotlib.text import Text

from axles.units import KMH
from bifurcation.special_points import PointKind
from comparisons.figures import cycle_plots, margin_figures
from comparisons.verify import report_figures


@pytest.fixture
def drawn(monkeypatch):
    """Figures handed to save_figure, instead of files."""
    figures = []
    for module in (report_figures, cycle_plots, margin_figures):
        monkeypatch.setattr(module, "save_figure", lambda fig, path: figures.append(fig))
    return figures


def line_pixels(ax):
    """Independent of the code under test: every Line2D's data in display pixels, filled in every 2 px."""
    out = []
    box = ax.get_window_extent()
    for line in ax.get_lines():
        xy = line.get_transform().transform(np.column_stack(line.get_data()).astype(float))
        xy = xy[np.all(np.isfinite(xy), axis=1)]
        if line.get_linestyle() in ("None", "none", "", " ") or len(xy) < 2:
            out.append(xy)
            continue
        for a, b in zip(xy[:-1], xy[1:]):
            n = max(int(np.hypot(*(b - a)) / 2.0), 1)
            out.append(a + np.linspace(0.0, 1.0, n + 1)[:, None] * (b - a))
    for contour in ax.collections:      # contour lines (not the filled bands)
        if getattr(contour, "filled", True):
            continue
        for path in contour.get_paths():
            xy = contour.get_transform().transform(path.vertices)
            for a, b in zip(xy[:-1], xy[1:]):
                n = max(int(np.hypot(*(b - a)) / 2.0), 1)
                out.append(a + np.linspace(0.0, 1.0, n + 1)[:, None] * (b - a))
    xy = np.vstack(out) if out else np.zeros((0, 2))
    return xy[(xy[:, 0] > box.x0) & (xy[:, 0] < box.x1) & (xy[:, 1] > box.y0) & (xy[:, 1] < box.y1)]


def text_boxes(fig, renderer):
    """(what, Bbox) of every visible, non-empty text: titles, axis labels, annotations, legends (as a whole);
    tick labels are left out (matplotlib lays them out itself)."""
    boxes = []
    for ax in fig.axes:
        for t in [ax.title, ax._left_title, ax._right_title, ax.xaxis.label, ax.yaxis.label, *ax.texts]:
            if t.get_visible() and t.get_text().strip():
                boxes.append((t.get_text(), Text.get_window_extent(t, renderer)))
        for child in ax.get_children():
            if isinstance(child, Legend) and child.get_visible():
                boxes.append(("legend", child.get_window_extent(renderer)))
    for legend in fig.legends:
        boxes.append(("figure legend", legend.get_window_extent(renderer)))
    if fig._suptitle is not None:
        boxes.append((fig._suptitle.get_text(), fig._suptitle.get_window_extent(renderer)))
    return boxes


def overlaps(fig):
    """Texts that cover line data, and pairs of texts that cover each other (1 px of slack)."""
    FigureCanvasAgg(fig)
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    boxes = text_boxes(fig, renderer)
    found = []
    for ax in fig.axes:
        if not ax.get_visible() or ax.get_label() == "<colorbar>":
            continue
        data = line_pixels(ax)
        for what, b in boxes:
            inside = (data[:, 0] > b.x0 + 1) & (data[:, 0] < b.x1 - 1) & (data[:, 1] > b.y0 + 1) & (data[:, 1] < b.y1 - 1)
            if np.any(inside):
                found.append(f"'{what}' covers {int(inside.sum())} px of data")
        for patch in ax.patches:          # bars
            pb = patch.get_window_extent(renderer)
            for what, b in boxes:
                if pb.width > 0 and pb.height > 0 and b.x0 + 1 < pb.x1 and pb.x0 + 1 < b.x1 and b.y0 + 1 < pb.y1 \
                        and pb.y0 + 1 < b.y1:
                    found.append(f"'{what}' covers a bar")
    for i, (wa, a) in enumerate(boxes):
        for wb, b in boxes[i + 1:]:
            if a.x0 + 1 < b.x1 and b.x0 + 1 < a.x1 and a.y0 + 1 < b.y1 and b.y0 + 1 < a.y1:
                found.append(f"'{wa}' and '{wb}' overlap")
    return found


def test_the_checker_finds_a_label_on_a_curve():
    from matplotlib.figure import Figure
    fig = Figure()
    ax = fig.subplots()
    ax.plot([0, 10], [0, 10])
    ax.annotate("on the line", (5, 5))
    ax.text(1, 8, "clear of it")
    assert overlaps(fig) == ["'on the line' covers 14 px of data"] or (
        len(overlaps(fig)) == 1 and "'on the line' covers" in overlaps(fig)[0])


def test_hopf_speeds(drawn):
    curves = {"section 3": [(np.linspace(1.0, 3.0, 40), 20 + 12 * np.linspace(1.0, 3.0, 40)),
                            (np.linspace(1.0, 2.0, 40), 300 - 100 * np.linspace(0.0, 1.0, 40))]}
    points = {"section 3": {"reduced": [(1.5, 38.0), (2.5, 50.0)], "paper": [(1.5, 39.0), (2.5, 50.2)],
                            "mbs_reduced": [(1.5, 38.0), (2.5, 50.0)], "mbs_full": [(1.5, 30.0), (2.5, 45.0)]}}
    report_figures.plot_hopf_speeds(points, "x.png", curves=curves)
    (fig,) = drawn
    assert overlaps(fig) == []
    top, bottom = fig.axes[:2]
    # The paper's 1 km/h shows in the lower panel: its marker sits 1 km/h above the zero line.
    paper = [line for line in bottom.get_lines() if line.get_marker() == "x"][0]
    np.testing.assert_allclose(paper.get_ydata(), [1.0, 0.2], atol=1e-9)
    assert len([line for line in top.get_lines() if line.get_linestyle() == "-"]) == 2   # the curves


def test_jump_histories(drawn):
    t = np.arange(0.0, 60.0, 0.01)
    speed = 150 + t
    runs = [report_figures.RunHistory(model, t, speed, a * np.sin(2 * np.pi * 5 * t) * (t > 20),
                                      0.5 * a * np.sin(2 * np.pi * 5 * t) * (t > 20), [(20.0 + k, 170.0 + k, "yaw -> tramp")])
            for k, (model, a) in enumerate((("reduced", 10.0), ("mbs", 9.0)))]
    exp = report_figures.Experiment("ramp up, 1.5 bar", runs, {"S1": 184.75})
    report_figures.plot_jump_histories([exp, exp], "x.png", "jumps")
    assert overlaps(drawn[0]) == []


def test_assumption_tornado(drawn):
    shifts = [report_figures.AssumptionShift(p, name, s) for p in (1.5, 2.5) for name, s in
              (("full", [12.0, -3.0]), ("kingpin_offset", [0.5, None]), ("caster", []), ("hcl", [-7.0, 2.0]))]
    report_figures.plot_assumption_tornado(shifts, "x.png")
    assert overlaps(drawn[0]) == []


def _point(p, amp_deg, kind=None):
    return SimpleNamespace(p=p, kind=kind, bracket=(p, p), data={"amplitude": np.radians([amp_deg] * 8)},
                           stable=True, max_abs=lambda name, a=amp_deg: np.radians(a))


def _diagram(spans, hopf, specials=()):
    branches = []
    for lo, hi, height in spans:
        v = np.linspace(lo, hi, 30)
        pts = [_point(x, height * np.sin(np.pi * (x - lo) / (hi - lo)) + 1e-3) for x in v[1:-1]]
        branches.append(SimpleNamespace(points=pts, start=SimpleNamespace(p=lo), end=SimpleNamespace(p=hi),
                                        special_points=[s for s in specials if lo <= s.p <= hi]))
    return SimpleNamespace(branches=branches, hopf=[SimpleNamespace(p=h) for h in hopf], p_min=0.0,
                           p_max=400 * KMH)


def test_model_branches_names_plurals_units_and_enlarges_a_narrow_branch(drawn):
    kmh = KMH
    reduced = _diagram([(26 * kmh, 97 * kmh, 9.8), (193 * kmh, 346 * kmh, 3.2)],
                       [26 * kmh, 97 * kmh, 193 * kmh, 346 * kmh],
                       [_point(200 * kmh, 2.0, PointKind.TORUS), _point(190 * kmh, 1.0, PointKind.CYCLE_FOLD)])
    full = _diagram([(0.5 * kmh, 3.7 * kmh, 0.8), (38 * kmh, 92 * kmh, 6.9)], [38 * kmh],
                    [_point(195 * kmh, 0.0, PointKind.CYCLE_FOLD)])
    cycle_plots.plot_model_branches([("reduced model", reduced, "C0"), ("full geometry, MBS", full, "C3")], "x.png",
                                    title="Limit cycles at 1.5 bar, t0 = 0.25 m: reduced model and full geometry")
    (fig,) = drawn
    assert overlaps(fig) == []
    FigureCanvasAgg(fig)
    fig.canvas.draw()
    texts = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    assert "full geometry, MBS (1 Hopf point)" in texts and "reduced model (4 Hopf points)" in texts
    assert len(fig.axes) == 2 and fig.axes[1].get_xlim()[1] < 6.0       # the 0.5-3.7 km/h branch, enlarged


def test_margin_map_is_centred_at_zero_with_a_zero_tick(drawn):
    speeds = np.linspace(0.0, 400 * KMH, 60)
    pressures = np.linspace(1.0e5, 3.0e5, 30)
    zeta = 0.0485 - 0.108 * np.exp(-((speeds[None, :] - 20) / 10) ** 2) * np.ones((30, 1))
    minimum = SimpleNamespace(speed_kmh=72.0, pressure_bar=2.0, damping_ratio=float(zeta.min()), mode="yaw")
    study = SimpleNamespace(speeds=speeds, pressures=pressures, damping_ratio=zeta, minimum=minimum)
    margin_figures.plot_margin_maps([(study, "margins", ())], "x.png")
    (fig,) = drawn
    bar = [ax for ax in fig.axes if ax.get_label() == "<colorbar>"][0]
    ticks = bar.get_yticks()
    assert 0.0 in ticks and np.all(np.abs(ticks * 100 - np.round(ticks * 100)) < 1e-9)   # round ticks, 0 among them
    filled = [c for c in fig.axes[0].collections if hasattr(c, "levels")][0]
    assert 0.0 in filled.levels and filled.norm(0.0) == pytest.approx(0.5)
    assert overlaps(fig) == []
    assert f"star: minimum {zeta.min():+.3f} (yaw) at 72 km/h, 2 bar" in fig.axes[0].get_title()


def test_paper_cycle_diagram_labels_clear_of_the_data():
    """Figure 3 (the paper's cycle-diagram kind, about 2 s): the Hopf points' names sit off the straight-running
    line and the branches, placed after the figure's layout is final."""
    from comparisons.figures.registry import REGISTRY, DiagramStore
    drawing = REGISTRY[3].draw(DiagramStore())
    assert overlaps(drawing.figure) == []
    assert {t.get_text() for ax in drawing.figure.axes for t in ax.texts} >= {"HB1", "HB2"}


@pytest.mark.slow
@pytest.mark.parametrize("number", [4, 5, 9, 14, 15, 17, 18])
def test_paper_figures_labels_and_keys_clear_of_the_data(number):
    """The paper's other figure kinds (15-150 s each): labels placed by place_labels, keys off the curves."""
    from comparisons.figures.registry import REGISTRY, DiagramStore
    assert overlaps(REGISTRY[number].draw(DiagramStore()).figure) == []


class _SwappedStore:
    """A :class:`DiagramStore` whose MBS slot holds the reduced model at other settings, so that the figures drawn
    for two models can be checked for their text in a few seconds (the drawing code is the same for any family)."""

    def __init__(self, swap):
        from comparisons.figures.registry import DiagramStore
        self.store, self.swap = DiagramStore(), swap

    def family(self, key):
        return self.store.family(self.swap(key) if key.fidelity is not None else key)

    def diagram(self, key):
        return self.store.diagram(self.swap(key) if key.fidelity is not None else key)


def test_hopf_plane_of_two_models_labels_clear_of_the_data():
    """Figure 5's kind for two models (about 3 s): both models' Hopf curves, special points and the hatched
    stability difference, with every label clear of the curves and of the other texts."""
    from dataclasses import replace

    from comparisons.figures import beside_figures
    from comparisons.figures.hopf_figures import pressure_key
    from mbs_shimmy.fidelity import Fidelity
    from reduced_model.model import Effects
    store = _SwappedStore(lambda key: replace(key, fidelity=None, effects=Effects.parse("hcl")))
    key = replace(pressure_key(lo_bar=0.5, hi_bar=3.0, vmax_kmh=150.0), n_seeds=5)
    drawing = beside_figures._plane_figure(store, key, Fidelity.full(), 1e5, "bar", 1.5e5, "p [bar]", "two models")
    assert overlaps(drawing.figure) == []
    ax = drawing.figure.axes[0]
    assert {line.get_color() for line in ax.get_lines() if line.get_linestyle() == "-"} >= {"k", "tab:red"}
    assert any(note.startswith("at 1.5 bar: yaw window: the reduced model") for note in drawing.notes)


def test_cycle_panels_of_two_models_labels_clear_of_the_data(monkeypatch):
    """Figures 3, 4 and 9's kind for two models (about 3 s): a window in one model only is hatched, both models'
    unstable straight running is a bar below the axis, and no label covers data."""
    from dataclasses import replace

    from comparisons.figures import beside_figures
    from comparisons.figures.registry import CycleKey, DiagramStore, store_cycles
    from mbs_shimmy.fidelity import Fidelity
    monkeypatch.setattr(beside_figures, "store_cycles", lambda store, key: store_cycles(
        store, replace(key, fidelity=None, pressure_bar=2.0) if key.fidelity is not None else key))
    monkeypatch.setattr(beside_figures, "_checked", lambda family, diagram: (1e-9, 1, 0))
    drawing = beside_figures.cycle_panels_beside(DiagramStore(), [("1.5 bar", CycleKey(1.5, 400.0))], 400.0,
                                                 "two models", Fidelity.full())
    assert overlaps(drawing.figure) == []
    top = drawing.figure.axes[0]
    assert any(c.get_hatch() == ".." for c in top.collections)    # the tramp window of one model only
    bars = [line for line in top.get_lines() if line.get_linewidth() == 3.0]
    assert {line.get_color() for line in bars} == {"k", "tab:red"}
    assert any("tramp window" in note and "in the reduced model only" in note for note in drawing.notes)
