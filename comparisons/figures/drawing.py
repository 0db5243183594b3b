"""Drawing helpers shared by the figure recipes: shading, curves, special points and their labels."""

from __future__ import annotations

import numpy as np

from axles.axle import interface_text
from axles.units import KMH, kmh
from comparisons.figures.plots import stability_grid
from comparisons.figures.registry import MIN_LABEL_SPEED_KMH, P_I0_BAR, VMAX_KMH
from bifurcation.equilibria.hopf import find_hopf_points
from bifurcation.equilibria.hopf_curves import HopfCurve, HopfDiagram
from bifurcation.special_points import PointKind, PointStatus
from reduced_model.family import SpeedFamily


def _pressure_label(p_bar: float) -> str:
    return f"{p_bar:g} bar ({p_bar / P_I0_BAR:.3g} $p_{{i0}}$)"


def _shade_stable(ax, family: SpeedFamily, diagram: HopfDiagram, factor: float, colour="0.85", alpha=1.0) -> None:
    """Shade where straight running is stable (all eigenvalues in the left half plane)."""
    speeds = np.linspace(diagram.p_min, diagram.p_max, 201)
    values = np.linspace(diagram.lo, diagram.hi, 121)
    stable = (stability_grid(family, speeds, values) == 0).astype(float)
    ax.contourf(kmh(speeds), values / factor, stable, levels=[0.5, 1.5], colors=[colour], alpha=alpha)


def _draw_curves(ax, diagram: HopfDiagram, factor: float, colour, label=None, lw=1.4) -> None:
    for i, c in enumerate(diagram.curves):
        ax.plot(kmh(c.ps), c.qs / factor, "-", color=colour, lw=lw, label=label if i == 0 else None)


def _located(diagram: HopfDiagram, kind: PointKind) -> list:
    return sorted((p for p in diagram.points_of(kind) if p.status is PointStatus.LOCATED
                   and kmh(p.p) >= MIN_LABEL_SPEED_KMH), key=lambda p: p.q)


def _curve_of(diagram: HopfDiagram, point) -> HopfCurve:
    """The curve passing closest to a special point."""
    def dist(c):
        return np.min(np.hypot((c.ps - point.p) / 10.0,
                               (c.qs - point.q) / (diagram.hi - diagram.lo)))
    return min(diagram.curves, key=dist)


def _fold_is_maximum(diagram: HopfDiagram, point) -> bool:
    """Whether the Hopf curve reaches a local maximum of the parameter at this fold (else a minimum)."""
    c = _curve_of(diagram, point)
    k = int(np.argmin(np.hypot((c.ps - point.p) / 10.0, (c.qs - point.q) / (diagram.hi - diagram.lo))))
    around = c.qs[max(k - 3, 0):k + 4]
    return bool(np.mean(around) < point.q)


def _mark(ax, point, factor, text, colour="k", offset=(5, 5), marker="o", text_at=None, items=None) -> None:
    """Mark a special point; the label sits ``offset`` points away, or at data position ``text_at`` with an arrow,
    or, when ``items`` is a list, goes into it as (x, y, text, colour) for
    :func:`comparisons.figures.plots.place_labels` once the axes are final."""
    x, y = kmh(point.p), point.q / factor
    ax.plot(x, y, marker, color=colour, ms=5, mfc="white", mew=1.3, zorder=5)
    if text and items is not None and text_at is None:
        items.append((x, y, text, colour))
    elif text:
        where = dict(xytext=text_at, textcoords="data", arrowprops=dict(arrowstyle="-", color=colour, lw=0.7)) \
            if text_at is not None else dict(xytext=offset, textcoords="offset points")
        ax.annotate(text, (x, y), fontsize=8, color=colour, zorder=6,
                    bbox=dict(boxstyle="round,pad=0.15", fc="white", ec="none", alpha=0.75), **where)


def _label_hopf_points(ax, family: SpeedFamily, q: float, factor: float, vmax_kmh: float, colour="k") -> list:
    """Mark the Hopf points on the line q = const; their labels HB1, HB2, ... by speed (the paper's naming) as
    (x, y, text, colour) items for :func:`comparisons.figures.plots.place_labels`, to be placed once the axes'
    limits are final."""
    points = find_hopf_points(family, q, 0.0, vmax_kmh * KMH, lyapunov=False)
    items = []
    for i, h in enumerate(points, 1):
        ax.plot(kmh(h.p), q / factor, ".", color=colour, ms=6)
        items.append((kmh(h.p), q / factor, f"HB{i}", colour))
    return items


def _point_note(name: str, p, unit: str, factor: float, fmt: str = ".4g") -> str:
    return f"{name}: {kmh(p.p):.2f} km/h, {p.q / factor:{fmt}} {unit}"


def _special_notes(prefix: str, diagram: HopfDiagram, unit: str, factor: float) -> list[str]:
    names = {PointKind.HOPF_FOLD: "fold", PointKind.HOPF_HOPF: "Hopf-Hopf", PointKind.GENERALIZED_HOPF: "DH",
             PointKind.ZERO_HOPF: "zero-Hopf"}
    notes = []
    for p in sorted(diagram.special_points, key=lambda p: (p.kind.value, p.q)):
        status = "" if p.status is PointStatus.LOCATED else f" ({p.status.value})"
        notes.append(f"{prefix}{_point_note(names.get(p.kind, p.kind.value), p, unit, factor)}{status}")
    return notes


def _incomplete_notes(prefix: str, diagram: HopfDiagram) -> list[str]:
    return [f"{prefix}INCOMPLETE curve: {' | '.join(interface_text(m) for m in c.messages)}" for c in diagram.curves if not c.complete]


def _speed_axis(ax, vmax_kmh: float = VMAX_KMH, vmin_kmh: float = 0.0) -> None:
    ax.set_xlim(vmin_kmh, vmax_kmh)
    ax.set_xlabel("speed V [km/h]")


# Marker keys in words (figures 6, 7, 13, 14, 17): hollow markers on the curves of each colour.
SPECIAL_MARKERS = ((PointKind.HOPF_FOLD, "o", "fold of a Hopf curve (F)"), (PointKind.HOPF_HOPF, "s", "Hopf-Hopf point (HH)"),
                   (PointKind.GENERALIZED_HOPF, "D", "degenerate Hopf point (DH)"))


def marker_key(ax, kinds=(PointKind.HOPF_FOLD, PointKind.HOPF_HOPF, PointKind.GENERALIZED_HOPF), shading=None,
               **legend_kwargs):
    """A legend that says in words what the hollow markers (and the grey shading) mean; added as an artist so
    that the axes' own legend stays."""
    from matplotlib.legend import Legend
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch
    handles = [Line2D([], [], ls="none", marker=m, color="0.3", mfc="white", ms=5, label=text)
               for kind, m, text in SPECIAL_MARKERS if kind in kinds]
    handles += [Patch(color=c, label=t) for c, t in (shading or ())]
    legend = Legend(ax, handles, [h.get_label() for h in handles], fontsize=7, framealpha=0.9, **legend_kwargs)
    legend.set_clip_on(False)    # else clipped to the axes and left out of the saved figure's tight box
    ax.add_artist(legend)
    return legend
