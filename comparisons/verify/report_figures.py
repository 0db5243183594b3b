"""The figures of the verification report, one per section, drawn from plain numbers (no model objects), so
that the report can be redrawn from its JSON.  matplotlib's object API (``Figure``), no global state."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Mapping, Sequence

import numpy as np
from matplotlib.figure import Figure

from comparisons.figures.plots import save_figure
from comparisons.recordings.decimation import envelope_indices

# Hopf-speed sources: marker, colour, legend text.
HOPF_SOURCES = {
    "paper": ("x", "k", "paper (printed)"),
    "reduced": ("o", "tab:blue", "reduced model"),
    "mbs_reduced": ("+", "tab:orange", "MBS, reduced model's assumptions"),
    "mbs_full": ("^", "tab:green", "MBS, full geometry"),
}
RUN_COLOURS = {"reduced": "tab:blue", "mbs": "tab:orange"}
RUN_NAMES = {"reduced": "reduced model", "mbs": "MBS"}


def plot_hopf_speeds(panels: Mapping[str, Mapping[str, Sequence[tuple[float, float]]]], path: str,
                     title: str = "Hopf speeds against tyre pressure") -> None:
    """``panels``: panel title -> source (a key of :data:`HOPF_SOURCES`) -> [(pressure bar, speed km/h)]."""
    n = max(len(panels), 1)
    fig = Figure(figsize=(5.2 * n, 4.4))
    axes = np.atleast_1d(fig.subplots(1, n, sharey=True, squeeze=False)[0])
    for ax, (name, sources) in zip(axes, panels.items()):
        for key, points in sources.items():
            marker, colour, label = HOPF_SOURCES.get(key, ("s", "tab:red", key))
            pts = [(p, v) for p, v in points if v is not None and np.isfinite(v)]
            if not pts:
                continue
            p, v = np.array(pts).T
            filled = "none" if marker in "o^s" else colour
            ax.plot(p, v, marker, color=colour, mfc=filled, ms=8 if key == "reduced" else 7, mew=1.4, ls="none",
                    label=label)
        ax.set_title(name, fontsize=10)
        ax.set_xlabel("tyre pressure [bar]")
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("Hopf speed [km/h]")
    axes[0].legend(fontsize=8, loc="best")
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


def _thin(t: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Every 20 ms's min and max: a figure of a 100 s run at 1 kHz shows the same envelope from 1/10 the points."""
    k = envelope_indices(t, y, 0.02)
    return t[k], y[k]


def plot_jump_histories(experiments: Sequence[Experiment], path: str, title: str = "") -> None:
    """One column per experiment: max theta1 and psi of every run overlaid against time, the speed on a second
    axis, the times where the speed passes each mark (S1, T2, ...) dashed, the detected switches dotted."""
    n = len(experiments)
    fig = Figure(figsize=(6.4 * n, 6.0))
    axes = fig.subplots(2, n, sharex="col", squeeze=False)
    for j, exp in enumerate(experiments):
        top, bottom = axes[0, j], axes[1, j]
        for run in exp.runs:
            colour = RUN_COLOURS.get(run.model, "k")
            name = RUN_NAMES.get(run.model, run.model)
            for ax, y in ((top, run.theta1_deg), (bottom, run.psi_deg)):
                ax.plot(*_thin(run.t, y), color=colour, lw=0.5, alpha=0.8, label=name if ax is top else None)
            for time_s, speed, text in run.switches:
                for ax in (top, bottom):
                    ax.axvline(time_s, color=colour, ls=":", lw=1.3)
                top.annotate(f"{name}: {text}\n{speed:.1f} km/h", (time_s, 0.97), xycoords=("data", "axes fraction"),
                             textcoords="offset points", xytext=(3, -24 - 22 * exp.runs.index(run)), fontsize=7,
                             color=colour, bbox=dict(boxstyle="round,pad=0.1", fc="white", ec="none", alpha=0.8))
        ref = exp.runs[0]
        for label, kmh in exp.marks.items():
            crossing = _crossing_time(ref.t, ref.speed_kmh, kmh)
            if crossing is None:
                continue
            for ax in (top, bottom):
                ax.axvline(crossing, color="0.3", ls="--", lw=1.0)
            bottom.annotate(f"speed passes {label}\n({kmh:.2f} km/h)", (crossing, 0.03),
                            xycoords=("data", "axes fraction"), textcoords="offset points", xytext=(-3, 0),
                            ha="right", fontsize=7, color="0.25")
        twin = top.twinx()
        twin.plot(ref.t, ref.speed_kmh, color="0.55", lw=1.0)
        twin.set_ylabel("speed [km/h]", color="0.45")
        top.set_title(exp.title, fontsize=10)
        top.set_ylabel(r"$\theta_1$, right wheel yaw [deg]")
        bottom.set_ylabel(r"$\psi$, axle tramp [deg]")
        bottom.set_xlabel("time [s]")
        for ax in (top, bottom):
            ax.grid(alpha=0.3)
        top.legend(fontsize=8, loc="lower left")
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
        labelled = set()
        for i, s in enumerate(rows):
            if not s.hopf_shifts_kmh:
                ax.text(0.98, i, "no Hopf point on either side", va="center", ha="right", fontsize=7, color="0.35",
                        transform=ax.get_yaxis_transform())
            for k, x in enumerate(s.hopf_shifts_kmh):
                y = i - 0.4 + width * (k + 0.5)
                colour = f"C{k}"
                if x is None:
                    ax.plot(0.0, y, "x", color=colour, ms=7, mew=1.5)
                else:
                    ax.barh(y, x, height=width * 0.9, color=colour,
                            label=None if k in labelled else f"HB{k + 1}")
                    labelled.add(k)
        ax.set_yticks(range(len(rows)), [
            f"{s.assumption.replace('_', ' ')}: full geometry with - without" if s.assumption in ELEMENTS
            else "every assumption off (full geometry): MBS - reduced model" if s.assumption == "full"
            else f"{s.assumption.replace('_', ' ')} off: MBS - reduced model" for s in rows], fontsize=8)
        ax.axvline(0.0, color="k", lw=0.8)
        ax.set_xlabel("Hopf speed shift [km/h], as each row's label says")
        ax.set_title(f"{p:g} bar (x: the point has no MBS partner)", fontsize=9)
        ax.grid(axis="x", alpha=0.3)
        if labelled:
            ax.legend(fontsize=8, loc="lower right")
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    save_figure(fig, path)
