"""Curves of cycle folds and torus points in (V, q) planes (figure 18; figure 8 draws them too)."""

from __future__ import annotations

from __future__ import annotations


import numpy as np
from matplotlib.figure import Figure

from reduced_model.cycle_curves import CycleCurve, cycle_bifurcation_curve
from reduced_model.cycles import cycle_diagram
from reduced_model.model import Effects
from reduced_model.special_points import ConvergenceError, PointKind

from .. import paper_reference as paper
from ..cycle_plots import CURVE_STYLES, special_point_labels
from .drawing import _draw_curves, _incomplete_notes, _located, _mark, _point_note, _shade_stable, _speed_axis
from .hopf_figures import _pressure_key
from .registry import BAR, DiagramStore, Drawing, KMH, register



# Figure 18: the window of the two-parameter cycle continuation (tests/test_cycles_curves.py).  Below 0.2 bar the
# torus curves need more than 300 continuation steps (over 25 s each) and do not reach the window's edge.
FIG18_EFFECTS = "hcl,pt"
FIG18_WINDOW = (0.2, 0.6, 100.0, 300.0)     # bar, bar, km/h, km/h
FIG18_VIEW_KMH = (130.0, 230.0)
FIG18_START_BAR = 0.25                      # one-parameter cycle branches whose S and T points seed the curves


@register(18, "cycle_bifurcation_curves_hcl_pt", cost=14)
def draw_cycle_curves(store: DiagramStore) -> Drawing:
    lo_bar, hi_bar, vmin_kmh, vmax_kmh = FIG18_WINDOW
    effects = Effects.parse(FIG18_EFFECTS)
    key = _pressure_key(effects, lo_bar, hi_bar, vmin_kmh, vmax_kmh, n_seeds=21)
    hopf, family = store.diagram(key), store.family(key)
    cycles = cycle_diagram(family, FIG18_START_BAR * BAR, vmin_kmh * KMH, vmax_kmh * KMH)
    fig = Figure(figsize=(7.2, 5.4))
    ax = fig.subplots()
    _shade_stable(ax, family, hopf, BAR)
    _draw_curves(ax, hopf, BAR, "k", label="Hopf curves")
    notes, complete = [], hopf.complete and cycles.complete
    paper_hh = paper.SECTION5[FIG18_EFFECTS]["hopf_hopf_bar"]
    for i, hh in enumerate(_located(hopf, PointKind.HOPF_HOPF)[::-1], 1):
        _mark(ax, hh, BAR, f"HH{i}", colour="tab:red", marker="s", offset=(6, 4))
        notes.append(_point_note(f"HH{i}", hh, "bar", BAR) + (f" (paper {paper_hh:g} bar)" if i == 1 else ""))
    for i, dh in enumerate(_located(hopf, PointKind.GENERALIZED_HOPF), 1):
        _mark(ax, dh, BAR, "DH", colour="tab:blue", marker="D", offset=(8, 2))
        notes.append(_point_note("DH (HB3 turns subcritical)", dh, "bar", BAR))
    for text, point in special_point_labels(cycles):
        if point.kind not in (PointKind.CYCLE_FOLD, PointKind.TORUS):
            continue
        try:
            curve: CycleCurve = cycle_bifurcation_curve(family, point, lo_bar * BAR, hi_bar * BAR,
                                                        vmin_kmh * KMH, vmax_kmh * KMH)
        except ConvergenceError as exc:
            notes.append(f"{text}: INCOMPLETE: {exc}")
            complete = False
            continue
        style, colour = CURVE_STYLES[curve.kind]
        ax.plot(curve.speeds * 3.6, curve.values / BAR, style, color=colour, lw=1.6,
                label=f"{'saddle-node (S)' if curve.kind is PointKind.CYCLE_FOLD else 'torus (T)'} curves"
                if text in ("S1", "T1") else None)
        k = int(np.argmin(np.abs(curve.values - 0.5 * (FIG18_START_BAR * BAR + curve.values.max()))))
        ax.annotate(text, (curve.speeds[k] * 3.6, curve.values[k] / BAR), textcoords="offset points",
                    xytext=(5, -3) if text == "T1" else (-18, -3), fontsize=9, color=colour)
        ends = [e for e in curve.ends if e is not None]
        for v, q in ends:
            ax.plot(v * 3.6, q / BAR, "*", color=colour, ms=9, zorder=6)
        end_text = "; ".join(f"amplitude vanishes at {v * 3.6:.2f} km/h, {q / BAR:.4f} bar" for v, q in ends)
        notes.append(f"{text} ({curve.kind.value}, from {point.speed * 3.6:.2f} km/h at {FIG18_START_BAR:g} bar): "
                     f"{end_text or 'no zero-amplitude end'}; {' | '.join(curve.messages)}")
        complete &= curve.complete
    ax.axhline(FIG18_START_BAR, color="0.5", lw=0.7, ls=":")
    # The paper's names: HB3 turns subcritical at DH (its cycles are unstable below it), HB2 stays supercritical.
    for h in cycles.hopf:
        name = "HB3" if h.first_lyapunov > 0 else "HB2"
        ax.annotate(name, (h.speed_kmh, FIG18_START_BAR), textcoords="offset points", xytext=(4, 3), fontsize=8)
        notes.append(f"{name} at {FIG18_START_BAR:g} bar: {h.speed_kmh:.2f} km/h, first Lyapunov coefficient "
                     f"{'positive (subcritical)' if h.first_lyapunov > 0 else 'negative (supercritical)'}")
    _speed_axis(ax, FIG18_VIEW_KMH[1], FIG18_VIEW_KMH[0])
    ax.set_ylim(lo_bar, hi_bar)
    ax.set_ylabel("inflation pressure $p_i$ [bar]")
    ax.legend(fontsize=8, loc="upper right", framealpha=0.9)
    ax.set_title("Fig. 18: enlarged (V, $p_i$) diagram, effects HCL + PT; shaded: straight running stable\n"
                 f"stars: cycle curves end at zero amplitude; dotted: {FIG18_START_BAR:g} bar (where they start)",
                 fontsize=9)
    notes.append(f"window {lo_bar:g}-{hi_bar:g} bar: T1 and T2 leave it at its lower edge; the paper's HH2, where "
                 "they meet again, is below it (not computed)")
    notes += _incomplete_notes("", hopf)
    return Drawing(fig, tuple(notes), complete)
