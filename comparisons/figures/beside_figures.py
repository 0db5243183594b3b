"""The paper's figures for the multibody model beside the reduced model (``shimmy figures --model mbs``): the same
axes, both models drawn (the reduced model black, the MBS red), and what differs marked.

- Hopf curves in a (V, q) plane (figures 5 and 8): where straight running is stable in one model only is hatched in
  that model's colour; each model's folds, Hopf-Hopf and degenerate Hopf points are marked in its colour, and its
  Hopf points on the paper's line q = const are named HB1, HB2, ... in its colour.
- Limit cycles in speed (figures 3, 4 and 9): each model's branches (solid stable, dashed unstable) and special
  points; below the axis a bar per model where its straight running is unstable, and a hatched span where a shimmy
  window exists in one model only.  The notes pair the windows (:mod:`.model_differences`): the shift of each Hopf
  speed, the windows in one model only.

Every MBS orbit drawn is checked on Exudyn's own right-hand side (:func:`comparisons.studies.exudyn_check.
checked_on_exudyn`, as ``shimmy cycles --model mbs``); the notes give the largest residual.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Patch

from axles.axle import interface_text
from axles.units import BAR, KMH, kmh
from bifurcation.equilibria.hopf import find_hopf_points
from bifurcation.special_points import PointKind
from comparisons.figures.cycle_figures import TRAIL_FIG9, _cycle_notes
from comparisons.figures.cycle_plots import CURVE_STYLES, LABELS, branch_lines, special_point_labels
from comparisons.figures.drawing import SPECIAL_MARKERS, _incomplete_notes, _located, _point_note, _speed_axis
from comparisons.figures.hopf_figures import T0_RANGE, pressure_key
from comparisons.figures.model_differences import compare_windows, stability_difference, windows_of
from comparisons.figures.plots import place_labels, stability_grid
from comparisons.figures.registry import (
    EFFECT_STYLES,
    FIG9_VMAX_KMH,
    P_I0_BAR,
    VMAX_KMH,
    CycleKey,
    DiagramKey,
    DiagramStore,
    Drawing,
    register,
    store_cycles,
)
from mbs_shimmy.fidelity import Fidelity
from reduced_model.model import STATE_NAMES, Effects
from axles.parameters import YANG2024

REFERENCE_COLOUR = "k"
MBS_COLOUR = "tab:red"
COLOURS = (REFERENCE_COLOUR, MBS_COLOUR)
HATCHES = ("////", "\\\\\\\\")         # stable in the reduced model only, in the MBS only
REFERENCE_NAME = "the reduced model"
GRID = (201, 121)       # speeds, parameter values of the stability grids (as the reduced model's figures)
FOLD_NAMES = {PointKind.HOPF_FOLD: "F", PointKind.HOPF_HOPF: "HH", PointKind.GENERALIZED_HOPF: "DH"}



def mbs_name(fidelity: Fidelity) -> str:
    """The MBS as the figures name it: "the full geometry (MBS)", "the MBS, every assumption on", ..."""
    return {"full": "the full geometry (MBS)", "reduced": "the MBS, every assumption on"}.get(
        fidelity.label, f"the MBS (assumptions on: {fidelity.label})")


def _hatch(ax, speeds, values, mask, colour, hatch: str) -> None:
    if not mask.any():
        return
    filled = ax.contourf(kmh(speeds), values, mask.astype(float), levels=[0.5, 1.5], colors="none", hatches=[hatch])
    filled.set_edgecolor(colour)
    filled.set_linewidth(0.0)


def hopf_plane(ax, store: DiagramStore, key: DiagramKey, fidelity: Fidelity, factor: float, unit: str,
               line: float | None, legend: bool = True, every_label: bool = True) -> tuple[list, list, bool]:
    """Both models' Hopf curves of ``key`` in (V, q) with the stability difference hatched; their special points
    marked (labelled, or with ``every_label`` False only each model's highest fold) and Hopf points on the line
    q = ``line`` named (none without a line).  Returns (label items, notes, complete)."""
    keys = (key, replace(key, fidelity=fidelity))
    names = (REFERENCE_NAME, mbs_name(fidelity))
    speeds = np.linspace(key.vmin_kmh * KMH, key.vmax_kmh * KMH, GRID[0])
    values = np.linspace(key.lo, key.hi, GRID[1])
    grids = [stability_grid(store.family(k), speeds, values) for k in keys]
    both = (grids[0] == 0) & (grids[1] == 0)
    ax.contourf(kmh(speeds), values / factor, both.astype(float), levels=[0.5, 1.5], colors=["0.88"])
    only = stability_difference(*grids)
    for mask, colour, hatch in zip(only, COLOURS, HATCHES):
        _hatch(ax, speeds, values / factor, mask, colour, hatch)
    items, notes, complete, found = [], [], True, []
    for grid, k, name, colour in zip(grids, keys, names, COLOURS):
        diagram, family = store.diagram(k), store.family(k)
        for c in diagram.curves:
            ax.plot(kmh(c.ps), c.qs / factor, "-", color=colour, lw=1.5 if colour == MBS_COLOUR else 1.2)
        folds = _located(diagram, PointKind.HOPF_FOLD)
        for kind, marker, _ in SPECIAL_MARKERS:
            for s in _located(diagram, kind):
                ax.plot(kmh(s.p), s.q / factor, marker, color=colour, ms=5, mfc="white", mew=1.3, zorder=5)
                if every_label or s is folds[-1]:
                    items.append((kmh(s.p), s.q / factor, f"{FOLD_NAMES[kind]} {s.q / factor:.3g} {unit}", colour))
                notes.append(f"{name}: " + _point_note(kind.value.replace("_", " "), s, unit, factor))
        if folds:
            notes.append(f"{name}: highest fold {folds[-1].q / factor:.4g} {unit} at {kmh(folds[-1].p):.2f} km/h")
        notes += _incomplete_notes(f"{name}: ", diagram)
        complete &= diagram.complete
        notes.append(f"{name}: {100 * np.mean(grid == 0):.1f} % of the window stable"
                     + ("" if not folds else f"; shimmy-free above {folds[-1].q / factor:.4g} {unit}"))
        if line is not None:
            hopf = find_hopf_points(family, line, speeds[0], speeds[-1])
            for i, h in enumerate(sorted(hopf, key=lambda h: h.p), 1):
                ax.plot(kmh(h.p), line / factor, ".", color=colour, ms=7, zorder=5)
                items.append((kmh(h.p), line / factor, f"HB{i}", colour))
            found.append(windows_of(family, hopf, speeds[0], speeds[-1]))
    if line is not None:
        notes += [f"at {line / factor:g} {unit}: " + d.text(names) for d in compare_windows(*found)]
        ax.axhline(line / factor, color="0.5", lw=0.7, ls=":")
    for mask, name in zip(only, names):
        notes.append(f"straight running stable in {name} only: {100 * np.mean(mask):.1f} % of the window")
    if legend:
        ax.legend(handles=plane_key(fidelity), fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0),
                  framealpha=0.9)
    return items, notes, complete


def plane_key(fidelity: Fidelity) -> list:
    """The key of :func:`hopf_plane`: each model's colour, the shading and the hatching."""
    names = (REFERENCE_NAME, mbs_name(fidelity))
    handles = [Line2D([], [], color=c, lw=1.4, label=n) for c, n in zip(COLOURS, names)]
    handles += [Patch(color="0.88", label="straight running stable in both")]
    handles += [Patch(facecolor="white", edgecolor=c, hatch=h, label=f"stable in {n} only")
                for c, n, h in zip(COLOURS, names, HATCHES)]
    return handles


def _plane_figure(store, key, fidelity, factor, unit, line, ylabel, title) -> Drawing:
    fig = Figure(figsize=(9.6, 5.0))
    ax = fig.subplots()
    items, notes, complete = hopf_plane(ax, store, key, fidelity, factor, unit, line)
    _speed_axis(ax, key.vmax_kmh, key.vmin_kmh)
    ax.set_ylim(key.lo / factor, key.hi / factor)
    ax.set_ylabel(ylabel)
    ax.set_title(title, fontsize=9)
    fig.tight_layout()
    place_labels(ax, items, fontsize=7)        # the layout is final
    return Drawing(fig, tuple(notes), complete)


@register(5, "pressure_hopf_curves", cost=70, beside=True)
def draw_pressure_beside(store: DiagramStore, fidelity: Fidelity) -> Drawing:
    return _plane_figure(store, pressure_key(), fidelity, BAR, "bar", 1.5 * BAR, "inflation pressure $p_i$ [bar]",
                         f"Fig. 5: {mbs_name(fidelity)} in red, {REFERENCE_NAME} in black; Hopf curves in "
                         f"(V, $p_i$), lateral force only\nHB labels on the 1.5 bar line (dotted); hatched: straight "
                         f"running stable in one model only")


# Figure 8's cycle curves start from each model's cycles at t = 0.25 m (figure 9a's), the full geometry's above
# FIG8_MBS_VMIN_KMH only: its branch born at 3.56 km/h grows to yaw cycles of 50-60 deg that lift a wheel, each on
# 640 mesh intervals (52.6 km/h after 9.5 min, docs/results.md); the S and T points of figure 9a lie at 150-350
# km/h.
FIG8_MBS_VMIN_KMH = 100.0


@register(8, "trail_hopf_curves_1.5bar", cost=400, beside=True)
def draw_trail_beside(store: DiagramStore, fidelity: Fidelity) -> Drawing:
    from bifurcation.cycles.branches import cycle_diagram
    from comparisons.figures.cycle_curve_figures import FIG8_START_T, _draw_cycle_curves
    from comparisons.studies.exudyn_check import curve_on_exudyn
    key = DiagramKey(Effects(), "t0", 1.5, *T0_RANGE, 0.0, VMAX_KMH)
    fig = Figure(figsize=(9.6, 5.0))
    ax = fig.subplots()
    items, notes, complete = hopf_plane(ax, store, key, fidelity, 1.0, "m", YANG2024.t0, legend=False)
    for k, colour, name, vmin in ((key, REFERENCE_COLOUR, REFERENCE_NAME, 0.0),
                                  (replace(key, fidelity=fidelity), MBS_COLOUR, mbs_name(fidelity),
                                   FIG8_MBS_VMIN_KMH)):
        family = store.family(k)
        cycles = cycle_diagram(family, FIG8_START_T, vmin * KMH, VMAX_KMH * KMH)
        more, ok = _draw_cycle_curves(ax, family, cycles, key.lo, key.hi, vmin, VMAX_KMH, 1.0, "m", FIG8_START_T,
                                      notes, label_at=0.75, colour=colour, prefix=f"{name}: ",
                                      check=None if colour == REFERENCE_COLOUR else
                                      (lambda curve, family=family: curve_on_exudyn(family, curve)))
        items += more
        complete &= ok and cycles.complete
        notes += [f"{name}: the branch from {kmh(b.start.p) if b.start else math.nan:.2f} km/h at t = {FIG8_START_T:g} m is INCOMPLETE: "
                  f"{interface_text(b.message)}" for b in cycles.branches if not b.complete]
    notes.append(f"{mbs_name(fidelity)}: S and T curves from its cycles at t = {FIG8_START_T:g} m above "
                 f"{FIG8_MBS_VMIN_KMH:g} km/h only (its branch born at 3.56 km/h grows to yaw cycles of 50-60 deg "
                 f"that lift a wheel, each on 640 mesh intervals: minutes for every 50 km/h)")
    ax.axhline(FIG8_START_T, color="0.5", lw=0.7, ls=":")
    handles = plane_key(fidelity) + [Line2D([], [], color="0.3", ls=CURVE_STYLES[kind][0], lw=1.4, label=label)
                                     for kind, label in ((PointKind.CYCLE_FOLD, "saddle-node (S) curves"),
                                                         (PointKind.TORUS, "torus (T) curves"))]
    ax.legend(handles=handles, fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), framealpha=0.9)
    _speed_axis(ax, key.vmax_kmh, key.vmin_kmh)
    ax.set_ylim(key.lo, key.hi)
    ax.set_ylabel("pneumatic trail t [m]")
    ax.set_title(f"Fig. 8: {mbs_name(fidelity)} in red, {REFERENCE_NAME} in black; Hopf curves in (V, t) at 1.5 bar"
                 f"\nHB labels on the Table 1 trail (dotted); S, T curves from each model's cycles at t = "
                 f"{FIG8_START_T:g} m (dotted); hatched: straight running stable in one model only", fontsize=9)
    fig.tight_layout()
    place_labels(ax, items, fontsize=7)        # the layout is final
    return Drawing(fig, tuple(notes), complete)


# Figure 18's full-geometry S curves start from its cycles at FIG18_MBS_START_BAR: its one generalized Hopf point in
# the window (204.72 km/h, 0.2561 bar) is a sign change of the camber kink's coefficient, below which (0.25 bar, the
# reduced model's line) its onset is soft with no fold or torus point, and above which a kink makes its onset hard
# with a fold a few thousandths of a degree from the Hopf point (0.0038 deg at 0.3 bar, 2026-12-07).  Branch
# switching at that point starts 0.004 bar from it, where the fold's cycles are 0.0004 deg, and gives no curve that
# ends there; from 0.3 bar the curve runs to the window's top and down to that point (stop 45).
FIG18_MBS_START_BAR = 0.3


@register(18, "cycle_bifurcation_curves_hcl_pt", cost=300, beside=True)
def draw_cycle_curves_beside(store: DiagramStore, fidelity: Fidelity) -> Drawing:
    from bifurcation.cycles.branches import cycle_diagram
    from comparisons.figures.cycle_curve_figures import (
        FIG18_EFFECTS,
        FIG18_START_BAR,
        FIG18_VIEW_KMH,
        FIG18_WINDOW,
        _draw_cycle_curves,
        _draw_switched_curves,
    )
    from comparisons.studies.exudyn_check import curve_on_exudyn
    lo_bar, hi_bar, vmin_kmh, vmax_kmh = FIG18_WINDOW
    key = pressure_key(Effects.parse(FIG18_EFFECTS), lo_bar, hi_bar, vmin_kmh, vmax_kmh, n_seeds=21)
    fig = Figure(figsize=(9.6, 5.4))
    ax = fig.subplots()
    items, notes, complete = hopf_plane(ax, store, key, fidelity, BAR, "bar", FIG18_START_BAR * BAR, legend=False)
    family = store.family(key)
    complete &= _draw_switched_curves(ax, family, store.diagram(key), FIG18_WINDOW, notes, items,
                                      colour=REFERENCE_COLOUR, prefix=f"{REFERENCE_NAME}: ")
    mbs_key = replace(key, fidelity=fidelity)
    mbs, name = store.family(mbs_key), mbs_name(fidelity)

    def on_exudyn(curve):
        return curve_on_exudyn(mbs, curve)

    complete &= _draw_switched_curves(ax, mbs, store.diagram(mbs_key), FIG18_WINDOW, notes, items,
                                      colour=MBS_COLOUR, prefix=f"{name}: ", check=on_exudyn)
    line = FIG18_MBS_START_BAR * BAR
    cycles = cycle_diagram(mbs, line, vmin_kmh * KMH, vmax_kmh * KMH)
    for b in cycles.branches:
        notes.append(f"{name}: at {FIG18_MBS_START_BAR:g} bar, " + _onset_text(b))
    more, ok = _draw_cycle_curves(ax, mbs, cycles, key.lo, key.hi, vmin_kmh, vmax_kmh, BAR, "bar", line, notes,
                                  label_at=0.75, colour=MBS_COLOUR, prefix=f"{name}: ", check=on_exudyn)
    items += more
    complete &= ok and cycles.complete
    ax.axhline(FIG18_MBS_START_BAR, color=MBS_COLOUR, lw=0.7, ls=":")
    handles = plane_key(fidelity) + [Line2D([], [], color="0.3", ls=CURVE_STYLES[kind][0], lw=1.4, label=label)
                                     for kind, label in ((PointKind.CYCLE_FOLD, "saddle-node (S) curves"),
                                                         (PointKind.TORUS, "torus (T) curves"))]
    ax.legend(handles=handles, fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), framealpha=0.9)
    _speed_axis(ax, FIG18_VIEW_KMH[1], FIG18_VIEW_KMH[0])
    ax.set_ylim(lo_bar, hi_bar)
    ax.set_ylabel("inflation pressure $p_i$ [bar]")
    ax.set_title(f"Fig. 18: {name} in red, {REFERENCE_NAME} in black; effects HCL + PT\nthe reduced model's S, T "
                 f"curves switched onto at its HH1 and DH; the full geometry's from its cycles at "
                 f"{FIG18_MBS_START_BAR:g} bar (red dotted); hatched: straight running stable in one model only",
                 fontsize=9)
    fig.tight_layout()
    place_labels(ax, items, fontsize=7)        # the layout is final
    return Drawing(fig, tuple(notes), complete)


def _onset_text(branch) -> str:
    """A branch's start and its onset as one note: where the cycles are born and how far its first fold lies."""
    from bifurcation.special_points import PointStatus
    start = f"the branch from {kmh(branch.start.p):.3f} km/h" if branch.start else "a branch"
    folds = [p for p in branch.points_of(PointKind.CYCLE_FOLD) if p.status is PointStatus.LOCATED]
    if not folds or branch.start is None:
        return f"{start}: no cycle fold"
    first = min(folds, key=lambda p: abs(p.p - branch.start.p))
    theta = float(np.degrees(first.data["cycle"].amplitude[0]))
    return (f"{start}: first cycle fold at {kmh(first.p):.4f} km/h ({kmh(first.p - branch.start.p):+.2g} km/h from "
            f"the Hopf point, max|theta1| {theta:.2g} deg)")


# --- limit cycles ------------------------------------------------------------------------------------------------

def _checked(family, diagram) -> tuple[float, int, int]:
    """(largest Exudyn residual, orbits checked, orbits failing) of an MBS diagram's orbits."""
    from comparisons.studies.exudyn_check import checked_on_exudyn
    checks = [checked_on_exudyn(family, p) for b in diagram.branches for p in b.points]
    return max((c.residual for c in checks), default=0.0), len(checks), sum(not c.passed for c in checks)


def _draw_model(axes, diagram, colour: str, items: tuple[list, list]) -> None:
    """One model's branches, Hopf points and special points (their labels into ``items``, one list per panel) in
    the (theta1, psi) panels."""
    for ax, name, its in zip(axes, ("theta1", "psi"), items):
        for branch in diagram.branches:
            for stable, v, a in branch_lines(branch, name):
                ax.plot(v, a, "-" if stable else "--", color=colour, lw=1.5)
        for i, h in enumerate(sorted(diagram.hopf, key=lambda h: h.p), 1):
            ax.plot(kmh(h.p), 0.0, "o", color=colour, ms=5, zorder=5)
            if name == "theta1":
                its.append((kmh(h.p), 0.0, f"HB{i}", colour))
        for text, p in special_point_labels(diagram):
            amp = np.degrees(p.data["amplitude"][STATE_NAMES.index(name)])
            ax.plot(kmh(p.p), amp, LABELS.get(p.kind, ("", "x"))[1], color=colour, ms=6, mfc="none")
            its.append((kmh(p.p), amp, text, colour))


def _unstable_bars(ax, windows, colour: str, level: int, top: float) -> None:
    y = -(0.035 + 0.04 * level) * top
    for w in windows.windows:
        ax.plot([w.low_kmh, w.high_kmh], [y, y], "-", color=colour, lw=3.0, solid_capstyle="butt")


def cycle_panels_beside(store: DiagramStore, panels, vmax_kmh: float, figure_title: str, fidelity: Fidelity,
                        paper_args=None, mbs_branch_budget_s: float | None = None) -> Drawing:
    """One column of (max|theta1|, max|psi|) axes per panel (title, CycleKey of the reduced model), each with both
    models; ``mbs_branch_budget_s``: wall clock per MBS branch, past which it is drawn as far as it got and the
    figure is incomplete."""
    columns = len(panels)
    names = (REFERENCE_NAME, mbs_name(fidelity))
    colours = COLOURS
    fig = Figure(figsize=(5.8 * columns + 0.4, 7.0))
    axes = fig.subplots(2, columns, sharex="col", squeeze=False)
    notes, complete, labelled = [], True, []
    for j, (title, key) in enumerate(panels):
        prefix = f"{title.split(' ')[0]} " if columns > 1 else ""
        items = ([], [])
        found = []
        mbs_key = replace(key, fidelity=fidelity, branch_budget_s=mbs_branch_budget_s)
        for k, name, colour in zip((key, mbs_key), names, colours):
            family, diagram = store_cycles(store, k)
            _draw_model(axes[:, j], diagram, colour, items)
            args = dict((paper_args or [{}] * columns)[j]) if k.fidelity is None else {}
            notes += [f"{prefix}{name}: {n}" for n in _cycle_notes("", family, diagram, **args)]
            if k.fidelity is not None and any(b.points for b in diagram.branches):
                worst, count, failed = _checked(family, diagram)
                notes.append(f"{prefix}{name}: {count} orbits checked on Exudyn's right-hand side, largest relative "
                             f"collocation residual {worst:.2g}"
                             + (f", {failed} above the tolerance" if failed else ""))
                complete &= failed == 0
            complete &= diagram.complete
            found.append(windows_of(family, diagram.hopf, diagram.p_min, diagram.p_max))
        differences = compare_windows(*found)
        notes += [prefix + d.text(names) for d in differences]
        if not differences:
            notes.append(f"{prefix}no shimmy window in either model")
            for ax in axes[:, j]:
                ax.text(0.5, 0.5, "no Hopf point in either model:\nstraight running stable at every speed",
                        transform=ax.transAxes, ha="center", va="center", fontsize=9, color="0.3")
        for ax in axes[:, j]:
            ax.set_xlim(0.0, vmax_kmh)
            top = max(ax.get_ylim()[1], 1e-3)
            for level, (windows, colour) in enumerate(zip(found, colours)):
                _unstable_bars(ax, windows, colour, level, top)
            for d in differences:       # a window in one model only: hatched in that model's colour
                if d.reference is None or d.other is None:
                    w, colour = (d.reference, colours[0]) if d.other is None else (d.other, colours[1])
                    # a background (a collection, not a patch): labels may sit on it
                    ax.fill_between([w.low_kmh, w.high_kmh], 0.0, 1.0, transform=ax.get_xaxis_transform(),
                                    facecolor="none", edgecolor=colour, hatch="..", lw=0.0, alpha=0.35, zorder=0)
            ax.set_ylim(-0.14 * top, 1.1 * top)
            ax.grid(alpha=0.3)
        none = [n for n, w in zip(names, found) if not w.windows]
        axes[0, j].set_title(title + "".join(f"\n{n}: no Hopf point" for n in none if len(none) == 1), fontsize=10)
        axes[0, j].set_ylabel(r"max $|\theta_1|$ [deg]")
        axes[1, j].set_ylabel(r"max $|\psi|$ [deg]")
        axes[1, j].set_xlabel("speed V [km/h]")
        labelled += list(zip(axes[:, j], items))
    handles = [Line2D([], [], color=c, lw=1.5, label=n) for c, n in zip(colours, names)]
    handles += [Line2D([], [], color="0.3", ls="--", label="unstable cycles"),
                Line2D([], [], color="0.3", lw=3.0, label="bars below the axis: straight running unstable"),
                Patch(facecolor="none", edgecolor="0.3", hatch="..", label="a shimmy window in one model only")]
    fig.legend(handles=handles, loc="lower center", ncol=3, fontsize=8, frameon=False)
    fig.suptitle(figure_title, fontsize=10)
    fig.tight_layout(rect=(0, 0.07, 1, 1))
    for ax, its in labelled:        # once the layout is final
        place_labels(ax, its)
    return Drawing(fig, tuple(notes), complete)


@register(3, "cycles_nominal", cost=40, beside=True)
def draw_cycles_nominal_beside(store: DiagramStore, fidelity: Fidelity) -> Drawing:
    return cycle_panels_beside(store, [(f"{P_I0_BAR:g} bar ($p_{{i0}}$)", CycleKey(P_I0_BAR, 120.0))], 120.0,
                               f"Fig. 3: {mbs_name(fidelity)} in red, {REFERENCE_NAME} in black; limit "
                               f"cycles at nominal pressure", fidelity)


@register(4, "cycles_1.5bar_2.7bar", cost=60, beside=True)
def draw_cycles_low_high_beside(store: DiagramStore, fidelity: Fidelity) -> Drawing:
    panels = [("(a) 1.5 bar (0.6 $p_{i0}$)", CycleKey(1.5, VMAX_KMH)),
              ("(b) 2.7 bar (1.08 $p_{i0}$)", CycleKey(2.7, VMAX_KMH))]
    return cycle_panels_beside(store, panels, VMAX_KMH, f"Fig. 4: {mbs_name(fidelity)} in red, "
                               f"{REFERENCE_NAME} in black; limit cycles at low and high pressure", fidelity)


# Figure 9's full-geometry branch at t = 0.25 m born at 3.56 km/h grows to yaw cycles of 50-60 deg that lift a
# wheel, each on 640 mesh intervals: 52.6 km/h after 9.5 min (2026-12-07), and not finished after 43 min beside other
# runs.  Each of its branches gets this much wall clock and is drawn as far as it got (the figure incomplete).
FIG9_MBS_BRANCH_BUDGET_S = 90.0


@register(9, "cycles_trail", cost=600, beside=True)
def draw_cycles_trail_beside(store: DiagramStore, fidelity: Fidelity) -> Drawing:
    panels = [(f"({c}) t = {t0:g} m, 1.5 bar", CycleKey(1.5, FIG9_VMAX_KMH, (("t0", t0),)))
              for c, t0 in zip("ab", TRAIL_FIG9)]
    return cycle_panels_beside(store, panels, FIG9_VMAX_KMH, f"Fig. 9: {mbs_name(fidelity)} in red, "
                               f"{REFERENCE_NAME} in black; limit cycles at two pneumatic trails, 1.5 bar", fidelity,
                               mbs_branch_budget_s=FIG9_MBS_BRANCH_BUDGET_S)




# Figure 17 beside: the main window only (its zooms Z1, Z2 are the reduced model's), from 0.05 bar as figure 5.
FIG17_BAR = (0.05, 3.0)


@register(17, "cumulative_effects_hopf_curves", cost=500, beside=True)
def draw_cumulative_beside(store: DiagramStore, fidelity: Fidelity) -> Drawing:
    fig = Figure(figsize=(13.0, 7.6))
    axes = fig.subplots(2, 3, sharex=True, sharey=True).ravel()
    notes, complete, labelled = [], True, []
    for ax, effects, (label, _) in zip(axes, Effects.cumulative(), EFFECT_STYLES):
        items, more, ok = hopf_plane(ax, store, pressure_key(effects, *FIG17_BAR), fidelity, BAR, "bar", None,
                                     legend=False, every_label=False)
        notes += [f"{label}: {n}" for n in more]
        complete &= ok
        labelled.append((ax, items))
        ax.set_title(label, fontsize=9)
        ax.set_xlim(0.0, VMAX_KMH)
        ax.set_ylim(*FIG17_BAR)
    for ax in axes[3:5]:
        ax.set_xlabel("speed V [km/h]")
    for ax in axes[::3]:
        ax.set_ylabel("$p_i$ [bar]")
    axes[-1].set_axis_off()
    axes[-1].legend(handles=plane_key(fidelity), fontsize=8, loc="center", title="F: each model's highest fold",
                    title_fontsize=8)
    fig.suptitle(f"Fig. 17: {mbs_name(fidelity)} in red, {REFERENCE_NAME} in black; Hopf curves with the tyre "
                 f"properties following pressure cumulatively\nLF lateral force, HCL half-contact length, PT pneumatic "
                 f"trail, RL relaxation length, VS vertical stiffness; hatched: straight running stable in one model "
                 f"only", fontsize=9)
    fig.tight_layout()
    for ax, items in labelled:      # once the layout is final
        place_labels(ax, items, fontsize=7)
    return Drawing(fig, tuple(notes), complete)
