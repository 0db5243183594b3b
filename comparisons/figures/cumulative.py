"""Figure 17: Hopf curves for the cumulative tyre-property sets, with zooms Z1 and Z2."""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure
from matplotlib.patches import Rectangle

from axles import paper_reference as paper
from axles.units import BAR, kmh
from comparisons.figures.drawing import (
    _draw_curves,
    _incomplete_notes,
    _located,
    _special_notes,
    _speed_axis,
    marker_key,
)
from comparisons.figures.hopf_figures import pressure_key
from comparisons.figures.plots import place_labels
from comparisons.figures.registry import EFFECT_STYLES, DiagramStore, Drawing, register
from bifurcation.equilibria.hopf_curves import HopfDiagram
from bifurcation.special_points import PointKind
from reduced_model.model import Effects

ZOOM_SEEDS = 41   # a curve lying between two seed lines of a zoom window would be missed: see uncovered


def uncovered(full: HopfDiagram, zoom: HopfDiagram, tol: float = 1e-2) -> int:
    """How many points of the full-window curves inside the zoom window are farther than ``tol`` (relative to
    the zoom window; chords of the polylines sag by ~1e-3) from every zoom curve: a check that the zoom's own
    seeding found every curve."""
    dv, dq = zoom.p_max - zoom.p_min, zoom.hi - zoom.lo
    zoom_pts = [np.column_stack([c.ps / dv, c.qs / dq]) for c in zoom.curves]
    count = 0
    for c in full.curves:
        inside = ((c.ps > zoom.p_min) & (c.ps < zoom.p_max) & (c.qs > zoom.lo) & (c.qs < zoom.hi))
        for v, q in zip(c.ps[inside] / dv, c.qs[inside] / dq):
            dist = min((_segment_distance(P, np.array([v, q])) for P in zoom_pts), default=np.inf)
            count += dist > tol
    return int(count)


def _segment_distance(P: np.ndarray, x: np.ndarray) -> float:
    """Distance from x to the polyline P (rows are points)."""
    if len(P) == 1:
        return float(np.linalg.norm(P[0] - x))
    a, seg = P[:-1], np.diff(P, axis=0)
    lam = np.clip(np.einsum("ij,ij->i", x - a, seg) / np.maximum(np.einsum("ij,ij->i", seg, seg), 1e-300), 0, 1)
    return float(np.min(np.linalg.norm(a + lam[:, None] * seg - x, axis=1)))


Z1 = (2.45, 2.65, 30.0, 90.0)     # bar, bar, km/h, km/h: where the yaw mode ends
Z2 = (0.01, 0.6, 150.0, 260.0)    # where the two modes meet at low pressure
# The full window reaches down to Z2's lower edge, so that every curve piece the zooms should show is checked.
P17_BAR = (Z2[0], 3.0)


def _z2_names(zoom: HopfDiagram, effects: Effects, label: str, colour, notes: list) -> list:
    """The paper's names in Z2: the cusp where HB2 and HB3 meet once HCL follows pressure (a fold of the Hopf
    curve, paper 220.5 km/h, 0.078 bar) and HH1, where they cross once PT follows too (paper 0.53 bar)."""
    ref = paper.SECTION5.get(",".join(effects.names), {})
    out = []
    if "cusp_kmh" in ref:
        folds = _located(zoom, PointKind.HOPF_FOLD)
        if folds:
            f = min(folds, key=lambda p: abs(kmh(p.p) - ref["cusp_kmh"]))
            out.append((kmh(f.p), f.q / BAR, f"cusp ({label})", colour))
            notes.append(f"{label}: cusp (HB2 meets HB3) at {kmh(f.p):.2f} km/h, {f.q / BAR:.4f} bar "
                         f"(paper {ref['cusp_kmh']:g} km/h, {ref['cusp_bar']:g} bar)")
    if "hopf_hopf_bar" in ref:
        crossings = _located(zoom, PointKind.HOPF_HOPF)
        if crossings:
            h = min(crossings, key=lambda p: abs(p.q / BAR - ref["hopf_hopf_bar"]))
            out.append((kmh(h.p), h.q / BAR, f"HH1 ({label})", colour))
            notes.append(f"{label}: HH1 (HB2 crosses HB3) at {kmh(h.p):.2f} km/h, {h.q / BAR:.4f} bar "
                         f"(paper {ref['hopf_hopf_bar']:g} bar)")
    return out


@register(17, "cumulative_effects_hopf_curves", cost=18)
def draw_cumulative(store: DiagramStore) -> Drawing:
    fig = Figure(figsize=(11.0, 5.6))
    grid = fig.add_gridspec(2, 2, width_ratios=(1.6, 1.0))
    ax = fig.add_subplot(grid[:, 0])
    zooms = (fig.add_subplot(grid[0, 1]), fig.add_subplot(grid[1, 1]))
    notes, complete = [], True
    z2_labels = []
    for effects, (label, colour) in zip(Effects.cumulative(), EFFECT_STYLES):
        diagram = store.diagram(pressure_key(effects, *P17_BAR))
        _draw_curves(ax, diagram, BAR, colour, label=label)
        folds = _located(diagram, PointKind.HOPF_FOLD)
        if folds:
            notes.append(f"{label}: no shimmy above {folds[-1].q / BAR:.4f} bar "
                         f"(fold at {kmh(folds[-1].p):.2f} km/h)")
        notes += _special_notes(f"{label}: ", diagram, "bar", BAR)
        notes += _incomplete_notes(f"{label}: ", diagram)
        complete &= diagram.complete
        for zax, (plo, phi, vlo, vhi) in zip(zooms, (Z1, Z2)):
            zd = store.diagram(pressure_key(effects, plo, phi, vlo, vhi, n_seeds=ZOOM_SEEDS))
            missed = uncovered(diagram, zd)
            if missed:
                complete = False
                notes.append(f"{label} zoom: INCOMPLETE: {missed} points of the full-window curves inside the "
                             f"zoom lie on no zoom curve")
            _draw_curves(zax, zd, BAR, colour, label=label)
            for f in _located(zd, PointKind.HOPF_FOLD):
                zax.plot(kmh(f.p), f.q / BAR, "o", color=colour, ms=4, mfc="white")
            for s in _located(zd, PointKind.HOPF_HOPF):
                zax.plot(kmh(s.p), s.q / BAR, "s", color=colour, ms=4, mfc="white")
            complete &= zd.complete
            notes += _incomplete_notes(f"{label} zoom: ", zd)
            if (plo, phi, vlo, vhi) == Z2:
                z2_labels += _z2_names(zd, effects, label, colour, notes)
    for name, zax, (plo, phi, vlo, vhi) in zip(("Z1", "Z2"), zooms, (Z1, Z2)):
        zax.set_xlim(vlo, vhi)
        zax.set_ylim(plo, phi)
        zax.set_title(f"({name})", fontsize=9)
        zax.set_xlabel("speed V [km/h]", fontsize=8)
        zax.set_ylabel("$p_i$ [bar]", fontsize=8)
        zax.tick_params(labelsize=8)
        zax.grid(alpha=0.3)
        ax.add_patch(Rectangle((vlo, plo), vhi - vlo, phi - plo, fill=False, ls="--", lw=0.8, color="0.3"))
        ax.annotate(name, (vhi, phi), textcoords="offset points", xytext=(2, 2), fontsize=8)
    # Keys below the axes, off the curves (inside, every corner holds a curve at some pressure).
    marker_key(zooms[1], kinds=(PointKind.HOPF_FOLD, PointKind.HOPF_HOPF), loc="upper center",
               bbox_to_anchor=(0.5, -0.3), ncol=2)
    _speed_axis(ax)
    ax.set_ylim(*P17_BAR)
    ax.set_ylabel("inflation pressure $p_i$ [bar]")
    ax.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.1), ncol=5, framealpha=0.9)
    ax.set_title("Fig. 17: Hopf curves with the tyre properties following pressure cumulatively\n"
                 "LF lateral force, HCL half-contact length, PT pneumatic trail, RL relaxation length, "
                 "VS vertical stiffness", fontsize=9)
    fig.tight_layout()
    place_labels(zooms[1], z2_labels)     # once the layout is final
    return Drawing(fig, tuple(notes), complete)
