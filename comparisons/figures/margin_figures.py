"""Stability-margin maps: the least damping ratio of straight running, filled over (speed, pressure), its zero level
(where shimmy sets in) drawn, the minimum marked; Hopf curves or Hopf points on top when given."""

from __future__ import annotations

import numpy as np
from matplotlib.colors import TwoSlopeNorm
from matplotlib.figure import Figure

from axles.units import BAR, kmh
from comparisons.figures.plots import save_figure

CMAP = "RdBu"     # red: negative damping (shimmy), blue: damped


def margin_limits(studies) -> tuple[float, float]:
    """One colour scale for several maps: from their finite values, always reaching both sides of zero."""
    values = np.concatenate([s.damping_ratio[np.isfinite(s.damping_ratio)].ravel() for s in studies] + [[0.0]])
    lo, hi = float(values.min()), float(values.max())
    return min(lo, -1e-3), max(hi, 1e-3)


def diverging_scale(lo: float, hi: float, bands: int = 8, ticks: int = 4):
    """(contour levels, colour-bar ticks, norm) of a diverging map over [lo, hi] (lo < 0 < hi) centred at zero.

    Each side gets its own round step (matplotlib's MaxNLocator), so that zero is a level and a tick, every
    level is a round number and the white of the colour map falls exactly on zero; the norm
    (:class:`~matplotlib.colors.TwoSlopeNorm`) stretches each side to its half of the colours, so that a small
    negative margin still shows red against a large positive one."""
    from matplotlib.ticker import MaxNLocator

    def side(limit: float, n: int) -> np.ndarray:
        """Round steps from zero to at least |limit|, signed like ``limit``, zero left out."""
        values = MaxNLocator(nbins=n, steps=[1, 2, 2.5, 5, 10]).tick_values(0.0, abs(limit))
        values = values[values > 0.0]
        return values[:int(np.searchsorted(values, abs(limit) * (1.0 - 1e-9))) + 1] * np.sign(limit)

    levels = np.unique(np.concatenate([side(lo, bands), side(hi, bands), [0.0]]))
    tick_values = np.unique(np.concatenate([side(lo, ticks), side(hi, ticks), [0.0]]))
    tick_values = tick_values[(tick_values >= levels[0]) & (tick_values <= levels[-1])]
    return levels, tick_values, TwoSlopeNorm(vmin=levels[0], vcenter=0.0, vmax=levels[-1])


def draw_margin_map(ax, study, title: str, limits: tuple[float, float] | None = None, hopf=()):
    """The filled map of ``study`` (:class:`comparisons.studies.margin_study.MarginStudy`) on ``ax``; ``hopf``: (km/h, bar)
    points to mark.  Returns the filled contour set (for a colour bar)."""
    lo, hi = limits or margin_limits([study])
    speeds, bars, zeta = kmh(study.speeds), study.pressures / BAR, study.damping_ratio
    if len(bars) == 1:       # one pressure: a band, so that contourf has two rows
        bars, zeta = np.array([bars[0] - 0.05, bars[0] + 0.05]), np.vstack([zeta, zeta])
    levels, _, norm = diverging_scale(lo, hi)
    filled = ax.contourf(speeds, bars, zeta, levels=levels, cmap=CMAP, norm=norm, extend="both")
    if np.nanmin(zeta) < 0.0 < np.nanmax(zeta):
        ax.contour(speeds, bars, zeta, levels=[0.0], colors="k", linewidths=1.3)
    for v, p in hopf:
        ax.plot(v, p, "o", ms=4, mfc="none", mec="k")
    low = study.minimum
    if low is not None:
        # The star marks the minimum; its value goes in the title, where it covers nothing.
        ax.plot(low.speed_kmh, low.pressure_bar, "*", ms=11, color="gold", mec="k", zorder=5)
        title += (f"\nstar: minimum {low.damping_ratio:+.3f} ({low.mode}) at {low.speed_kmh:.0f} km/h, "
                  f"{low.pressure_bar:g} bar")
    ax.set_xlabel("speed V [km/h]")
    ax.set_ylabel("tyre pressure [bar]")
    ax.set_title(title, fontsize=9)
    return filled


def plot_margin_maps(panels, path: str, title: str = "") -> None:
    """Maps side by side on one colour scale: ``panels`` of (study, title, hopf points (km/h, bar))."""
    limits = margin_limits([s for s, _, _ in panels])
    fig = Figure(figsize=(5.4 * len(panels) + 0.8, 4.4))
    axes = fig.subplots(1, len(panels), squeeze=False)[0]
    filled = None
    for ax, (study, text, hopf) in zip(axes, panels):
        filled = draw_margin_map(ax, study, text, limits, hopf)
    bar = fig.colorbar(filled, ax=list(axes), shrink=0.9, ticks=diverging_scale(*limits)[1])
    bar.set_label("least damping ratio of straight running (negative: shimmy)")
    if title:
        fig.suptitle(title, fontsize=10, y=1.03)
    save_figure(fig, path)


def plot_margin_map(study, path: str, title: str) -> None:
    """One map (``shimmy margins --plot``); black line: zero damping, the shimmy boundary."""
    plot_margin_maps([(study, title + "\nblack: zero damping (shimmy boundary)", ())], path)


def plot_hopf_diagram_with_margins(diagram, family, study, path: str) -> None:
    """``shimmy curves --plot`` over a pressure: the Hopf diagram, and beside it the margin map of the same window
    with the Hopf curves drawn on it (they lie on its zero level where the last stable pair crosses)."""
    from comparisons.figures.plots import draw_hopf_diagram
    fig = Figure(figsize=(12.4, 4.8))
    left, right = fig.subplots(1, 2)
    draw_hopf_diagram(left, diagram, family)
    effects = ",".join(family.model.effects.names) or "section 3 model"
    left.set_title(f"Hopf curves ({effects}); shaded: straight running stable", fontsize=9)
    filled = draw_margin_map(right, study, "least damping ratio; black: zero level; white: Hopf curves")
    for c in diagram.curves:
        right.plot(kmh(c.ps), c.qs / BAR, "-", color="w", lw=1.0)
    right.set_xlim(kmh(diagram.p_min), kmh(diagram.p_max))
    right.set_ylim(diagram.lo / BAR, diagram.hi / BAR)
    right.set_ylabel(f"{diagram.param} [bar]")
    fig.colorbar(filled, ax=right, shrink=0.9, ticks=diverging_scale(*margin_limits([study]))[1]).set_label(
        "least damping ratio (negative: shimmy)")
    save_figure(fig, path)
