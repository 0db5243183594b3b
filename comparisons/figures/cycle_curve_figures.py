"""Curves of cycle folds (S) and torus points (T) in (V, q) planes with the Hopf curves: figures 8 and 18."""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

from axles import paper_reference as paper
from axles.axle import interface_text
from axles.units import BAR, KMH, kmh
from comparisons.figures.cycle_plots import CURVE_STYLES, special_point_labels
from comparisons.figures.drawing import (
    _draw_curves,
    _incomplete_notes,
    _label_hopf_points,
    _located,
    _mark,
    _point_note,
    _shade_stable,
    _speed_axis,
)
from comparisons.figures.hopf_figures import T0_RANGE, pressure_key
from comparisons.figures.plots import place_labels
from comparisons.figures.registry import (
    MIN_LABEL_SPEED_KMH,
    VMAX_KMH,
    DiagramKey,
    DiagramStore,
    Drawing,
    register,
)
from bifurcation.cycle_curves.curve import cycle_bifurcation_curve
from bifurcation.cycle_curves.result import CycleCurve
from bifurcation.cycles.branches import cycle_diagram
from bifurcation.special_points import ConvergenceError, PointKind, PointStatus
from reduced_model.model import Effects
from axles.parameters import YANG2024

# Figure 18: the window of the two-parameter cycle continuation (tests/test_cycles_curves.py).  Below 0.2 bar T1
# and T2 run on to 0.05 bar without meeting (tests/test_cycle_curve_ends.py, slow): the paper's HH2 is not there.
FIG18_EFFECTS = "hcl,pt"
FIG18_WINDOW = (0.2, 0.6, 100.0, 300.0)     # bar, bar, km/h, km/h
FIG18_VIEW_KMH = (130.0, 230.0)
FIG18_START_BAR = 0.25                      # pressure of the one-parameter branches named HB2, HB3 in the figure


def _draw_cycle_curves(ax, family, cycles, lo: float, hi: float, vmin_kmh: float, vmax_kmh: float,
                       factor: float, unit: str, start: float, notes: list, label_at: float = 0.5,
                       colour: str | None = None, prefix: str = "", check=None) -> tuple[list, bool]:
    """Continue every cycle fold (S) and torus point (T) of the one-parameter ``cycles`` (at q = ``start``) in
    the (V, q) window and draw it (in ``colour``, else each kind's own; ``prefix`` before each note); ``check``
    (curve -> :class:`~comparisons.studies.exudyn_check.CurveCheck`): an MBS curve's points on Exudyn, in the notes,
    a failing point making the figure incomplete.  Returns (labels to place: (x, y, text, colour), complete)."""
    items, complete = [], True
    for text, point in special_point_labels(cycles):
        if point.kind not in (PointKind.CYCLE_FOLD, PointKind.TORUS):
            continue
        try:
            curve: CycleCurve = cycle_bifurcation_curve(family, point, lo, hi, vmin_kmh * KMH, vmax_kmh * KMH)
        except ConvergenceError as exc:
            notes.append(f"{prefix}{text}: INCOMPLETE: {interface_text(exc)}")
            complete = False
            continue
        origin = f"from {kmh(point.p):.2f} km/h at {start / factor:g} {unit}"
        more: list = []
        complete &= _draw_cycle_curve(ax, family, text, origin, curve, factor, unit, start, more, items, label_at,
                                      colour)
        if check is not None:
            checked = check(curve)
            more.append(f"{text}: {checked.text()}")
            complete &= checked.failing == 0
        notes += [prefix + n for n in more]
    return items, complete


def _draw_switched_curves(ax, family, hopf, window: tuple[float, float, float, float], notes: list, items: list,
                          colour: str | None = None, prefix: str = "", check=None) -> bool:
    """The cycle curves born at the Hopf-Hopf (T) and generalized Hopf (S) points of ``hopf`` in ``window`` (bar,
    bar, km/h, km/h), by branch switching there, drawn (in ``colour``, else each kind's) with their notes
    (``prefix`` before each); ``check`` as in :func:`_draw_cycle_curves`.  Returns whether every one is complete."""
    from bifurcation.cycle_curves.switching import named_curves, switched_curves

    lo_bar, hi_bar, vmin_kmh, vmax_kmh = window
    complete = True
    origins = [(f"HH{i}", p) for i, p in enumerate(_located(hopf, PointKind.HOPF_HOPF)[::-1], 1)] + \
        [("DH", p) for p in _located(hopf, PointKind.GENERALIZED_HOPF)]
    found = switched_curves(family, [p for _, p in origins], lo_bar * BAR, hi_bar * BAR, vmin_kmh * KMH,
                            vmax_kmh * KMH)
    origin_of = {id(s): name for (name, _), s in zip(origins, found)}
    for (origin, point), switched in zip(origins, found):
        if switched.error is None and not switched.curves:
            notes.append(f"{prefix}branch switching at {origin} ({kmh(point.p):.2f} km/h, {point.q / BAR:.4g} bar) "
                         "gives no curve that ends there")
    for name, switched, curve in named_curves(found):
        origin = origin_of[id(switched)]
        if curve is None:
            notes.append(f"{prefix}curves from {origin}: INCOMPLETE: {interface_text(switched.error)}")
            complete = False
            continue
        more: list = []
        complete &= _draw_cycle_curve(ax, family, name, f"born at {origin}", curve, BAR, "bar",
                                      FIG18_START_BAR * BAR, more, items, 0.5, colour)
        if check is not None:
            checked = check(curve)
            more.append(f"{name}: {checked.text()}")
            complete &= checked.failing == 0
        notes += [prefix + n for n in more]
    return complete


# MatCont's abbreviations for the codimension-two points of cycles (the notes spell them out).
CODIM2_LABELS = {PointKind.CUSP_OF_CYCLES: "CPC", PointKind.FOLD_FLIP: "LPPD", PointKind.FOLD_NEIMARK_SACKER: "LPNS",
                 PointKind.RESONANCE_1_3: "R3", PointKind.RESONANCE_1_4: "R4", PointKind.RESONANCE_1_1: "R1",
                 PointKind.RESONANCE_1_2: "R2", PointKind.CHENCINER: "CH", PointKind.GENERALIZED_PERIOD_DOUBLING: "GPD"}


def _draw_cycle_curve(ax, family, text: str, origin: str, curve: CycleCurve, factor: float, unit: str,
                      start: float, notes: list, items: list, label_at: float, colour: str | None = None) -> bool:
    """Draw one S or T curve with its ends (stars) and the codimension-two points of cycles found along it (x),
    in ``colour`` (else its kind's); add its label to ``items`` and its notes; returns whether it is complete."""
    style, own = CURVE_STYLES[curve.kind]
    colour = colour or own
    ax.plot(kmh(curve.ps), curve.qs / factor, style, color=colour, lw=1.6,
            label=f"{'saddle-node (S)' if curve.kind is PointKind.CYCLE_FOLD else 'torus (T)'} curves"
            if text in ("S1", "T1") else None)
    # The label sits the fraction ``label_at`` of the way from the starting line to the curve's far end.
    k = int(np.argmin(np.abs(curve.qs - (start + label_at * (curve.qs.max() - start)))))
    items.append((kmh(curve.ps[k]), curve.qs[k] / factor, text, colour))
    ends = [e for e in curve.ends if e is not None]
    for v, q in ends:
        ax.plot(kmh(v), q / factor, "*", color=colour, ms=9, zorder=6)
    located = {(p.p, p.q): p for p in curve.end_points if p is not None}
    end_text = "; ".join(f"amplitude vanishes at {kmh(v):.2f} km/h, {q / factor:.4f} {unit}"
                         + (f" ({located[(v, q)].kind.value.replace('_', '-')} point located on its Hopf curve)"
                            if (v, q) in located else " (extrapolated)") for v, q in ends)
    for sp in curve.special_points:    # codimension-two points of cycles found along the curve
        ax.plot(kmh(sp.p), sp.q / factor, "x", color=colour, ms=7, mew=1.6, zorder=6)
        items.append((kmh(sp.p), sp.q / factor, CODIM2_LABELS.get(sp.kind, sp.kind.value), colour))
        notes.append(f"{text}: {sp.kind.value.replace('_', ' ')} ({CODIM2_LABELS.get(sp.kind, '')}) at "
                     f"{kmh(sp.p):.2f} km/h, {sp.q / factor:.4g} {unit} ({sp.status.value})")
    messages = " | ".join(interface_text(m) for m in curve.messages)
    theta1 = np.degrees(curve.amplitudes[:, 0])    # how wide a band of (V, q) the curve's cycles can shimmy in
    notes.append(f"{text} ({curve.kind.value}, {origin}): {end_text or 'no zero-amplitude end'}; {messages}; "
                 f"its critical cycles' max|theta1| {theta1.min():.2g}-{theta1.max():.2g} deg")
    return curve.complete


@register(18, "cycle_bifurcation_curves_hcl_pt", cost=30)
def draw_cycle_curves(store: DiagramStore) -> Drawing:
    lo_bar, hi_bar, vmin_kmh, vmax_kmh = FIG18_WINDOW
    effects = Effects.parse(FIG18_EFFECTS)
    key = pressure_key(effects, lo_bar, hi_bar, vmin_kmh, vmax_kmh, n_seeds=21)
    hopf, family = store.diagram(key), store.family(key)
    cycles = cycle_diagram(family, FIG18_START_BAR * BAR, vmin_kmh * KMH, vmax_kmh * KMH)
    fig = Figure(figsize=(7.2, 5.4))
    ax = fig.subplots()
    _shade_stable(ax, family, hopf, BAR)
    _draw_curves(ax, hopf, BAR, "k", label="Hopf curves")
    notes, complete = [], hopf.complete and cycles.complete
    paper_hh = paper.SECTION5[FIG18_EFFECTS]["hopf_hopf_bar"]
    items: list = []
    for i, hh in enumerate(_located(hopf, PointKind.HOPF_HOPF)[::-1], 1):
        _mark(ax, hh, BAR, f"HH{i}", colour="tab:red", marker="s", items=items)
        notes.append(_point_note(f"HH{i}", hh, "bar", BAR) + (f" (paper {paper_hh:g} bar)" if i == 1 else ""))
    for i, dh in enumerate(_located(hopf, PointKind.GENERALIZED_HOPF), 1):
        _mark(ax, dh, BAR, "DH", colour="tab:blue", marker="D", items=items)
        notes.append(_point_note("DH (HB3 turns subcritical)", dh, "bar", BAR))
    complete &= _draw_switched_curves(ax, family, hopf, FIG18_WINDOW, notes, items)
    ax.axhline(FIG18_START_BAR, color="0.5", lw=0.7, ls=":")
    # The paper's names: HB3 turns subcritical at DH (its cycles are unstable below it), HB2 stays supercritical.
    for h in cycles.hopf:
        name = "HB3" if h.first_lyapunov > 0 else "HB2"
        items.append((kmh(h.p), FIG18_START_BAR, name, "k"))
        notes.append(f"{name} at {FIG18_START_BAR:g} bar: {kmh(h.p):.2f} km/h, first Lyapunov coefficient "
                     f"{'positive (subcritical)' if h.first_lyapunov > 0 else 'negative (supercritical)'}")
    _speed_axis(ax, FIG18_VIEW_KMH[1], FIG18_VIEW_KMH[0])
    ax.set_ylim(lo_bar, hi_bar)
    place_labels(ax, items, fontsize=9)
    ax.set_ylabel("inflation pressure $p_i$ [bar]")
    ax.legend(fontsize=8, loc="upper right", framealpha=0.9)
    ax.set_title("Fig. 18: enlarged (V, $p_i$) diagram, effects HCL + PT; shaded: straight running stable\n"
                 "cycle curves switched onto at HH1 and DH (stars, located); x: codimension-two points of cycles",
                 fontsize=9)
    notes.append(f"window {lo_bar:g}-{hi_bar:g} bar: T1 and T2 leave it at its lower edge; continued down to 0.05 bar "
                 "they neither cross nor end at a Hopf-Hopf point (they pass the two Hopf-Hopf points of 0.1007 bar "
                 "with max|theta1| 2.6 and 2.1 deg): no HH2 where the paper draws one (README, differences)")
    notes += _incomplete_notes("", hopf)
    return Drawing(fig, tuple(notes), complete)


# Figure 8's cycle curves start from the one-parameter cycles at t = 0.25 m (figure 9a's S1, T1, T2, S2).
FIG8_START_T = 0.25


@register(8, "trail_hopf_curves_1.5bar", cost=40)
def draw_trail_low_pressure(store: DiagramStore) -> Drawing:
    key = DiagramKey(Effects(), "t0", 1.5, *T0_RANGE, 0.0, VMAX_KMH)
    diagram, family = store.diagram(key), store.family(key)
    fig = Figure(figsize=(6.8, 5.0))
    ax = fig.subplots()
    _shade_stable(ax, family, diagram, 1.0)
    _draw_curves(ax, diagram, 1.0, "k")
    hopf_labels = _label_hopf_points(ax, family, YANG2024.t0, 1.0, VMAX_KMH)
    notes, marks = [], []
    for i, hh in enumerate(_located(diagram, PointKind.HOPF_HOPF), 1):
        name = "HH" if len(_located(diagram, PointKind.HOPF_HOPF)) == 1 else f"HH{i}"
        _mark(ax, hh, 1.0, f"{name} (t = {hh.q:.3f} m)", colour="tab:red", marker="s", items=marks)
        notes.append(_point_note(name, hh, "m", 1.0))
    for i, dh in enumerate(_located(diagram, PointKind.GENERALIZED_HOPF), 1):
        _mark(ax, dh, 1.0, f"DH{i} (t = {dh.q:.3f} m)", colour="tab:blue", marker="D", items=marks)
        notes.append(_point_note(f"DH{i} (criticality changes)", dh, "m", 1.0))
    for i, f in enumerate(_located(diagram, PointKind.HOPF_FOLD), 1):
        _mark(ax, f, 1.0, f"F{i} ({f.q:.3f} m)", items=marks)
        notes.append(_point_note(f"fold F{i}", f, "m", 1.0))
    for p in diagram.points_of(PointKind.HOPF_FOLD):
        if p.status is not PointStatus.LOCATED or kmh(p.p) < MIN_LABEL_SPEED_KMH:
            notes.append(_point_note(f"fold at the window edge, not labelled ({p.status.value})", p, "m", 1.0))
    # The torus (T) and saddle-node (S) curves of the paper's figure 8, continued from figure 9a's points.
    cycles = cycle_diagram(family, FIG8_START_T, 0.0, VMAX_KMH * KMH)
    items, ok = _draw_cycle_curves(ax, family, cycles, key.lo, key.hi, 0.0, VMAX_KMH, 1.0, "m", FIG8_START_T,
                                   notes, label_at=0.75)
    ax.axhline(FIG8_START_T, color="0.5", lw=0.7, ls=":")
    ax.legend(fontsize=8, loc="center right", framealpha=0.9)
    ax.axhline(YANG2024.t0, color="0.4", lw=0.7, ls=":")
    _speed_axis(ax)
    ax.set_ylim(key.lo, key.hi)
    ax.set_ylabel("pneumatic trail t [m]")
    # One placement for every label, once the limits are final, so that none lands on another.
    place_labels(ax, items + [(*item, 8) for item in hopf_labels + marks], fontsize=9,
                 avoid=[(kmh(p.p), p.q) for p in diagram.special_points])
    ax.set_title("Fig. 8: Hopf curves in (V, t) at 1.5 bar (0.6 $p_{i0}$); shaded: straight running stable\n"
                 f"HB labels on the Table 1 trail (dotted); S, T curves from the cycles at t = {FIG8_START_T:g} m; "
                 "stars: their zero-amplitude ends",
                 fontsize=9)
    notes += _incomplete_notes("", diagram)
    return Drawing(fig, tuple(notes), diagram.complete and cycles.complete and ok)
