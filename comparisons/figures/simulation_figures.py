"""Figures from simulated runs (figures 10, 11)."""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

from axles import paper_reference as paper
from axles.axle import interface_text
from axles.units import BAR, KMH, kmh
from comparisons.figures.cycle_figures import _trail_key
from comparisons.figures.cycle_plots import special_point_labels
from comparisons.figures.registry import DiagramStore, Drawing, register, store_cycles
from bifurcation.cycles.branches import cycle_at
from bifurcation.special_points import ConvergenceError
from reduced_model.modes import ModeClassifier, ModeHistory
from reduced_model.simulation import initial_state, integrate
from reduced_model.trajectory import SpeedSchedule, Trajectory
from axles.pressures import TyrePressures

# Figure 10: the speed ramps of tests/test_simulation.py (1 km/h per s through the bistable window), each
# started from the default small disturbance theta1 = 0.01 rad where only one mode is stable.
RAMP_UP_KMH = (120.0, 200.0, 80.0, 85.0)      # from, to, ramp seconds, simulated seconds
RAMP_DOWN_KMH = (200.0, 120.0, 80.0, 80.0)


def _trajectory_column(axes, tr: Trajectory, history: ModeHistory, crossing: tuple[str, float], title: str) -> list:
    name, v_cross = crossing
    speed_kmh = kmh(tr.speed)
    k = int(np.argmin(np.abs(speed_kmh - v_cross)))
    notes = []
    for ax, (state, label) in zip(axes, (("theta1", r"$\theta_1$ [deg]"), ("psi", r"$\psi$ [deg]"))):
        ax.plot(tr.t, np.degrees(tr.state(state)), lw=0.3, color="k")
        ax.axvline(tr.t[k], color="0.45", lw=1.0, ls="--")
        for s in history.switches:
            ax.axvline(s.time, color="C3", lw=1.2, ls=":")
        ax.set_ylabel(label)
        ax.set_xlim(tr.t[0], tr.t[-1])
        ax.grid(alpha=0.3)
    top = axes[0]
    top.annotate(f"{name} {v_cross:.2f} km/h", (tr.t[k], 0.02), xycoords=("data", "axes fraction"),
                 textcoords="offset points", xytext=(-3, 0), ha="right", fontsize=8, color="0.3")
    for s in history.switches:
        top.annotate(f"{s.before.value} → {s.after.value}\n{kmh(s.speed):.2f} km/h", (s.time, 0.97),
                     xycoords=("data", "axes fraction"), textcoords="offset points", xytext=(3, -24), fontsize=8,
                     color="C3", zorder=6, bbox=dict(boxstyle="round,pad=0.15", fc="white", ec="none", alpha=0.85))
        notes.append(f"{title[:3]} switch {s.before.value} -> {s.after.value} at t = {s.time:.2f} s, "
                     f"{kmh(s.speed):.2f} km/h ({name} = {v_cross:.2f} km/h)")
    if not history.switches:
        notes.append(f"{title[:3]} no mode switch detected (initial mode {history.initial.value})")
    twin = top.twinx()
    twin.plot(tr.t, speed_kmh, color="C0", lw=1.0)
    twin.set_ylabel("speed V [km/h]", color="C0")
    twin.tick_params(axis="y", colors="C0")
    top.set_title(title, fontsize=10)
    axes[-1].set_xlabel("time [s]")
    if not tr.complete:
        notes.append(f"{title[:3]} INCOMPLETE simulation: {interface_text(tr.message)}")
    return notes


@register(10, "mode_change_time_histories", cost=18)
def draw_mode_changes(store: DiagramStore) -> Drawing:
    family, diagram = store_cycles(store, _trail_key(0.25))
    labels = dict(special_point_labels(diagram))
    s1, t2 = kmh(labels["S1"].p), kmh(labels["T2"].p)
    model = family.model
    fig = Figure(figsize=(12.0, 6.0))
    axes = fig.subplots(2, 2, sharex="col")
    notes, complete = [], True
    for j, ((v0, v1, ramp, duration), crossing, title) in enumerate((
            (RAMP_UP_KMH, ("S1", s1), "(a) speed increasing"), (RAMP_DOWN_KMH, ("T2", t2), "(b) speed decreasing"))):
        tr = integrate(model, TyrePressures.uniform(1.5 * BAR), SpeedSchedule.ramp(v0 * KMH, v1 * KMH, ramp), duration)
        history = ModeClassifier().classify(tr)
        notes += _trajectory_column(axes[:, j], tr, history, crossing,
                                    f"{title}: {v0:g} → {v1:g} km/h in {ramp:g} s")
        complete &= tr.complete
    notes.append(f"paper: the jumps happen at S1 ({paper.FIG9A['S1']:g} km/h) and T2 ({paper.FIG9A['T2']:g} km/h); "
                 "ramp speeds at the jumps are not printed")
    notes.append("(b) " + paper.KNOWN_DIFFERENCES["cycles:fig10b:jump"])
    fig.suptitle("Fig. 10: mode changes at t = 0.25 m, 1.5 bar (start theta1 = 0.01 rad); red dotted: detected "
                 "switch, grey dashed: speed passes S1 / T2", fontsize=10)
    fig.tight_layout()
    return Drawing(fig, tuple(notes), complete)


# Figure 11: L1 the default small disturbance, L2 a large wheel-yaw start (as in tests/test_simulation.py).
PHASE_STARTS = (("L1", {"theta1": 0.01}, "0.55", (-22, 6)), ("L2", {"theta1": 0.2, "psi": 0.01}, "k", (8, -12)))
PHASE_DURATION = 20.0


@register(11, "phase_portrait_180kmh", cost=6)
def draw_phase_portrait(store: DiagramStore) -> Drawing:
    family, diagram = store_cycles(store, _trail_key(0.25))
    V = paper.FIG11_SPEED_KMH * KMH
    fig = Figure(figsize=(6.8, 5.4))
    ax = fig.subplots()
    notes, complete = [], True
    cycles = {}
    for branch, mode in zip(diagram.branches, ("yaw", "tramp")):
        stable = [p for p in branch.points if p.stable]
        try:
            cycles[mode] = cycle_at(family, min(stable, key=lambda p: abs(p.p - V)), V)
        except (ValueError, ConvergenceError) as exc:
            notes.append(f"continuation cycle of the {mode} mode at 180 km/h not found: {interface_text(exc)}")
    for name, start, colour, offset in PHASE_STARTS:
        tr = integrate(family.model, TyrePressures.uniform(1.5 * BAR), SpeedSchedule.constant(V), PHASE_DURATION, initial_state(start))
        history = ModeClassifier().classify(tr)
        psi, psid = np.degrees(tr.state("psi")), np.degrees(tr.state("psi_dot"))
        ax.plot(psi, psid, lw=0.4, color=colour, label=f"{name}: → {history.final_mode.value} mode")
        ax.plot(psi[0], psid[0], "s", color=colour, ms=7, zorder=6)
        ax.annotate(name, (psi[0], psid[0]), textcoords="offset points", xytext=offset, fontsize=9, color=colour,
                    zorder=6, fontweight="bold", bbox=dict(boxstyle="round,pad=0.1", fc="white", ec="none"))
        last = tr.t > tr.t[-1] - 1.0
        a_sim = np.degrees(np.max(np.abs(tr.state("psi")[last])))
        mode = history.final_mode.value
        ref = cycles.get(mode)
        ref_text = f", continuation cycle {np.degrees(ref.max_abs('psi')):.4f} deg" if ref is not None else ""
        notes.append(f"{name} (start {', '.join(f'{k} = {v:g} rad' for k, v in start.items())}): settles in the "
                     f"{mode} mode, max|psi| over the last second {a_sim:.4f} deg{ref_text}")
        complete &= tr.complete
    for mode, c in cycles.items():
        x = c.orbit.at(np.linspace(0.0, 1.0, 400))
        ax.plot(np.degrees(x[:, 4]), np.degrees(x[:, 5]), "--", color="C3" if mode == "tramp" else "C0", lw=1.3,
                label=f"stable {mode} cycle (continuation, {c.frequency_hz:.2f} Hz)")
    ax.set_xlabel(r"$\psi$ [deg]")
    ax.set_ylabel(r"$\dot\psi$ [deg/s]")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.12), ncol=2)
    ax.set_title(f"Fig. 11: phase portrait at {paper.FIG11_SPEED_KMH:g} km/h, t = 0.25 m, 1.5 bar "
                 f"({PHASE_DURATION:g} s each)", fontsize=10)
    return Drawing(fig, tuple(notes), complete)
