"""Figures: matplotlib only, kept out of the model packages.  matplotlib's object API (``Figure``): no pyplot
state, no backend chosen at import, nothing to close."""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

from reduced_model.family import SpeedFamily
from reduced_model.hopf_curves import HopfDiagram
from reduced_model.special_points import PointKind

from .files import atomic_path
from .options import interface_unit

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
        stack = A0[None] + speeds[:, None, None] * A1[None]  # affine in V (see reduced_model.hopf)
        count[i] = np.sum(np.linalg.eigvals(stack).real > 0.0, axis=1)
    return count


def draw_hopf_diagram(ax, diagram: HopfDiagram, family: SpeedFamily, color="k", shade=True, label=None) -> None:
    unit, factor = interface_unit(diagram.param)
    if shade:
        speeds = np.linspace(diagram.vmin, diagram.vmax, 161)
        values = np.linspace(diagram.lo, diagram.hi, 121)
        stable = stability_grid(family, speeds, values) == 0
        ax.contourf(speeds * 3.6, values / factor, stable.astype(float), levels=[0.5, 1.5], colors=["0.85"])
    for i, c in enumerate(diagram.curves):
        ax.plot(c.speeds * 3.6, c.values / factor, "-", color=color, lw=1.4, label=label if i == 0 else None)
    for s in diagram.special_points:
        marker, text = MARKERS.get(s.kind, ("x", s.kind.value))
        ax.plot(s.speed * 3.6, s.value / factor, marker, color="C3", ms=5)
        ax.annotate(text, (s.speed * 3.6, s.value / factor), textcoords="offset points", xytext=(4, 4),
                    fontsize=8, color="C3")
    ax.set_xlim(diagram.vmin * 3.6, diagram.vmax * 3.6)
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
