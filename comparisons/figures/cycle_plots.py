"""Figures of limit-cycle branches (the paper's figures 3, 4, 9 and 15) and of simulated runs (figures 10, 11)."""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

from axles.units import BAR, kmh
from comparisons.figures.plots import place_labels, save_figure, stability_grid
from bifurcation.cycles.problem import CycleBranch, CycleDiagram
from bifurcation.special_points import PointKind
from reduced_model.family import SpeedFamily
from reduced_model.model import STATE_NAMES
from reduced_model.modes import ModeHistory
from reduced_model.trajectory import Trajectory

LABELS = {PointKind.CYCLE_FOLD: ("S", "o"), PointKind.TORUS: ("T", "s"), PointKind.PERIOD_DOUBLING: ("PD", "^")}
MODEL_NAMES = {"reduced": "reduced model", "mbs": "multibody model (Exudyn)"}
PANELS = (("theta1", r"max $|\theta_1|$ [deg]"), ("psi", r"max $|\psi|$ [deg]"))


def special_point_labels(diagram: CycleDiagram) -> list[tuple[str, object]]:
    """(label, point) numbered like the paper: S1, S2, ... and T1, T2, ... by decreasing speed (figure 9a: S1
    184.75 and S2 135.56 km/h, T1 181.65 and T2 157.39 km/h); listed in branch order."""
    points = [p for b in diagram.branches for p in sorted(b.special_points, key=lambda p: p.bracket[0])]
    number = {}
    for kind in {p.kind for p in points}:
        same = sorted((p for p in points if p.kind is kind), key=lambda p: -p.p)
        number.update({id(p): i for i, p in enumerate(same, 1)})
    return [(f"{LABELS.get(p.kind, (p.kind.value, 'x'))[0]}{number[id(p)]}", p) for p in points]


def _stability_runs(branch: CycleBranch):
    """Consecutive runs of equal stability, each sharing its end point with the next run."""
    runs, start = [], 0
    for i in range(1, len(branch.points) + 1):
        if i == len(branch.points) or branch.points[i].stable != branch.points[start].stable:
            runs.append((branch.points[start].stable, branch.points[start:min(i + 1, len(branch.points))]))
            start = i
    return runs


def branch_lines(branch: CycleBranch, name: str):
    """(stable, speeds km/h, max |x_name| deg) of each run of equal stability, joined to the Hopf points the
    branch starts and ends at (amplitude zero there)."""
    for stable, pts in _stability_runs(branch):
        v = [kmh(p.p) for p in pts]
        a = [np.degrees(p.max_abs(name)) for p in pts]
        if branch.start is not None and pts[0] is branch.points[0]:
            v, a = [kmh(branch.start.p)] + v, [0.0] + a
        if branch.end is not None and pts[-1] is branch.points[-1]:
            v, a = v + [kmh(branch.end.p)], a + [0.0]
        yield stable, v, a


def kick_marks(kicks) -> list[tuple[float, float, str]]:
    """(speed km/h, kick deg, label) of each bracketed kick threshold (:class:`comparisons.studies.kick.KickThreshold`):
    the initial theta1 that leaves the lower state, drawn on the max |theta1| axis because it is the same angle."""
    return [(kmh(k.speed), float(np.degrees(k.kick)), f"kick {np.degrees(k.kick):.2f} deg")
            for k in kicks if k.status.is_complete]


def _draw_kicks(ax, kicks, color: str, items: list) -> None:
    for v, a, text in kick_marks(kicks):
        ax.plot(v, a, "v", color=color, ms=7, zorder=6)
        items.append((v, a, text, color))


def draw_cycle_diagram(axes, diagram: CycleDiagram, family: SpeedFamily, color="k", hopf_labels=None,
                       kicks=(), place: bool = True) -> list:
    """Straight running on the axis and the cycle branches above it, in (speed, max|theta1|) and (speed,
    max|psi|) panels; special points S/T/PD named like the paper; Hopf points named by ``hopf_labels`` ((name,
    point) pairs; default HB1, HB2, ... by speed); the ``kicks`` that leave the lower state of a bistable window
    as triangles in the theta1 panel.  Labels are placed so that they do not collide; with ``place=False`` they are
    returned as [(axes, items)] for :func:`place_labels` once the figure's layout is final (a label placed before
    the axes are resized or their limits change can end up on the data)."""
    labelled = []
    speeds = np.linspace(diagram.p_min, diagram.p_max, 801)
    unstable = stability_grid(family, speeds, np.array([diagram.q]))[0] > 0
    labels = special_point_labels(diagram)
    if hopf_labels is None:
        hopf_labels = [(f"HB{i}", h) for i, h in enumerate(sorted(diagram.hopf, key=lambda h: h.p), 1)]
    for ax, (name, ylabel) in zip(axes, PANELS):
        # Straight running on the axis: solid where stable, dashed where not.
        for flag, style in ((False, "-"), (True, "--")):
            y = np.where(unstable == flag, 0.0, np.nan)
            ax.plot(kmh(speeds), y, style, color="0.4", lw=1.2)
        for branch in diagram.branches:
            for stable, v, a in branch_lines(branch, name):
                ax.plot(v, a, "-" if stable else "--", color=color, lw=1.5)
        items = []
        for text, h in hopf_labels:
            ax.plot(kmh(h.p), 0.0, "o", color="C0", ms=5, zorder=5)
            items.append((kmh(h.p), 0.0, text, "C0"))
        for text, p in labels:
            amp = np.degrees(p.data["amplitude"][STATE_NAMES.index(name)])
            marker = LABELS.get(p.kind, ("", "x"))[1]
            ax.plot(kmh(p.p), amp, marker, color="C3", ms=6, mfc="none")
            items.append((kmh(p.p), amp, text, "C3"))
        if name == "theta1":
            _draw_kicks(ax, kicks, "C2", items)
        ax.set_xlim(kmh(diagram.p_min), kmh(diagram.p_max))
        ax.set_ylabel(ylabel)
        top = max(ax.get_ylim()[1], 1e-3)
        ax.set_ylim(-0.1 * top, 1.08 * top)    # room for the Hopf points' labels below the axis
        labelled.append((ax, items))
    axes[-1].set_xlabel("speed V [km/h]")
    if place:
        for ax, items in labelled:
            place_labels(ax, items)
        return []
    return labelled


def plot_cycle_diagram(diagram: CycleDiagram, family: SpeedFamily, path: str, title: str | None = None,
                       kicks=()) -> None:
    fig = Figure(figsize=(6.4, 6.4))
    axes = fig.subplots(2, 1, sharex=True)
    labelled = draw_cycle_diagram(axes, diagram, family, kicks=kicks, place=False)
    effects = ",".join(family.model.effects.names) or "section 3 model"
    axes[0].set_title(title or f"Limit cycles at {diagram.q / BAR:g} bar ({effects}); "
                               f"solid stable, dashed unstable", fontsize=10)
    fig.tight_layout()
    for ax, items in labelled:
        place_labels(ax, items)
    save_figure(fig, path)


def plot_trajectory(trajectory: Trajectory, history: ModeHistory, path: str, title: str | None = None) -> None:
    """theta1 and psi (degrees) against time, the speed on a second axis, mode switches marked."""
    fig = Figure(figsize=(7.2, 5.6))
    axes = fig.subplots(2, 1, sharex=True)
    for ax, (name, label) in zip(axes, ((r"theta1", r"$\theta_1$ [deg]"), ("psi", r"$\psi$ [deg]"))):
        ax.plot(trajectory.t, np.degrees(trajectory.state(name)), lw=0.5, color="k")
        ax.set_ylabel(label)
        for s in history.switches:
            ax.axvline(s.time, color="C3", lw=1.0, ls=":")
        if not np.allclose(trajectory.speed, trajectory.speed[0]):
            twin = ax.twinx()
            twin.plot(trajectory.t, kmh(trajectory.speed), color="C0", lw=1.0)
            twin.set_ylabel("speed [km/h]", color="C0")
    for s in history.switches:
        axes[0].annotate(f"{s.before.value} -> {s.after.value}\n{kmh(s.speed):.1f} km/h", (s.time, 1.0),
                         xycoords=("data", "axes fraction"), textcoords="offset points", xytext=(3, -22),
                         fontsize=8, color="C3")
    axes[-1].set_xlabel("time [s]")
    model = MODEL_NAMES.get(trajectory.model, trajectory.model)
    axes[0].set_title(title or f"{model}: {trajectory.integrator.split(',')[0]}", fontsize=9)
    save_figure(fig, path)


def plot_phase_portrait(trajectories, path: str, labels=None, title: str | None = None) -> None:
    """psi against psi_dot (figure 11), one curve per trajectory, initial points as squares."""
    fig = Figure(figsize=(5.6, 4.6))
    ax = fig.subplots()
    for i, tr in enumerate(trajectories):
        psi, psid = np.degrees(tr.state("psi")), np.degrees(tr.state("psi_dot"))
        ax.plot(psi, psid, lw=0.5, color=f"C{i}", label=None if labels is None else labels[i])
        ax.plot(psi[0], psid[0], "s", color=f"C{i}")
    ax.set_xlabel(r"$\psi$ [deg]")
    ax.set_ylabel(r"$\dot\psi$ [deg/s]")
    if labels is not None:
        ax.legend(fontsize=8)
    if title:
        ax.set_title(title, fontsize=10)
    save_figure(fig, path)


CURVE_STYLES = {PointKind.CYCLE_FOLD: ("-.", "C2"), PointKind.TORUS: (":", "C1")}


def plot_cycle_curves(hopf, curves, labels, family: SpeedFamily, path: str, title: str | None = None) -> None:
    """Figure 8/18 style: Hopf curves of straight running (shaded where it is stable) with the curves of cycle
    folds (S, dash-dotted) and torus points (T, dotted) in the (V, q) plane; ends at zero amplitude marked."""
    from axles.axle import interface_unit
    from comparisons.figures.plots import draw_hopf_diagram

    unit, factor = interface_unit(family.param)
    fig = Figure(figsize=(6.8, 5.0))
    ax = fig.subplots()
    draw_hopf_diagram(ax, hopf, family)
    for curve, label in zip(curves, labels):
        if curve is None or len(curve.ps) == 0:
            continue
        style, color = CURVE_STYLES.get(curve.kind, ("--", "C4"))
        ax.plot(kmh(curve.ps), curve.qs / factor, style, color=color, lw=1.6)
        k = len(curve.ps) // 2
        ax.annotate(label, (kmh(curve.ps[k]), curve.qs[k] / factor), textcoords="offset points",
                    xytext=(4, -10), fontsize=8, color=color)
        for end in curve.ends:
            if end is not None:
                ax.plot(kmh(end[0]), end[1] / factor, "*", color=color, ms=8)
    ax.set_title(title or f"cycle folds (S, dash-dot) and torus points (T, dotted) in (V, {family.param} "
                          f"[{unit}])", fontsize=10)
    save_figure(fig, path)


def plot_cycle_overlay(diagram: CycleDiagram, family: SpeedFamily, simulated: dict, path: str,
                       title: str | None = None) -> None:
    """The continuation diagram with steady amplitudes of simulations on top (brute-force bifurcation diagram).

    ``simulated`` maps a label to a list of (speed m/s, max|theta1| rad, max|psi| rad).
    """
    fig = Figure(figsize=(6.4, 6.4))
    axes = fig.subplots(2, 1, sharex=True)
    labelled = draw_cycle_diagram(axes, diagram, family, place=False)
    styles = {"reduced": ("o", "C0", "MBS, all assumptions on"), "full": ("x", "C3", "MBS, full geometry")}
    for label, points in simulated.items():
        marker, color, text = styles.get(label, ("s", "C2", label))
        good = [(v, a, b) for v, a, b in points if np.isfinite(a)]
        if not good:
            continue
        v, a, b = (np.array(c) for c in zip(*good))
        axes[0].plot(kmh(v), np.degrees(a), marker, color=color, mfc="none", ms=6, label=text)
        axes[1].plot(kmh(v), np.degrees(b), marker, color=color, mfc="none", ms=6)
    axes[0].legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    axes[0].set_title(title or f"Limit cycles at {diagram.q / BAR:g} bar", fontsize=10)
    fig.tight_layout()
    for ax, items in labelled:      # after the simulations' markers, so that no label covers them
        place_labels(ax, items)
    save_figure(fig, path)


def plural(count: int, noun: str) -> str:
    """"1 Hopf point", "2 Hopf points"."""
    return f"{count} {noun}{'' if count == 1 else 's'}"


NARROW_SHARE = 0.03     # a branch narrower than this share of the speed axis is also drawn enlarged


def _draw_model(ax, diagram: CycleDiagram, color: str, kicks, items: list) -> None:
    for branch in diagram.branches:
        for stable, v, a in branch_lines(branch, "theta1"):
            ax.plot(v, a, "-" if stable else "--", color=color, lw=1.5)
    for h in diagram.hopf:
        ax.plot(kmh(h.p), 0.0, "o", color=color, ms=5, zorder=5)
    for text, p in special_point_labels(diagram):
        amp = np.degrees(p.data["amplitude"][STATE_NAMES.index("theta1")])
        ax.plot(kmh(p.p), amp, LABELS.get(p.kind, ("", "x"))[1], color=color, ms=7, mfc="none")
        items.append((kmh(p.p), amp, text, color))
    _draw_kicks(ax, kicks, color, items)


def _narrow_spans(models, width_kmh: float) -> list[tuple[float, float]]:
    """Speed spans (km/h) of the branches narrower than :data:`NARROW_SHARE` of the axis."""
    spans = []
    for _, diagram, *_ in models:
        for branch in diagram.branches:
            v = [x for _, vs, _ in branch_lines(branch, "theta1") for x in vs]
            if v and max(v) - min(v) < NARROW_SHARE * width_kmh:
                spans.append((min(v), max(v)))
    return spans


def plot_model_branches(models, path: str, title: str | None = None) -> None:
    """Several models' cycle branches at one case: max |theta1| (deg) against speed (km/h), stable solid,
    unstable dashed, Hopf points as dots on the axis and cycle folds, torus and period-doubling points marked and
    named like the paper (S1, T1, ... per model, in the model's colour, never beside another model's point), kick
    thresholds as triangles.  A branch too narrow to see at full scale (under :data:`NARROW_SHARE` of the speed
    axis) is drawn again, enlarged, in a panel of its own.  The key is below the axes.  ``models``: (name,
    CycleDiagram, colour) or (name, CycleDiagram, colour, kicks)."""
    from matplotlib.lines import Line2D
    vmin = min(kmh(d.p_min) for _, d, *_ in models)
    vmax = max(kmh(d.p_max) for _, d, *_ in models)
    narrow = _narrow_spans(models, vmax - vmin)
    fig = Figure(figsize=(9.6 if narrow else 7.2, 5.4))
    if narrow:
        ax, zoom = fig.subplots(1, 2, gridspec_kw={"width_ratios": (3, 1)})
    else:
        ax, zoom = fig.subplots(), None
    items, zoom_items, handles = [], [], []
    hopf = [(kmh(h.p), 0.0) for _, diagram, *_ in models for h in diagram.hopf]
    for label, diagram, color, *kicks in models:
        _draw_model(ax, diagram, color, kicks[0] if kicks else (), items)
        if zoom is not None:
            _draw_model(zoom, diagram, color, kicks[0] if kicks else (), zoom_items)
        handles.append(Line2D([], [], color=color, lw=1.5, label=f"{label} ({plural(len(diagram.hopf), 'Hopf point')})"))
    handles += [Line2D([], [], color="0.3", ls="-", label="stable"), Line2D([], [], color="0.3", ls="--",
                                                                            label="unstable")]
    ax.set_xlim(vmin, vmax)
    top = max(ax.get_ylim()[1], 1e-3)
    ax.set_ylim(-0.05 * top, 1.15 * top)
    ax.set_xlabel("speed V [km/h]")
    ax.set_ylabel(r"max $|\theta_1|$ [deg]")
    ax.legend(handles=handles, fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.14), ncol=2, frameon=False)
    if zoom is not None:
        lo, hi = min(a for a, _ in narrow), max(b for _, b in narrow)
        pad = max(0.15 * (hi - lo), 0.2)
        zoom.set_xlim(max(lo - pad, 0.0), hi + pad)
        shown = [a for line in zoom.get_lines() for v, a in zip(*line.get_data())
                 if zoom.get_xlim()[0] <= v <= zoom.get_xlim()[1] and np.isfinite(a)]
        ztop = max(max(shown, default=0.0), 1e-3)
        zoom.set_ylim(-0.05 * ztop, 1.2 * ztop)
        zoom.set_xlabel("speed V [km/h]")
        zoom.set_title(f"enlarged: {lo:.1f}-{hi:.1f} km/h", fontsize=9)
        ax.axvspan(max(lo - pad, 0.0), hi + pad, color="0.85", zorder=0)
        place_labels(zoom, [i for i in zoom_items if zoom.get_xlim()[0] <= i[0] <= zoom.get_xlim()[1]], avoid=hopf)
    place_labels(ax, items, avoid=hopf)
    ax.set_title(title or "Limit cycles", fontsize=10)
    save_figure(fig, path)
