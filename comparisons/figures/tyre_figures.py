"""Figures that need only the tyre formulas (figures 2, 12, 16)."""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

from axles.units import BAR
from comparisons.figures.drawing import _pressure_label
from comparisons.figures.registry import (
    P_I0_BAR,
    PRESSURE_COLOURS,
    SLIP_PRESSURES_BAR,
    DiagramStore,
    Drawing,
    register,
)
from reduced_model import tyre
from axles.parameters import YANG2024


@register(2, "lateral_force")
def draw_lateral_force(store: DiagramStore) -> Drawing:
    alpha_deg = np.linspace(-20.0, 20.0, 801)
    fig = Figure(figsize=(6.4, 4.4))
    ax = fig.subplots()
    notes = []
    for p in SLIP_PRESSURES_BAR:
        mf = tyre.magic_formula(YANG2024, p * BAR)
        fy = mf.force(np.radians(alpha_deg))
        ax.plot(alpha_deg, fy / 1e3, color=PRESSURE_COLOURS[p], label=_pressure_label(p))
        notes.append(f"{p:g} bar: peak |F_y| {np.max(np.abs(fy)) / 1e3:.3f} kN at "
                     f"{abs(alpha_deg[np.argmax(np.abs(fy))]):.2f} deg, cornering stiffness "
                     f"{mf.K * np.pi / 180 / 1e3:.3f} kN/deg")
    ax.axhline(0, color="0.6", lw=0.6)
    ax.axvline(0, color="0.6", lw=0.6)
    ax.set_xlim(alpha_deg[0], alpha_deg[-1])
    ax.set_xlabel("slip angle α [deg]")
    ax.set_ylabel("lateral force $F_y$ [kN]")
    ax.set_title(f"Fig. 2: lateral force, eqs. (2.4)-(2.9), $F_z$ = {YANG2024.Fz0:g} N\n"
                 "(sign of eq. 2.4: the force opposes the slip angle)", fontsize=10)
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    return Drawing(fig, tuple(notes))


@register(12, "trail_vs_slip")
def draw_trail(store: DiagramStore) -> Drawing:
    alpha_deg = np.linspace(-15.0, 15.0, 601)
    fig = Figure(figsize=(6.4, 4.4))
    ax = fig.subplots()
    notes = []
    for p in SLIP_PRESSURES_BAR:
        t = tyre.pneumatic_trail(YANG2024, np.radians(alpha_deg), p * BAR)
        ax.plot(alpha_deg, t, color=PRESSURE_COLOURS[p], label=_pressure_label(p))
        notes.append(f"{p:g} bar: trail at zero slip {tyre.pneumatic_trail(YANG2024, 0.0, p * BAR):.4f} m, "
                     f"min {t.min():.4f} m")
    ax.axhline(0, color="0.6", lw=0.6)
    ax.set_xlim(alpha_deg[0], alpha_deg[-1])
    ax.set_xlabel("slip angle α [deg]")
    ax.set_ylabel("pneumatic trail t [m]")
    ax.set_title("Fig. 12: pneumatic trail, eqs. (4.2)-(4.8)", fontsize=10)
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    return Drawing(fig, tuple(notes))


@register(16, "tyre_properties_vs_pressure")
def draw_properties(store: DiagramStore) -> Drawing:
    p_bar = np.linspace(1.0, 3.5, 251)
    a = [tyre.half_contact_length(YANG2024, p * BAR) for p in p_bar]
    sigma = [tyre.relaxation_length(YANG2024, p * BAR) for p in p_bar]
    k5 = [tyre.vertical_stiffness(YANG2024, p * BAR) for p in p_bar]
    fig = Figure(figsize=(11.5, 3.6))
    axes = fig.subplots(1, 3)
    panels = ((a, "half-contact length a [m]", "(a) eq. (4.1)"), (sigma, "relaxation length σ [m]", "(b) eq. (4.9)"),
              (k5, "vertical stiffness $k_5$ [N/m]", "(c) eq. (4.10)"))
    for ax, (y, ylabel, title) in zip(axes, panels):
        ax.plot(p_bar, y, "k-")
        ax.axvline(P_I0_BAR, color="0.6", lw=0.8, ls="--")
        ax.set_xlabel("inflation pressure $p_i$ [bar]")
        ax.set_ylabel(ylabel)
        ax.set_title(title, fontsize=10)
        ax.grid(alpha=0.3)
    axes[2].ticklabel_format(axis="y", style="sci", scilimits=(5, 5))
    fig.suptitle("Fig. 16: tyre properties against inflation pressure (dashed: $p_{i0}$ = 2.5 bar)", fontsize=10)
    fig.tight_layout()
    notes = tuple(f"{p:g} bar: a = {tyre.half_contact_length(YANG2024, p * BAR):.4f} m, sigma = "
                  f"{tyre.relaxation_length(YANG2024, p * BAR):.4f} m, k5 = "
                  f"{tyre.vertical_stiffness(YANG2024, p * BAR):.4g} N/m" for p in (1.5, 2.5, 3.0))
    return Drawing(fig, notes)
