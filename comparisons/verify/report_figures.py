"""The figures of the verification report, one per section, drawn from plain numbers (no model objects), so
that the report can be redrawn from its JSON.  matplotlib's object API (``Figure``), no global state."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Mapping, Sequence

import numpy as np
from matplotlib.figure import Figure
from matplotlib.ticker import FixedLocator, FuncFormatter, NullLocator

from comparisons.figures.plots import save_figure
from comparisons.recordings.decimation import cycle_envelopes
from comparisons.recordings.timeseries import ENVELOPE_MIN_PERIOD_S

# Hopf-speed sources: marker, colour, legend text.
HOPF_SOURCES = {
    "paper": ("x", "k", "paper (printed)"),
    "reduced": ("o", "tab:blue", "reduced model"),
    "mbs_reduced": ("+", "tab:orange", "MBS, reduced model's assumptions"),
    "mbs_full": ("^", "tab:green", "MBS, full geometry"),
}
RUN_COLOURS = {"reduced": "tab:blue", "mbs": "tab:orange"}
RUN_NAMES = {"reduced": "reduced model", "mbs": "MBS"}


def curve_speeds_at(curves: Sequence[tuple[Sequence[float], Sequence[float]]], pressure_bar: float) -> list[float]:
    """Every speed (km/h) where one of the Hopf ``curves`` ((pressures bar, speeds km/h) along each) passes
    ``pressure_bar``, by linear interpolation between its points."""
    out = []
    for bars, speeds in curves:
        q, v = np.asarray(bars, dtype=float) - pressure_bar, np.asarray(speeds, dtype=float)
        for i in np.flatnonzero(np.sign(q[:-1]) * np.sign(q[1:]) <= 0.0):
            out.append(float(v[i] if q[i] == q[i + 1] else v[i] - q[i] * (v[i + 1] - v[i]) / (q[i + 1] - q[i])))
    return out


def plot_hopf_speeds(panels: Mapping[str, Mapping[str, Sequence[tuple[float, float]]]], path: str,
                     title: str = "Hopf speeds against tyre pressure",
                     curves: Mapping[str, Sequence[tuple[Sequence[float], Sequence[float]]]] | None = None) -> None:
    """``panels``: panel title -> source (a key of :data:`HOPF_SOURCES`) -> [(pressure bar, speed km/h)];
    ``curves``: panel title -> the reduced model's Hopf curves in (pressure, speed), each (pressures bar, speeds
    km/h).  Top row: the curves, with every source's points over them.  Bottom row: each point's speed minus the
    curve's at its pressure (symmetric-log axis, linear within 1 km/h), so that a 1 km/h difference between the
    paper and the curve shows, where at full scale the markers would sit on each other."""
    curves = curves or {}
    n = max(len(panels), 1)
    fig = Figure(figsize=(4.6 * n + 2.4, 6.2))
    axes = fig.subplots(2, n, sharex="col", squeeze=False, gridspec_kw={"height_ratios": (3, 1.6)})
    handles = {}
    for j, (name, sources) in enumerate(panels.items()):
        top, bottom = axes[0, j], axes[1, j]
        mine = curves.get(name, ())
        for k, (bars, speeds) in enumerate(mine):
            line, = top.plot(bars, speeds, "-", color="tab:blue", lw=1.3, alpha=0.7)
            handles.setdefault("curve", (line, "reduced model, Hopf curves (continued in pressure)"))
        for key, points in sources.items():
            marker, colour, label = HOPF_SOURCES.get(key, ("s", "tab:red", key))
            pts = [(p, v) for p, v in points if v is not None and np.isfinite(v)]
            if not pts:
                continue
            p, v = np.array(pts).T
            filled = "none" if marker in "o^s" else colour
            size = {"reduced": 9, "paper": 6}.get(key, 7)
            mark, = top.plot(p, v, marker, color=colour, mfc=filled, ms=size, mew=1.3, ls="none", zorder=4)
            handles.setdefault(key, (mark, label))
            if key == "reduced" or not mine:
                continue
            residual = []
            for pb, vb in zip(p, v):
                near = curve_speeds_at(mine, pb)
                if near:
                    residual.append((pb, vb - min(near, key=lambda c: abs(c - vb))))
            if residual:
                rp, rv = np.array(residual).T
                bottom.plot(rp, rv, marker, color=colour, mfc=filled, ms=size, mew=1.3, ls="none", zorder=4)
        top.set_title(name, fontsize=10)
        top.set_ylim(bottom=0.0)
        bottom.axhline(0.0, color="tab:blue", lw=1.0, alpha=0.7)
        bottom.set_yscale("symlog", linthresh=1.0)
        limit = max(2.0, *(abs(y) * 1.5 for line in bottom.get_lines() for y in line.get_ydata()))
        bottom.set_ylim(-limit, limit)
        bottom.yaxis.set_major_locator(FixedLocator([v for v in (-100, -10, -1, 0, 1, 10, 100) if abs(v) <= limit]))
        bottom.yaxis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:g}"))
        bottom.yaxis.set_minor_locator(NullLocator())
        bottom.set_xlabel("tyre pressure [bar]")
        for ax in (top, bottom):
            ax.grid(alpha=0.3)
    axes[0, 0].set_ylabel("Hopf speed [km/h]")
    axes[1, 0].set_ylabel("minus the curve [km/h]\n(symlog, linear within 1)")
    order = [k for k in ("curve", "paper", "reduced", "mbs_reduced", "mbs_full") if k in handles]
    order += [k for k in handles if k not in order]
    fig.legend([handles[k][0] for k in order], [handles[k][1] for k in order], fontsize=8,
               loc="upper left", bbox_to_anchor=(1.0, 0.9))
    fig.suptitle(title, fontsize=11)
    fig.tight_layout()
    save_figure(fig, path)


@dataclass(frozen=True)
class RunHistory:
    """One model's run of an experiment: time s, speed km/h, theta1 and psi in degrees, detected switches as
    (time s, speed km/h, text)."""

    model: str
    t: np.ndarray
    speed_kmh: np.ndarray
    theta1_deg: np.ndarray
    psi_deg: np.ndarray
    switches: Sequence[tuple[float, float, str]] = ()


@dataclass(frozen=True)
class Experiment:
    title: str
    runs: Sequence[RunHistory]
    marks: Mapping[str, float] = field(default_factory=dict)   # e.g. {"S1": 184.7}: speeds, km/h


# The first run narrow and opaque, the others wide and translucent: where they coincide both show.
_RUN_STYLE = {False: dict(lw=1.0, alpha=1.0), True: dict(lw=3.2, alpha=0.55)}


def plot_jump_histories(experiments: Sequence[Experiment], path: str, title: str = "") -> None:
    """One column per experiment: theta1 and psi of every run overlaid against time as their per-cycle envelopes
    (:func:`comparisons.recordings.decimation.cycle_envelopes`: lines through each swing's highest and lowest
    point, where the samples themselves would fill a band), the speed on a second
    axis, the times where the speed passes each mark (S1, T2, ...) dashed, the detected switches dotted.  What
    each line means, with the switch speeds, is in a key below the column: no label sits on a signal."""
    from matplotlib.lines import Line2D
    n = len(experiments)
    fig = Figure(figsize=(6.4 * n, 7.2))
    axes = fig.subplots(2, n, sharex="col", squeeze=False)
    for j, exp in enumerate(experiments):
        top, bottom = axes[0, j], axes[1, j]
        key = []
        for run in exp.runs:
            colour = RUN_COLOURS.get(run.model, "k")
            name = RUN_NAMES.get(run.model, run.model)
            style = _RUN_STYLE[run is not exp.runs[0]]
            for ax, y in ((top, run.theta1_deg), (bottom, run.psi_deg)):
                for idx in cycle_envelopes(run.t, y, ENVELOPE_MIN_PERIOD_S):
                    ax.plot(run.t[idx], y[idx], color=colour, **style)
            key.append(Line2D([], [], color=colour, **style, label=f"{name}: highest and lowest point of each swing"))
            for time_s, speed, text in run.switches:
                for ax in (top, bottom):
                    ax.axvline(time_s, color=colour, ls=":", lw=1.3)
                key.append(Line2D([], [], color=colour, ls=":", lw=1.3,
                                  label=f"{name}: {text} at {time_s:.1f} s, {speed:.1f} km/h"))
        ref = exp.runs[0]
        for label, kmh in exp.marks.items():
            crossing = _crossing_time(ref.t, ref.speed_kmh, kmh)
            if crossing is None:
                continue
            for ax in (top, bottom):
                ax.axvline(crossing, color="0.3", ls="--", lw=1.0)
            key.append(Line2D([], [], color="0.3", ls="--", lw=1.0,
                              label=f"speed passes {label} ({kmh:.2f} km/h) at {crossing:.1f} s"))
        twin = top.twinx()
        twin.plot(ref.t, ref.speed_kmh, color="0.55", lw=1.0)
        twin.set_ylabel("speed [km/h]", color="0.45")
        key.append(Line2D([], [], color="0.55", lw=1.0, label="speed (right axis)"))
        top.set_title(exp.title, fontsize=10)
        top.set_ylabel(r"$\theta_1$, right wheel yaw [deg]")
        bottom.set_ylabel(r"$\psi$, axle tramp [deg]")
        bottom.set_xlabel("time [s]")
        for ax in (top, bottom):
            ax.grid(alpha=0.3)
        bottom.legend(handles=key, fontsize=7, loc="upper left", bbox_to_anchor=(0.0, -0.2), frameon=False)
    if title:
        fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    save_figure(fig, path)


def _crossing_time(t: np.ndarray, speed: np.ndarray, kmh: float) -> float | None:
    s = np.asarray(speed) - kmh
    idx = np.flatnonzero(np.sign(s[:-1]) != np.sign(s[1:]))
    if len(idx) == 0:
        return None
    i = idx[0]
    return float(t[i] - s[i] * (t[i + 1] - t[i]) / (s[i + 1] - s[i]))


@dataclass(frozen=True)
class AssumptionShift:
    """What switching one assumption off in the MBS does at one pressure: the shift of each Hopf speed (km/h,
    None where a point has no partner) and of the peak limit-cycle amplitude (deg, None if not computed)."""

    pressure_bar: float
    assumption: str
    hopf_shifts_kmh: Sequence[float | None]
    peak_theta1_shift_deg: float | None = None


def plot_assumption_tornado(shifts: Sequence[AssumptionShift], path: str,
                            title: str = "What each assumption of the reduced model costs") -> None:
    """One panel per pressure; per assumption one horizontal bar per Hopf point (HB1, HB2, ...), longest on top;
    a point without partner is marked with a cross at zero, a row without any Hopf point says so.  Each row's label
    names what it compares: an assumption's row the MBS with that assumption off against the reduced model, a
    geometric element's row the full geometry with the element against it without."""
    from comparisons.studies.assumption_study import ELEMENTS
    pressures = sorted({s.pressure_bar for s in shifts})
    n = max(len(pressures), 1)
    height = max(3.0, 0.5 * max((sum(s.pressure_bar == p for s in shifts) for p in pressures), default=1) + 1.5)
    fig = Figure(figsize=(6.0 * n, height))
    axes = np.atleast_1d(fig.subplots(1, n, squeeze=False)[0])
    for ax, p in zip(axes, pressures):
        rows = [s for s in shifts if s.pressure_bar == p]
        rows.sort(key=lambda s: max((abs(x) for x in s.hopf_shifts_kmh if x is not None), default=0.0))
        k_max = max((len(s.hopf_shifts_kmh) for s in rows), default=0)
        width = 0.8 / max(k_max, 1)
        for i, s in enumerate(rows):
            for k, x in enumerate(s.hopf_shifts_kmh):
                y = i - 0.4 + width * (k + 0.5)
                colour = f"C{k}"
                if x is None:
                    ax.plot(0.0, y, "x", color=colour, ms=7, mew=1.5)
                else:
                    ax.barh(y, x, height=width * 0.9, color=colour)
        ax.set_yticks(range(len(rows)), [
            (f"{s.assumption.replace('_', ' ')}: full geometry with - without" if s.assumption in ELEMENTS
             else "every assumption off (full geometry): MBS - reduced model" if s.assumption == "full"
             else f"{s.assumption.replace('_', ' ')} off: MBS - reduced model")
            + ("" if s.hopf_shifts_kmh else "\n(no Hopf point on either side)") for s in rows], fontsize=8)
        ax.axvline(0.0, color="k", lw=0.8)
        ax.set_xlabel("Hopf speed shift [km/h], as each row's label says")
        ax.set_title(f"{p:g} bar (x: the point has no MBS partner)", fontsize=9)
        ax.grid(axis="x", alpha=0.3)
    # One key for every panel: the colour is the Hopf point's number at its pressure (HB1 lowest in speed).
    points = max((len(s.hopf_shifts_kmh) for s in shifts), default=0)
    if points:
        from matplotlib.patches import Patch
        axes[-1].legend(handles=[Patch(color=f"C{k}", label=f"HB{k + 1}") for k in range(points)], fontsize=8,
                        loc="upper left", bbox_to_anchor=(1.01, 1.0), title="Hopf point\n(at its pressure)",
                        title_fontsize=8)
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    save_figure(fig, path)
