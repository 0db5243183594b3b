"""Figures: matplotlib only, kept out of the model packages.  matplotlib's object API (``Figure``): no pyplot
state, no backend chosen at import, nothing to close."""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

from axles.axle import interface_unit
from axles.units import kmh
from comparisons.files import atomic_path
from bifurcation.equilibria.hopf_curves import HopfDiagram
from bifurcation.special_points import PointKind
from reduced_model.family import SpeedFamily

MARKERS = {PointKind.HOPF_FOLD: ("o", "F"), PointKind.HOPF_HOPF: ("s", "HH"),
           PointKind.GENERALIZED_HOPF: ("D", "DH"), PointKind.ZERO_HOPF: ("^", "ZH")}


def save_figure(fig, path: str) -> None:
    """Save through a temporary file (:func:`comparisons.files.atomic_path`): no truncated PNG at ``path``."""
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=130, bbox_inches="tight", format="png")


def stability_grid(family: SpeedFamily, speeds: np.ndarray, values: np.ndarray) -> np.ndarray:
    """Number of unstable eigenvalues of straight running on a (value, speed) grid."""
    count = np.zeros((len(values), len(speeds)), dtype=int)
    for i, q in enumerate(values):
        A0 = family.linear_matrix(0.0, q)
        A1 = family.linear_matrix(1.0, q) - A0
        stack = A0[None] + speeds[:, None, None] * A1[None]  # affine in V (see bifurcation.equilibria.hopf)
        count[i] = np.sum(np.linalg.eigvals(stack).real > 0.0, axis=1)
    return count


def draw_hopf_diagram(ax, diagram: HopfDiagram, family: SpeedFamily, color="k", shade=True, label=None) -> None:
    unit, factor = interface_unit(diagram.param)
    if shade:
        speeds = np.linspace(diagram.p_min, diagram.p_max, 161)
        values = np.linspace(diagram.lo, diagram.hi, 121)
        stable = stability_grid(family, speeds, values) == 0
        ax.contourf(kmh(speeds), values / factor, stable.astype(float), levels=[0.5, 1.5], colors=["0.85"])
    for i, c in enumerate(diagram.curves):
        ax.plot(kmh(c.ps), c.qs / factor, "-", color=color, lw=1.4, label=label if i == 0 else None)
    for s in diagram.special_points:
        marker, text = MARKERS.get(s.kind, ("x", s.kind.value))
        ax.plot(kmh(s.p), s.q / factor, marker, color="C3", ms=5)
        ax.annotate(text, (kmh(s.p), s.q / factor), textcoords="offset points", xytext=(4, 4),
                    fontsize=8, color="C3")
    ax.set_xlim(kmh(diagram.p_min), kmh(diagram.p_max))
    ax.set_ylim(diagram.lo / factor, diagram.hi / factor)
    ax.set_xlabel("speed V [km/h]")
    ax.set_ylabel(f"{diagram.param} [{unit}]")


def plot_hopf_diagram(diagram: HopfDiagram, family: SpeedFamily, path: str, title: str | None = None) -> None:
    fig = Figure(figsize=(6.4, 4.6))
    ax = fig.subplots()
    draw_hopf_diagram(ax, diagram, family)
    effects = ",".join(family.model.effects.names) or "section 3 model"
    ax.set_title(title or f"Hopf curves ({effects}); shaded: straight running stable", fontsize=10)
    save_figure(fig, path)


def place_labels(ax, items, fontsize: float = 8.0, avoid=()) -> None:
    """Annotate points without labels overlapping each other or the marked points.

    ``items``: (x, y, text, colour) in data coordinates; ``avoid``: further (x, y) data points to keep clear.
    Each label takes the first of a ring of offsets whose (estimated) box is free; call after the axes limits
    are set."""
    fig = ax.figure
    to_px = fig.dpi / 72.0
    taken = [_box(ax.transData.transform((x, y)), (-4, -4), (8, 8), to_px) for x, y, *_ in items]
    taken += [_box(ax.transData.transform(xy), (-4, -4), (8, 8), to_px) for xy in avoid]
    offsets = ((5, 4), (5, -12), (-8, 4), (-8, -12), (5, 14), (-8, 14), (5, -22), (-8, -22), (14, -4), (-16, -4),
               (5, 24), (-8, 24), (5, -32), (-8, -32))
    for x, y, text, colour in items:
        w, h = 0.62 * fontsize * max(len(line) for line in text.split("\n")), 1.25 * fontsize * (text.count("\n") + 1)
        anchor = ax.transData.transform((x, y))
        chosen = offsets[0]
        for dx, dy in offsets:
            left = dx if dx >= 0 else dx - w + 8
            box = _box(anchor, (left, dy), (w, h), to_px)
            if not any(_overlap(box, other) for other in taken):
                chosen = (dx, dy)
                break
        left = chosen[0] if chosen[0] >= 0 else chosen[0] - w + 8
        taken.append(_box(anchor, (left, chosen[1]), (w, h), to_px))
        ax.annotate(text, (x, y), textcoords="offset points", xytext=(left, chosen[1]), fontsize=fontsize,
                    color=colour, zorder=7, bbox=dict(boxstyle="round,pad=0.1", fc="white", ec="none", alpha=0.8))


def _box(anchor, offset, size, to_px):
    x0, y0 = anchor[0] + offset[0] * to_px, anchor[1] + offset[1] * to_px
    return (x0, y0, x0 + size[0] * to_px, y0 + size[1] * to_px)


def _overlap(a, b) -> bool:
    return a[0] < b[2] and b[0] < a[2] and a[1] < b[3] and b[1] < a[3]
