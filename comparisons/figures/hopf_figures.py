"""Hopf-curve figures in (V, q) planes (figures 5, 6, 7, 8, 13, 14)."""

from __future__ import annotations

from __future__ import annotations


import numpy as np
from matplotlib.figure import Figure

from reduced_model.model import Effects
from reduced_model.parameters import YANG2024
from reduced_model.special_points import PointKind, PointStatus

from ..plots import stability_grid
from .drawing import _curve_of, _draw_curves, _fold_is_maximum, _incomplete_notes, _label_hopf_points, _located, _mark, _point_note, _pressure_label, _shade_stable, _special_notes, _speed_axis
from .registry import BAR, DiagramKey, DiagramStore, Drawing, FOUR_PRESSURES_BAR, K5_PRESSURES_BAR, MIN_LABEL_SPEED_KMH, P_I0_BAR, PRESSURE_COLOURS, register, VMAX_KMH



def _pressure_key(effects: Effects = Effects(), lo_bar=0.05, hi_bar=3.0, vmin_kmh=0.0, vmax_kmh=VMAX_KMH,
                  n_seeds=9) -> DiagramKey:
    return DiagramKey(effects, "pressure", P_I0_BAR, lo_bar * BAR, hi_bar * BAR, vmin_kmh, vmax_kmh, n_seeds)


@register(5, "pressure_hopf_curves", cost=1)
def draw_pressure_curves(store: DiagramStore) -> Drawing:
    key = _pressure_key()
    diagram, family = store.diagram(key), store.family(key)
    fig = Figure(figsize=(6.8, 4.8))
    ax = fig.subplots()
    _shade_stable(ax, family, diagram, BAR)
    _draw_curves(ax, diagram, BAR, "k")
    _label_hopf_points(ax, family, 1.5 * BAR, BAR, VMAX_KMH)
    folds = _located(diagram, PointKind.HOPF_FOLD)
    notes = []
    if folds:
        f1 = folds[-1]   # the highest-pressure fold: where the last (yaw) mode vanishes
        _mark(ax, f1, BAR, f"F1 ({f1.speed * 3.6:.1f} km/h, {f1.value / BAR:.3f} bar)", offset=(6, 4))
        notes.append(_point_note("F1 (yaw mode vanishes)", f1, "bar", BAR))
        for f in folds[:-1]:
            _mark(ax, f, BAR, f"tramp-mode fold\n({f.speed * 3.6:.1f} km/h, {f.value / BAR:.3f} bar)",
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
    notes += _incomplete_notes("", diagram)
    return Drawing(fig, tuple(notes), diagram.complete)


def _four_pressure_figure(store: DiagramStore, param: str, lo: float, hi: float, ylabel: str,
                          pressures=FOUR_PRESSURES_BAR, unit: str = "m", sci: bool = False) -> tuple:
    fig = Figure(figsize=(8.4, 4.8))
    ax = fig.subplots()
    notes, complete, diagrams = [], True, {}
    speeds = values = None
    stable_count = 0
    for p in pressures:
        key = DiagramKey(Effects(), param, p, lo, hi, 0.0, VMAX_KMH)
        diagram, family = store.diagram(key), store.family(key)
        if speeds is None:
            speeds = np.linspace(diagram.vmin, diagram.vmax, 201)
            values = np.linspace(diagram.lo, diagram.hi, 121)
        stable_count = stable_count + (stability_grid(family, speeds, values) == 0)
        colour = PRESSURE_COLOURS[p]
        _draw_curves(ax, diagram, 1.0, colour, label=_pressure_label(p))
        for f in _located(diagram, PointKind.HOPF_FOLD):
            ax.plot(f.speed * 3.6, f.value, "o", color=colour, ms=4, mfc="white", zorder=4)
        for kind, marker in ((PointKind.HOPF_HOPF, "s"), (PointKind.GENERALIZED_HOPF, "D")):
            for s in _located(diagram, kind):
                ax.plot(s.speed * 3.6, s.value, marker, color=colour, ms=4, mfc="white", zorder=4)
        notes += _special_notes(f"{p:g} bar: ", diagram, unit, 1.0)
        notes += _incomplete_notes(f"{p:g} bar: ", diagram)
        complete &= diagram.complete
        diagrams[p] = diagram
    # One grey level per number of pressures at which straight running is stable: overlapping tints of four
    # colours mix into an unreadable brown.
    n = len(pressures)
    ax.contourf(speeds * 3.6, values, stable_count, levels=np.arange(0.5, n + 1), zorder=0,
                colors=[str(0.97 - 0.06 * k) for k in range(n)])
    ax.axhline(getattr(YANG2024, param), color="0.4", lw=0.7, ls=":")
    _speed_axis(ax)
    ax.set_ylim(lo, hi)
    ax.set_ylabel(ylabel)
    if sci:
        ax.ticklabel_format(axis="y", style="sci", scilimits=(5, 5))
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    return fig, ax, notes, complete, diagrams


_FOUR_NOTE = ("grey: straight running stable at 1, 2, 3 or all 4 pressures (darker: more); "
              "o fold, s Hopf-Hopf, D degenerate Hopf;\ndotted: Table 1 value")


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


@register(8, "trail_hopf_curves_1p5bar", cost=3)
def draw_trail_low_pressure(store: DiagramStore) -> Drawing:
    key = DiagramKey(Effects(), "t0", 1.5, *T0_RANGE, 0.0, VMAX_KMH)
    diagram, family = store.diagram(key), store.family(key)
    fig = Figure(figsize=(6.8, 5.0))
    ax = fig.subplots()
    _shade_stable(ax, family, diagram, 1.0)
    _draw_curves(ax, diagram, 1.0, "k")
    _label_hopf_points(ax, family, YANG2024.t0, 1.0, VMAX_KMH)
    notes = []
    for i, hh in enumerate(_located(diagram, PointKind.HOPF_HOPF), 1):
        name = "HH" if len(_located(diagram, PointKind.HOPF_HOPF)) == 1 else f"HH{i}"
        _mark(ax, hh, 1.0, f"{name} (t = {hh.value:.3f} m)", colour="tab:red", marker="s", offset=(-95, -3))
        notes.append(_point_note(name, hh, "m", 1.0))
    for i, dh in enumerate(_located(diagram, PointKind.GENERALIZED_HOPF), 1):
        _mark(ax, dh, 1.0, f"DH{i} (t = {dh.value:.3f} m)", colour="tab:blue", marker="D", offset=(6, -3))
        notes.append(_point_note(f"DH{i} (criticality changes)", dh, "m", 1.0))
    offsets = iter(((6, -12), (6, -12), (-40, 8), (6, -12)))
    for i, f in enumerate(_located(diagram, PointKind.HOPF_FOLD), 1):
        _mark(ax, f, 1.0, f"F{i} ({f.value:.3f} m)", offset=next(offsets, (6, 4)))
        notes.append(_point_note(f"fold F{i}", f, "m", 1.0))
    for p in diagram.points_of(PointKind.HOPF_FOLD):
        if p.status is not PointStatus.LOCATED or p.speed * 3.6 < MIN_LABEL_SPEED_KMH:
            notes.append(_point_note(f"fold at the window edge, not labelled ({p.status.value})", p, "m", 1.0))
    ax.axhline(YANG2024.t0, color="0.4", lw=0.7, ls=":")
    _speed_axis(ax)
    ax.set_ylim(key.lo, key.hi)
    ax.set_ylabel("pneumatic trail t [m]")
    ax.set_title("Fig. 8: Hopf curves in (V, t) at 1.5 bar (0.6 $p_{i0}$); shaded: straight running stable\n"
                 "HB labels on the Table 1 trail (dotted); torus/saddle-node curves need periodic orbits",
                 fontsize=9)
    notes += _incomplete_notes("", diagram)
    return Drawing(fig, tuple(notes), diagram.complete)


@register(13, "relaxation_length_hopf_curves", cost=12)
def draw_relaxation_length(store: DiagramStore) -> Drawing:
    fig, ax, notes, complete, _ = _four_pressure_figure(store, "sigma0", 0.01, 1.5,
                                                        "relaxation length σ [m]")
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
    for p, low_name, high_name in labelled:
        diagram = diagrams.get(p)
        if diagram is None:
            continue
        folds = _located(diagram, PointKind.HOPF_FOLD)
        top = max(diagram.curves, key=lambda c: np.min(c.values))
        upper = [f for f in folds if _curve_of(diagram, f) is top and not _fold_is_maximum(diagram, f)]
        lower_max = sorted((f for f in folds if _curve_of(diagram, f) is not top and _fold_is_maximum(diagram, f)),
                           key=lambda f: f.speed)
        if len(diagram.curves) > 1 and upper:
            f = min(upper, key=lambda f: f.value)
            _mark(ax, f, 1.0, f"{high_name} ({f.value / 1e5:.2f}e5 N/m)", colour=PRESSURE_COLOURS[p],
                  offset=(8, -4))
        if low_name and lower_max:
            f = lower_max[0]
            _mark(ax, f, 1.0, f"{low_name} ({f.value / 1e5:.2f}e5 N/m)", colour=PRESSURE_COLOURS[p],
                  text_at=(105.0, 1.75e5))
    ax.set_title("Fig. 14: Hopf curves in (V, $k_5$) at four pressures\n" + _FOUR_NOTE, fontsize=9)
    return Drawing(fig, tuple(notes), complete)
