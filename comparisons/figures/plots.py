"""Figures: matplotlib only, kept out of the model packages.  matplotlib's object API (``Figure``): no pyplot
state, no backend chosen at import, nothing to close."""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure
from matplotlib.text import Text

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


# Label offsets from the labelled point, in points: a ring close by first, then wider rings (with a leader line).
_RINGS = (8.0, 16.0, 28.0, 42.0, 60.0, 80.0, 100.0)
_DIRECTIONS = ((1, 0.6), (1, -1.2), (-1, 0.6), (-1, -1.2), (0, 1.4), (0, -1.8), (1, 0), (-1, 0))


def data_points_px(ax, step_px: float = 2.0) -> np.ndarray:
    """The axes' line data (every ``Line2D``: curves, markers, reference lines) in display pixels, segments
    filled in every ``step_px``, kept where they lie inside the axes."""
    box = ax.get_window_extent()
    out = []
    for line in ax.get_lines():
        if not line.get_visible():
            continue
        xy = line.get_transform().transform(np.column_stack(line.get_data()).astype(float))
        xy = xy[np.all(np.isfinite(xy), axis=1)]
        if len(xy) == 0:
            continue
        if line.get_linestyle() not in ("None", "none", "", " ") and len(xy) > 1:
            a, b = xy[:-1], xy[1:]
            n = np.maximum(np.ceil(np.hypot(*(b - a).T) / step_px).astype(int), 1)
            n = np.minimum(n, 4000)
            frac = np.concatenate([np.arange(k) / k for k in n])
            xy = np.vstack([np.repeat(a, n, axis=0) + frac[:, None] * np.repeat(b - a, n, axis=0), xy[-1:]])
        out.append(xy)
    if not out:
        return np.zeros((0, 2))
    xy = np.vstack(out)
    inside = (xy[:, 0] >= box.x0) & (xy[:, 0] <= box.x1) & (xy[:, 1] >= box.y0) & (xy[:, 1] <= box.y1)
    return xy[inside]


def _renderer(fig):
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    if not isinstance(fig.canvas, FigureCanvasAgg):
        FigureCanvasAgg(fig)
    return fig.canvas.get_renderer()


def place_labels(ax, items, fontsize: float = 8.0, avoid=(), margin_px: float = 10.0) -> None:
    """Annotate points so that no label covers data or another label.

    ``items``: (x, y, text, colour) in data coordinates, optionally with a fifth element, the item's font size; ``avoid``: further (x, y) data points to keep clear.
    Each label is measured by the renderer and takes the first offset, ring by ring outwards, where its box holds
    no line data of the axes (:func:`data_points_px`), no other label, and stays at least ``margin_px`` from
    every marked point but its own (so that a label never sits beside another model's point); labels further
    out get a thin leader line.  Call after the axes limits are set and the data drawn."""
    fig = ax.figure
    renderer = _renderer(fig)
    data = data_points_px(ax)
    axes_box = ax.get_window_extent()
    marks = [ax.transData.transform((x, y)) for x, y, *_ in items] + [ax.transData.transform(xy) for xy in avoid]
    taken = []
    for k, (x, y, text, colour, *size) in enumerate(items):
        own = marks[k]
        others = np.array([m for i, m in enumerate(marks) if i != k and np.hypot(*(m - own)) > 0.5]).reshape(-1, 2)
        best, best_score = None, None
        for ring in _RINGS:
            for dx, dy in _DIRECTIONS:
                offset = (dx * ring, dy * ring * 0.6)
                ann = ax.annotate(text, (x, y), textcoords="offset points", xytext=offset,
                                  fontsize=size[0] if size else fontsize,
                                  color=colour, zorder=7, ha="left" if dx > 0 else "right" if dx < 0 else "center",
                                  va="center", bbox=dict(boxstyle="round,pad=0.1", fc="white", ec="none", alpha=0.8),
                                  arrowprops=dict(arrowstyle="-", color=colour, lw=0.5, alpha=0.6) if ring > 16 else None)
                ann.update_positions(renderer)
                bb = Text.get_window_extent(ann, renderer)     # the text, without its leader line
                box = (bb.x0 - 1, bb.y0 - 1, bb.x1 + 1, bb.y1 + 1)
                score = (int(np.sum((data[:, 0] > box[0]) & (data[:, 0] < box[2]) & (data[:, 1] > box[1])
                                    & (data[:, 1] < box[3])))
                         + 50 * sum(_overlap(box, t) for t in taken)
                         + 50 * int(np.any((others[:, 0] > box[0] - margin_px) & (others[:, 0] < box[2] + margin_px)
                                           & (others[:, 1] > box[1] - margin_px) & (others[:, 1] < box[3] + margin_px)))
                         + 20 * int(not (box[0] >= axes_box.x0 and box[2] <= axes_box.x1 and box[1] >= axes_box.y0
                                         and box[3] <= axes_box.y1)))
                if best_score is None or score < best_score:
                    if best is not None:
                        best[0].remove()
                    best, best_score = (ann, box), score
                else:
                    ann.remove()
                if score == 0:
                    break
            if best_score == 0:
                break
        taken.append(best[1])


def _overlap(a, b) -> bool:
    return a[0] < b[2] and b[0] < a[2] and a[1] < b[3] and b[1] < a[3]
