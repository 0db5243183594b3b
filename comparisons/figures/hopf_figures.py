"""Hopf-curve figures in (V, q) planes (figures 5, 6, 7, 13, 14; figure 8 adds cycle curves, see
:mod:`.cycle_curve_figures`)."""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

from axles.units import BAR, kmh
from comparisons.figures.drawing import (
    SPECIAL_MARKERS,
    _curve_of,
    _draw_curves,
    _fold_is_maximum,
    _incomplete_notes,
    _label_hopf_points,
    _located,
    _mark,
    _point_note,
    _pressure_label,
    _shade_stable,
    _special_notes,
    _speed_axis,
    marker_key,
)
from comparisons.figures.plots import place_labels, stability_grid
from comparisons.figures.registry import (
    FOUR_PRESSURES_BAR,
    K5_PRESSURES_BAR,
    P_I0_BAR,
    PRESSURE_COLOURS,
    VMAX_KMH,
    DiagramKey,
    DiagramStore,
    Drawing,
    register,
)
from bifurcation.special_points import PointKind
from reduced_model.model import Effects
from axles.parameters import YANG2024


def pressure_key(effects: Effects = Effects(), lo_bar=0.05, hi_bar=3.0, vmin_kmh=0.0, vmax_kmh=VMAX_KMH,
                  n_seeds=9) -> DiagramKey:
    return DiagramKey(effects, "pressure", P_I0_BAR, lo_bar * BAR, hi_bar * BAR, vmin_kmh, vmax_kmh, n_seeds)


@register(5, "pressure_hopf_curves", cost=1)
def draw_pressure_curves(store: DiagramStore) -> Drawing:
    key = pressure_key()
    diagram, family = store.diagram(key), store.family(key)
    fig = Figure(figsize=(6.8, 4.8))
    ax = fig.subplots()
    _shade_stable(ax, family, diagram, BAR)
    _draw_curves(ax, diagram, BAR, "k")
    hopf_labels = _label_hopf_points(ax, family, 1.5 * BAR, BAR, VMAX_KMH)
    folds = _located(diagram, PointKind.HOPF_FOLD)
    notes = []
    if folds:
        f1 = folds[-1]   # the highest-pressure fold: where the last (yaw) mode vanishes
        _mark(ax, f1, BAR, f"F1 ({kmh(f1.p):.1f} km/h, {f1.q / BAR:.3f} bar)", offset=(6, 4))
        notes.append(_point_note("F1 (yaw mode vanishes)", f1, "bar", BAR))
        for f in folds[:-1]:
            _mark(ax, f, BAR, f"tramp-mode fold\n({kmh(f.p):.1f} km/h, {f.q / BAR:.3f} bar)",
                  offset=(-40, 8))
            notes.append(_point_note("tramp-mode fold (tramp mode vanishes)", f, "bar", BAR))
    ax.text(70, 1.0, "yaw\nmode", ha="center", fontsize=9)
    ax.text(270, 1.0, "tramp mode", ha="center", fontsize=9)
    ax.text(300, 2.5, "no shimmy (shaded)", ha="center", fontsize=9)
    _speed_axis(ax)
    ax.set_ylim(key.lo / BAR, key.hi / BAR)
    ax.set_ylabel("inflation pressure $p_i$ [bar]")
    ax.set_title("Fig. 5: Hopf curves, lateral force depends on pressure (section 3 model)\n"
                 "shaded: straight running stable", fontsize=10)
    place_labels(ax, hopf_labels)      # the limits are final
    notes += _incomplete_notes("", diagram)
    return Drawing(fig, tuple(notes), diagram.complete)


def _four_pressure_figure(store: DiagramStore, param: str, lo: float, hi: float, ylabel: str,
                          pressures=FOUR_PRESSURES_BAR, unit: str = "m", sci: bool = False, zoom=None) -> tuple:
    """Hopf curves in (V, param) at four pressures; ``zoom`` = (vlo, vhi, qlo, qhi) adds an inset where the
    curves crowd (their markers would collide at full scale)."""
    fig = Figure(figsize=(8.4, 4.8))
    ax = fig.subplots()
    panels = [ax]
    if zoom is not None:
        inset = ax.inset_axes((0.58, 0.56, 0.4, 0.4))
        inset.set_xlim(zoom[0], zoom[1])
        inset.set_ylim(zoom[2], zoom[3])
        inset.tick_params(labelsize=7)
        ax.indicate_inset_zoom(inset, edgecolor="0.3")
        panels.append(inset)
    notes, complete, diagrams = [], True, {}
    speeds = values = None
    stable_count = 0
    for p in pressures:
        key = DiagramKey(Effects(), param, p, lo, hi, 0.0, VMAX_KMH)
        diagram, family = store.diagram(key), store.family(key)
        if speeds is None:
            speeds = np.linspace(diagram.p_min, diagram.p_max, 201)
            values = np.linspace(diagram.lo, diagram.hi, 121)
        stable_count = stable_count + (stability_grid(family, speeds, values) == 0)
        colour = PRESSURE_COLOURS[p]
        for panel in panels:
            _draw_curves(panel, diagram, 1.0, colour, label=_pressure_label(p) if panel is ax else None)
            for kind, marker, _ in SPECIAL_MARKERS:
                for s in _located(diagram, kind):
                    panel.plot(kmh(s.p), s.q, marker, color=colour, ms=4, mfc="white", zorder=4)
        notes += _special_notes(f"{p:g} bar: ", diagram, unit, 1.0)
        notes += _incomplete_notes(f"{p:g} bar: ", diagram)
        complete &= diagram.complete
        diagrams[p] = diagram
    # One grey level per number of pressures at which straight running is stable: overlapping tints of four
    # colours mix into an unreadable brown.
    n = len(pressures)
    greys = [str(0.97 - 0.06 * k) for k in range(n)]
    for panel in panels:
        panel.contourf(kmh(speeds), values, stable_count, levels=np.arange(0.5, n + 1), zorder=0, colors=greys)
        panel.axhline(getattr(YANG2024, param), color="0.4", lw=0.7, ls=":")
    _speed_axis(ax)
    ax.set_ylim(lo, hi)
    ax.set_ylabel(ylabel)
    if sci:
        ax.ticklabel_format(axis="y", style="sci", scilimits=(5, 5))
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0), title="tyre pressure", title_fontsize=8)
    marker_key(ax, shading=[(greys[0], "straight running stable at one pressure"),
                            (greys[-1], f"... at all {n} (darker: more)")],
               loc="upper left", bbox_to_anchor=(1.01, 0.55), title="markers and shading", title_fontsize=8)
    return fig, ax, notes, complete, diagrams


_FOUR_NOTE = "markers and shading: see the key on the right; dotted: Table 1 value"


@register(6, "half_contact_length_hopf_curves", cost=3)
def draw_half_contact_length(store: DiagramStore) -> Drawing:
    fig, ax, notes, complete, _ = _four_pressure_figure(store, "a0", 0.05, 0.5, "half-contact length a [m]")
    ax.set_title("Fig. 6: Hopf curves in (V, a) at four pressures\n" + _FOUR_NOTE, fontsize=9)
    return Drawing(fig, tuple(notes), complete)


T0_RANGE = (0.02, 0.32)


@register(7, "trail_hopf_curves", cost=8)
def draw_trail_curves(store: DiagramStore) -> Drawing:
    fig, ax, notes, complete, _ = _four_pressure_figure(store, "t0", *T0_RANGE, "pneumatic trail t [m]")
    ax.set_title("Fig. 7: Hopf curves in (V, t) at four pressures\n" + _FOUR_NOTE, fontsize=9)
    return Drawing(fig, tuple(notes), complete)


@register(13, "relaxation_length_hopf_curves", cost=12)
def draw_relaxation_length(store: DiagramStore) -> Drawing:
    # The folds of the four low-speed loops crowd below 0.1 m and 50 km/h: shown enlarged.
    fig, ax, notes, complete, _ = _four_pressure_figure(store, "sigma0", 0.01, 1.5, "relaxation length σ [m]",
                                                        zoom=(5.0, 50.0, 0.01, 0.08))
    ax.set_title("Fig. 13: Hopf curves in (V, σ) at four pressures\n" + _FOUR_NOTE, fontsize=9)
    return Drawing(fig, tuple(notes), complete)


@register(14, "vertical_stiffness_hopf_curves", cost=6)
def draw_vertical_stiffness(store: DiagramStore) -> Drawing:
    fig, ax, notes, complete, diagrams = _four_pressure_figure(
        store, "k5_0", 1.5e5, 7.0e5, "vertical stiffness $k_5$ [N/m]", pressures=K5_PRESSURES_BAR,
        unit="N/m", sci=True)
    # The paper's names: at 1.024 p_i0 the modes separate at F1 (vertex of the raised part of the lower curve)
    # and F2 (lowest point of the upper, yaw-mode curve); F2 moves to F3 at higher pressure.
    labelled = [(2.56, "F1", "F2"), (2.7, None, "F3")]
    marks = []
    for p, low_name, high_name in labelled:
        diagram = diagrams.get(p)
        if diagram is None:
            continue
        folds = _located(diagram, PointKind.HOPF_FOLD)
        top = max(diagram.curves, key=lambda c: np.min(c.qs))
        upper = [f for f in folds if _curve_of(diagram, f) is top and not _fold_is_maximum(diagram, f)]
        lower_max = sorted((f for f in folds if _curve_of(diagram, f) is not top and _fold_is_maximum(diagram, f)),
                           key=lambda f: f.p)
        if len(diagram.curves) > 1 and upper:
            f = min(upper, key=lambda f: f.q)
            _mark(ax, f, 1.0, f"{high_name} ({f.q / 1e5:.2f}e5 N/m)", colour=PRESSURE_COLOURS[p], items=marks)
        if low_name and lower_max:
            f = lower_max[0]
            _mark(ax, f, 1.0, f"{low_name} ({f.q / 1e5:.2f}e5 N/m)", colour=PRESSURE_COLOURS[p], items=marks)
    ax.set_title("Fig. 14: Hopf curves in (V, $k_5$) at four pressures\n" + _FOUR_NOTE, fontsize=9)
    place_labels(ax, marks)     # the limits are final
    return Drawing(fig, tuple(notes), complete)
