"""The paper's figures recomputed by this project: a registry figure number -> drawing function.

Each drawing function takes a :class:`DiagramStore` (which computes and remembers Hopf diagrams, so that two
figures sharing a diagram compute it once) and returns a :class:`Drawing`: the matplotlib figure plus notes (the
computed numbers worth comparing with the paper's text).  Axes and units follow the paper: speed in km/h,
pressure in bar, lengths in m, stiffness in N/m, slip angles in degrees.

Figures that need what the project cannot compute yet are listed in :data:`UNAVAILABLE` with the reason;
asking for one raises :class:`FigureUnavailable`.  Making such a figure available means registering a drawing
function with :func:`register` (and removing its entry from :data:`UNAVAILABLE`).
"""

from __future__ import annotations

import dataclasses
import os
import time
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from reduced_model import tyre
from reduced_model.cycle_curves import CycleCurve, cycle_bifurcation_curve
from reduced_model.cycles import CycleBranch, CycleDiagram, branch_peak, cycle_at, cycle_diagram
from reduced_model.family import SpeedFamily
from reduced_model.hopf import hopf_points
from reduced_model.hopf_curves import HopfCurve, HopfDiagram, hopf_diagram
from reduced_model.model import Effects, ShimmyModel
from reduced_model.modes import ModeClassifier, ModeHistory
from reduced_model.parameters import YANG2024
from reduced_model.simulation import initial_state, simulate
from reduced_model.special_points import ConvergenceError, PointKind, PointStatus
from reduced_model.trajectory import SpeedSchedule, Trajectory

from . import paper_reference as paper
from .cycle_plots import CURVE_STYLES, draw_cycle_diagram, special_point_labels
from .plots import plt, save_figure, stability_grid

BAR = 1e5
KMH = 1.0 / 3.6
P_I0_BAR = YANG2024.pi0 / BAR
VMAX_KMH = 400.0                            # speed window of every (V, q) figure
FOUR_PRESSURES_BAR = (1.5, 2.0, 2.5, 3.0)   # 0.6, 0.8, 1.0, 1.2 p_i0 (figures 6, 7, 13)
# Figure 14: the text describes F1 and F2 at 1.024 p_i0 and F3 "with a further increase in p_i"; 2.7 bar shows F3.
K5_PRESSURES_BAR = (1.5, 2.5, 2.56, 2.7)
PRESSURE_COLOURS = {1.5: "tab:blue", 2.0: "tab:orange", 2.5: "tab:red", 3.0: "tab:green",
                    2.56: "tab:purple", 2.7: "tab:green", 3.5: "tab:brown"}
SLIP_PRESSURES_BAR = (1.5, 2.0, 2.5, 3.0, 3.5)
# Figure 17 colours as named in section 5 of the paper (VS is not named there).
EFFECT_STYLES = (("LF", "navy"), ("+HCL", "red"), ("+PT", "green"), ("+RL", "deepskyblue"),
                 ("+VS", "darkorange"))
MIN_LABEL_SPEED_KMH = 1.0  # folds at V ~ 0, where a curve touches the window's edge V = 0: in the notes, unlabelled


class FigureUnavailable(Exception):
    """A figure of the paper that this project cannot compute (yet); the message says what is missing."""


@dataclass(frozen=True)
class Drawing:
    figure: object                     # matplotlib Figure
    notes: tuple[str, ...] = ()
    complete: bool = True              # False when a Hopf curve stopped before leaving its window


@dataclass(frozen=True)
class FigureEntry:
    number: int
    name: str                          # short file-name part
    title: str
    draw: Callable[["DiagramStore"], Drawing]
    cost: float = 1.0                  # rough seconds on one core, to start the longest first in parallel runs

    @property
    def file_name(self) -> str:
        return f"fig{self.number:02d}_{self.name}.png"


@dataclass(frozen=True)
class FigureResult:
    number: int
    name: str
    path: str
    seconds: float
    complete: bool
    notes: tuple[str, ...]


PAPER_TITLES = {
    1: "model of steering wheel shimmy (rear, side and top view)",
    2: "influence of inflation pressure on the lateral force curve",
    3: "one-parameter bifurcation diagrams at nominal inflation pressure",
    4: "one-parameter bifurcation diagrams at 1.5 bar and 2.7 bar",
    5: "effect of inflation pressure on the Hopf bifurcations (lateral force only)",
    6: "effect of half-contact length on the Hopf bifurcations for four pressures",
    7: "effect of pneumatic trail on the Hopf bifurcations for four pressures",
    8: "effect of pneumatic trail on the Hopf bifurcations at 0.6 p_i0",
    9: "one-parameter bifurcation diagrams for pneumatic trail 0.25 m and 0.285 m at 1.5 bar",
    10: "time histories of mode changes at 0.25 m and 1.5 bar, increasing and decreasing speed",
    11: "phase portrait of the bi-stable region at 180 km/h",
    12: "influence of inflation pressure on the pneumatic trail against slip angle",
    13: "effect of relaxation length on the Hopf bifurcations for four pressures",
    14: "effect of vertical stiffness on the Hopf bifurcations for four pressures",
    15: "one-parameter bifurcation diagrams at p_i0 and 1.024 p_i0 with lowered vertical stiffness",
    16: "influence of inflation pressure on half-contact length, relaxation length and vertical stiffness",
    17: "Hopf curves in (V, p_i) for the cumulative tyre-property sets, with zooms Z1 and Z2",
    18: "enlarged diagram with torus and saddle-node bifurcation curves",
}

UNAVAILABLE: dict[int, str] = {
    1: "it is a drawing of the model, not a computed result (the 3D scene of a recording shows the geometry)",
}

REGISTRY: dict[int, FigureEntry] = {}


def register(number: int, name: str, cost: float = 1.0):
    """Decorator: make ``draw(store) -> Drawing`` the recipe of the paper's figure ``number``."""
    def wrap(draw: Callable[["DiagramStore"], Drawing]):
        REGISTRY[number] = FigureEntry(number, name, PAPER_TITLES[number], draw, cost)
        return draw
    return wrap


def available_figures() -> tuple[int, ...]:
    return tuple(sorted(n for n in REGISTRY if n not in UNAVAILABLE))


def unavailable_reason(number: int) -> str | None:
    """Why figure ``number`` cannot be made, or None if it can; unknown numbers raise KeyError."""
    if number not in PAPER_TITLES:
        raise KeyError(f"the paper has no figure {number} (it has figures 1-{max(PAPER_TITLES)})")
    if number in UNAVAILABLE or number not in REGISTRY:
        return UNAVAILABLE.get(number, "no recipe registered")
    return None


# --- computing -----------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class DiagramKey:
    effects: Effects
    param: str
    pressure_bar: float     # used when param != "pressure"
    lo: float               # SI
    hi: float
    vmin_kmh: float
    vmax_kmh: float
    n_seeds: int = 9


@dataclass
class DiagramStore:
    """Hopf diagrams by :class:`DiagramKey` and cycle diagrams by :class:`CycleKey`, each computed once per
    store."""

    _diagrams: dict = field(default_factory=dict)
    _families: dict = field(default_factory=dict)
    _cycles: dict = field(default_factory=dict)      # CycleKey -> (family, CycleDiagram)

    def family(self, key: DiagramKey) -> SpeedFamily:
        fkey = (key.effects, key.param, key.pressure_bar)
        if fkey not in self._families:
            self._families[fkey] = SpeedFamily(ShimmyModel(effects=key.effects), key.param,
                                               pressure=key.pressure_bar * BAR)
        return self._families[fkey]

    def diagram(self, key: DiagramKey) -> HopfDiagram:
        if key not in self._diagrams:
            self._diagrams[key] = hopf_diagram(self.family(key), key.lo, key.hi, key.vmin_kmh * KMH,
                                               key.vmax_kmh * KMH, n_seeds=key.n_seeds)
        return self._diagrams[key]


def make_figure(number: int, out_dir: str, store: DiagramStore | None = None) -> FigureResult:
    """Draw figure ``number`` into ``out_dir`` (atomic write); raises :class:`FigureUnavailable`."""
    reason = unavailable_reason(number)
    if reason is not None:
        raise FigureUnavailable(f"figure {number} ({PAPER_TITLES[number]}) cannot be made: {reason}")
    entry = REGISTRY[number]
    store = store if store is not None else DiagramStore()
    start = time.perf_counter()
    drawing = entry.draw(store)
    path = os.path.join(out_dir, entry.file_name)
    save_figure(drawing.figure, path)
    return FigureResult(number=number, name=entry.name, path=path, seconds=time.perf_counter() - start,
                        complete=drawing.complete, notes=drawing.notes)


def make_figures(numbers, out_dir: str, jobs: int = 1, on_done: Callable[[FigureResult], None] | None = None
                 ) -> list[FigureResult]:
    """Make the listed (available) figures into ``out_dir``, with ``jobs`` worker processes; results by number.

    Workers are spawned (not forked: the parent may run a progress-bar thread) and each keeps its own
    :class:`DiagramStore`, so figures sharing a diagram share it only when they land on the same worker.
    """
    numbers = sorted(set(numbers))
    for n in numbers:
        reason = unavailable_reason(n)
        if reason is not None:
            raise FigureUnavailable(f"figure {n} ({PAPER_TITLES[n]}) cannot be made: {reason}")
    results = []
    if jobs <= 1 or len(numbers) <= 1:
        store = DiagramStore()
        for n in numbers:
            results.append(make_figure(n, out_dir, store))
            if on_done is not None:
                on_done(results[-1])
        return sorted(results, key=lambda r: r.number)
    import concurrent.futures
    import multiprocessing
    ordered = sorted(numbers, key=lambda n: -REGISTRY[n].cost)
    with concurrent.futures.ProcessPoolExecutor(max_workers=min(jobs, len(numbers)),
                                                mp_context=multiprocessing.get_context("spawn")) as pool:
        futures = [pool.submit(_make_in_worker, n, out_dir) for n in ordered]
        for future in concurrent.futures.as_completed(futures):
            results.append(future.result())
            if on_done is not None:
                on_done(results[-1])
    return sorted(results, key=lambda r: r.number)


_WORKER_STORE: DiagramStore | None = None


def _make_in_worker(number: int, out_dir: str) -> FigureResult:
    global _WORKER_STORE
    if _WORKER_STORE is None:
        _WORKER_STORE = DiagramStore()
    return make_figure(number, out_dir, _WORKER_STORE)


# --- drawing helpers -----------------------------------------------------------------------------------------

def _pressure_label(p_bar: float) -> str:
    return f"{p_bar:g} bar ({p_bar / P_I0_BAR:.3g} $p_{{i0}}$)"


def _shade_stable(ax, family: SpeedFamily, diagram: HopfDiagram, factor: float, colour="0.85", alpha=1.0) -> None:
    """Shade where straight running is stable (all eigenvalues in the left half plane)."""
    speeds = np.linspace(diagram.vmin, diagram.vmax, 201)
    values = np.linspace(diagram.lo, diagram.hi, 121)
    stable = (stability_grid(family, speeds, values) == 0).astype(float)
    ax.contourf(speeds * 3.6, values / factor, stable, levels=[0.5, 1.5], colors=[colour], alpha=alpha)


def _draw_curves(ax, diagram: HopfDiagram, factor: float, colour, label=None, lw=1.4) -> None:
    for i, c in enumerate(diagram.curves):
        ax.plot(c.speeds * 3.6, c.values / factor, "-", color=colour, lw=lw, label=label if i == 0 else None)


def _located(diagram: HopfDiagram, kind: PointKind) -> list:
    return sorted((p for p in diagram.points_of(kind) if p.status is PointStatus.LOCATED
                   and p.speed * 3.6 >= MIN_LABEL_SPEED_KMH), key=lambda p: p.value)


def _curve_of(diagram: HopfDiagram, point) -> HopfCurve:
    """The curve passing closest to a special point."""
    def dist(c):
        return np.min(np.hypot((c.speeds - point.speed) / 10.0,
                               (c.values - point.value) / (diagram.hi - diagram.lo)))
    return min(diagram.curves, key=dist)


def _fold_is_maximum(diagram: HopfDiagram, point) -> bool:
    """Whether the Hopf curve reaches a local maximum of the parameter at this fold (else a minimum)."""
    c = _curve_of(diagram, point)
    k = int(np.argmin(np.hypot((c.speeds - point.speed) / 10.0, (c.values - point.value) / (diagram.hi - diagram.lo))))
    around = c.values[max(k - 3, 0):k + 4]
    return bool(np.mean(around) < point.value)


def _mark(ax, point, factor, text, colour="k", offset=(5, 5), marker="o", text_at=None) -> None:
    """Mark a special point; the label sits ``offset`` points away, or at data position ``text_at`` with an arrow."""
    x, y = point.speed * 3.6, point.value / factor
    ax.plot(x, y, marker, color=colour, ms=5, mfc="white", mew=1.3, zorder=5)
    if text:
        where = dict(xytext=text_at, textcoords="data", arrowprops=dict(arrowstyle="-", color=colour, lw=0.7)) \
            if text_at is not None else dict(xytext=offset, textcoords="offset points")
        ax.annotate(text, (x, y), fontsize=8, color=colour, zorder=6,
                    bbox=dict(boxstyle="round,pad=0.15", fc="white", ec="none", alpha=0.75), **where)


def _label_hopf_points(ax, family: SpeedFamily, q: float, factor: float, vmax_kmh: float, colour="k",
                       offset=(4, -11)) -> list:
    """Label the Hopf points on the line q = const as HB1, HB2, ... by speed (the paper's naming)."""
    points = hopf_points(family, q, 0.0, vmax_kmh * KMH, lyapunov=False)
    for i, h in enumerate(points, 1):
        ax.plot(h.speed * 3.6, q / factor, ".", color=colour, ms=6)
        ax.annotate(f"HB{i}", (h.speed * 3.6, q / factor), textcoords="offset points", xytext=offset, fontsize=8,
                    color=colour)
    return list(points)


def _point_note(name: str, p, unit: str, factor: float, fmt: str = ".4g") -> str:
    return f"{name}: {p.speed * 3.6:.2f} km/h, {p.value / factor:{fmt}} {unit}"


def _special_notes(prefix: str, diagram: HopfDiagram, unit: str, factor: float) -> list[str]:
    names = {PointKind.HOPF_FOLD: "fold", PointKind.HOPF_HOPF: "Hopf-Hopf", PointKind.GENERALIZED_HOPF: "DH",
             PointKind.ZERO_HOPF: "zero-Hopf"}
    notes = []
    for p in sorted(diagram.special_points, key=lambda p: (p.kind.value, p.value)):
        status = "" if p.status is PointStatus.LOCATED else f" ({p.status.value})"
        notes.append(f"{prefix}{_point_note(names.get(p.kind, p.kind.value), p, unit, factor)}{status}")
    return notes


def _incomplete_notes(prefix: str, diagram: HopfDiagram) -> list[str]:
    return [f"{prefix}INCOMPLETE curve: {' | '.join(c.messages)}" for c in diagram.curves if not c.complete]


def _speed_axis(ax, vmax_kmh: float = VMAX_KMH, vmin_kmh: float = 0.0) -> None:
    ax.set_xlim(vmin_kmh, vmax_kmh)
    ax.set_xlabel("speed V [km/h]")


# --- figures that need only the tyre formulas ----------------------------------------------------------------

@register(2, "lateral_force")
def draw_lateral_force(store: DiagramStore) -> Drawing:
    alpha_deg = np.linspace(-20.0, 20.0, 801)
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
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
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
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
    fig, axes = plt.subplots(1, 3, figsize=(11.5, 3.6))
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


# --- Hopf-curve figures --------------------------------------------------------------------------------------

def _pressure_key(effects: Effects = Effects(), lo_bar=0.05, hi_bar=3.0, vmin_kmh=0.0, vmax_kmh=VMAX_KMH,
                  n_seeds=9) -> DiagramKey:
    return DiagramKey(effects, "pressure", P_I0_BAR, lo_bar * BAR, hi_bar * BAR, vmin_kmh, vmax_kmh, n_seeds)


@register(5, "pressure_hopf_curves", cost=1)
def draw_pressure_curves(store: DiagramStore) -> Drawing:
    key = _pressure_key()
    diagram, family = store.diagram(key), store.family(key)
    fig, ax = plt.subplots(figsize=(6.8, 4.8))
    _shade_stable(ax, family, diagram, BAR)
    _draw_curves(ax, diagram, BAR, "k")
    _label_hopf_points(ax, family, 1.5 * BAR, BAR, VMAX_KMH)
    folds = _located(diagram, PointKind.HOPF_FOLD)
    notes = []
    if folds:
        f1 = folds[-1]   # the highest-pressure fold: where the last (yaw) mode vanishes
        _mark(ax, f1, BAR, f"F1 ({f1.speed * 3.6:.1f} km/h, {f1.value / BAR:.3f} bar)", offset=(6, 4))
        notes.append(_point_note("F1 (yaw mode vanishes)", f1, "bar", BAR))
        for f in folds[:-1]:
            _mark(ax, f, BAR, f"tramp-mode fold\n({f.speed * 3.6:.1f} km/h, {f.value / BAR:.3f} bar)",
                  offset=(-40, 8))
            notes.append(_point_note("tramp-mode fold (tramp mode vanishes)", f, "bar", BAR))
    ax.text(70, 1.0, "yaw\nmode", ha="center", fontsize=9)
    ax.text(270, 1.0, "tramp mode", ha="center", fontsize=9)
    ax.text(300, 2.5, "no shimmy (shaded)", ha="center", fontsize=9)
    _speed_axis(ax)
    ax.set_ylim(key.lo / BAR, key.hi / BAR)
    ax.set_ylabel("inflation pressure $p_i$ [bar]")
    ax.set_title("Fig. 5: Hopf curves, lateral force depends on pressure (section 3 model)\n"
                 "shaded: straight running stable", fontsize=10)
    notes += _incomplete_notes("", diagram)
    return Drawing(fig, tuple(notes), diagram.complete)


def _four_pressure_figure(store: DiagramStore, param: str, lo: float, hi: float, ylabel: str,
                          pressures=FOUR_PRESSURES_BAR, unit: str = "m", sci: bool = False) -> tuple:
    fig, ax = plt.subplots(figsize=(8.4, 4.8))
    notes, complete, diagrams = [], True, {}
    speeds = values = None
    stable_count = 0
    for p in pressures:
        key = DiagramKey(Effects(), param, p, lo, hi, 0.0, VMAX_KMH)
        diagram, family = store.diagram(key), store.family(key)
        if speeds is None:
            speeds = np.linspace(diagram.vmin, diagram.vmax, 201)
            values = np.linspace(diagram.lo, diagram.hi, 121)
        stable_count = stable_count + (stability_grid(family, speeds, values) == 0)
        colour = PRESSURE_COLOURS[p]
        _draw_curves(ax, diagram, 1.0, colour, label=_pressure_label(p))
        for f in _located(diagram, PointKind.HOPF_FOLD):
            ax.plot(f.speed * 3.6, f.value, "o", color=colour, ms=4, mfc="white", zorder=4)
        for kind, marker in ((PointKind.HOPF_HOPF, "s"), (PointKind.GENERALIZED_HOPF, "D")):
            for s in _located(diagram, kind):
                ax.plot(s.speed * 3.6, s.value, marker, color=colour, ms=4, mfc="white", zorder=4)
        notes += _special_notes(f"{p:g} bar: ", diagram, unit, 1.0)
        notes += _incomplete_notes(f"{p:g} bar: ", diagram)
        complete &= diagram.complete
        diagrams[p] = diagram
    # One grey level per number of pressures at which straight running is stable: overlapping tints of four
    # colours mix into an unreadable brown.
    n = len(pressures)
    ax.contourf(speeds * 3.6, values, stable_count, levels=np.arange(0.5, n + 1), zorder=0,
                colors=[str(0.97 - 0.06 * k) for k in range(n)])
    ax.axhline(getattr(YANG2024, param), color="0.4", lw=0.7, ls=":")
    _speed_axis(ax)
    ax.set_ylim(lo, hi)
    ax.set_ylabel(ylabel)
    if sci:
        ax.ticklabel_format(axis="y", style="sci", scilimits=(5, 5))
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    return fig, ax, notes, complete, diagrams


_FOUR_NOTE = ("grey: straight running stable at 1, 2, 3 or all 4 pressures (darker: more); "
              "o fold, s Hopf-Hopf, D degenerate Hopf;\ndotted: Table 1 value")


@register(6, "half_contact_length_hopf_curves", cost=3)
def draw_half_contact_length(store: DiagramStore) -> Drawing:
    fig, ax, notes, complete, _ = _four_pressure_figure(store, "a0", 0.05, 0.5, "half-contact length a [m]")
    ax.set_title("Fig. 6: Hopf curves in (V, a) at four pressures\n" + _FOUR_NOTE, fontsize=9)
    return Drawing(fig, tuple(notes), complete)


T0_RANGE = (0.02, 0.32)


@register(7, "trail_hopf_curves", cost=8)
def draw_trail_curves(store: DiagramStore) -> Drawing:
    fig, ax, notes, complete, _ = _four_pressure_figure(store, "t0", *T0_RANGE, "pneumatic trail t [m]")
    ax.set_title("Fig. 7: Hopf curves in (V, t) at four pressures\n" + _FOUR_NOTE, fontsize=9)
    return Drawing(fig, tuple(notes), complete)


@register(8, "trail_hopf_curves_1p5bar", cost=3)
def draw_trail_low_pressure(store: DiagramStore) -> Drawing:
    key = DiagramKey(Effects(), "t0", 1.5, *T0_RANGE, 0.0, VMAX_KMH)
    diagram, family = store.diagram(key), store.family(key)
    fig, ax = plt.subplots(figsize=(6.8, 5.0))
    _shade_stable(ax, family, diagram, 1.0)
    _draw_curves(ax, diagram, 1.0, "k")
    _label_hopf_points(ax, family, YANG2024.t0, 1.0, VMAX_KMH)
    notes = []
    for i, hh in enumerate(_located(diagram, PointKind.HOPF_HOPF), 1):
        name = "HH" if len(_located(diagram, PointKind.HOPF_HOPF)) == 1 else f"HH{i}"
        _mark(ax, hh, 1.0, f"{name} (t = {hh.value:.3f} m)", colour="tab:red", marker="s", offset=(-95, -3))
        notes.append(_point_note(name, hh, "m", 1.0))
    for i, dh in enumerate(_located(diagram, PointKind.GENERALIZED_HOPF), 1):
        _mark(ax, dh, 1.0, f"DH{i} (t = {dh.value:.3f} m)", colour="tab:blue", marker="D", offset=(6, -3))
        notes.append(_point_note(f"DH{i} (criticality changes)", dh, "m", 1.0))
    offsets = iter(((6, -12), (6, -12), (-40, 8), (6, -12)))
    for i, f in enumerate(_located(diagram, PointKind.HOPF_FOLD), 1):
        _mark(ax, f, 1.0, f"F{i} ({f.value:.3f} m)", offset=next(offsets, (6, 4)))
        notes.append(_point_note(f"fold F{i}", f, "m", 1.0))
    for p in diagram.points_of(PointKind.HOPF_FOLD):
        if p.status is not PointStatus.LOCATED or p.speed * 3.6 < MIN_LABEL_SPEED_KMH:
            notes.append(_point_note(f"fold at the window edge, not labelled ({p.status.value})", p, "m", 1.0))
    ax.axhline(YANG2024.t0, color="0.4", lw=0.7, ls=":")
    _speed_axis(ax)
    ax.set_ylim(key.lo, key.hi)
    ax.set_ylabel("pneumatic trail t [m]")
    ax.set_title("Fig. 8: Hopf curves in (V, t) at 1.5 bar (0.6 $p_{i0}$); shaded: straight running stable\n"
                 "HB labels on the Table 1 trail (dotted); torus/saddle-node curves need periodic orbits",
                 fontsize=9)
    notes += _incomplete_notes("", diagram)
    return Drawing(fig, tuple(notes), diagram.complete)


@register(13, "relaxation_length_hopf_curves", cost=12)
def draw_relaxation_length(store: DiagramStore) -> Drawing:
    fig, ax, notes, complete, _ = _four_pressure_figure(store, "sigma0", 0.01, 1.5,
                                                        "relaxation length σ [m]")
    ax.set_title("Fig. 13: Hopf curves in (V, σ) at four pressures\n" + _FOUR_NOTE, fontsize=9)
    return Drawing(fig, tuple(notes), complete)


@register(14, "vertical_stiffness_hopf_curves", cost=6)
def draw_vertical_stiffness(store: DiagramStore) -> Drawing:
    fig, ax, notes, complete, diagrams = _four_pressure_figure(
        store, "k5_0", 1.5e5, 7.0e5, "vertical stiffness $k_5$ [N/m]", pressures=K5_PRESSURES_BAR,
        unit="N/m", sci=True)
    # The paper's names: at 1.024 p_i0 the modes separate at F1 (vertex of the raised part of the lower curve)
    # and F2 (lowest point of the upper, yaw-mode curve); F2 moves to F3 at higher pressure.
    labelled = [(2.56, "F1", "F2"), (2.7, None, "F3")]
    for p, low_name, high_name in labelled:
        diagram = diagrams.get(p)
        if diagram is None:
            continue
        folds = _located(diagram, PointKind.HOPF_FOLD)
        top = max(diagram.curves, key=lambda c: np.min(c.values))
        upper = [f for f in folds if _curve_of(diagram, f) is top and not _fold_is_maximum(diagram, f)]
        lower_max = sorted((f for f in folds if _curve_of(diagram, f) is not top and _fold_is_maximum(diagram, f)),
                           key=lambda f: f.speed)
        if len(diagram.curves) > 1 and upper:
            f = min(upper, key=lambda f: f.value)
            _mark(ax, f, 1.0, f"{high_name} ({f.value / 1e5:.2f}e5 N/m)", colour=PRESSURE_COLOURS[p],
                  offset=(8, -4))
        if low_name and lower_max:
            f = lower_max[0]
            _mark(ax, f, 1.0, f"{low_name} ({f.value / 1e5:.2f}e5 N/m)", colour=PRESSURE_COLOURS[p],
                  text_at=(105.0, 1.75e5))
    ax.set_title("Fig. 14: Hopf curves in (V, $k_5$) at four pressures\n" + _FOUR_NOTE, fontsize=9)
    return Drawing(fig, tuple(notes), complete)


ZOOM_SEEDS = 41   # a curve lying between two seed lines of a zoom window would be missed: see _uncovered


def _uncovered(full: HopfDiagram, zoom: HopfDiagram, tol: float = 1e-2) -> int:
    """How many points of the full-window curves inside the zoom window are farther than ``tol`` (relative to
    the zoom window; chords of the polylines sag by ~1e-3) from every zoom curve: a check that the zoom's own
    seeding found every curve."""
    dv, dq = zoom.vmax - zoom.vmin, zoom.hi - zoom.lo
    zoom_pts = [np.column_stack([c.speeds / dv, c.values / dq]) for c in zoom.curves]
    count = 0
    for c in full.curves:
        inside = ((c.speeds > zoom.vmin) & (c.speeds < zoom.vmax) & (c.values > zoom.lo) & (c.values < zoom.hi))
        for v, q in zip(c.speeds[inside] / dv, c.values[inside] / dq):
            dist = min((_segment_distance(P, np.array([v, q])) for P in zoom_pts), default=np.inf)
            count += dist > tol
    return int(count)


def _segment_distance(P: np.ndarray, x: np.ndarray) -> float:
    """Distance from x to the polyline P (rows are points)."""
    if len(P) == 1:
        return float(np.linalg.norm(P[0] - x))
    a, seg = P[:-1], np.diff(P, axis=0)
    lam = np.clip(np.einsum("ij,ij->i", x - a, seg) / np.maximum(np.einsum("ij,ij->i", seg, seg), 1e-300), 0, 1)
    return float(np.min(np.linalg.norm(a + lam[:, None] * seg - x, axis=1)))


Z1 = (2.45, 2.65, 30.0, 90.0)     # bar, bar, km/h, km/h: where the yaw mode ends
Z2 = (0.01, 0.6, 150.0, 260.0)    # where the two modes meet at low pressure
# The full window reaches down to Z2's lower edge, so that every curve piece the zooms should show is checked.
P17_BAR = (Z2[0], 3.0)


@register(17, "cumulative_effects_hopf_curves", cost=18)
def draw_cumulative(store: DiagramStore) -> Drawing:
    fig = plt.figure(figsize=(11.0, 5.6))
    grid = fig.add_gridspec(2, 2, width_ratios=(1.6, 1.0))
    ax = fig.add_subplot(grid[:, 0])
    zooms = (fig.add_subplot(grid[0, 1]), fig.add_subplot(grid[1, 1]))
    notes, complete = [], True
    for effects, (label, colour) in zip(Effects.cumulative(), EFFECT_STYLES):
        diagram = store.diagram(_pressure_key(effects, *P17_BAR))
        _draw_curves(ax, diagram, BAR, colour, label=label)
        folds = _located(diagram, PointKind.HOPF_FOLD)
        if folds:
            notes.append(f"{label}: no shimmy above {folds[-1].value / BAR:.4f} bar "
                         f"(fold at {folds[-1].speed * 3.6:.2f} km/h)")
        notes += _special_notes(f"{label}: ", diagram, "bar", BAR)
        notes += _incomplete_notes(f"{label}: ", diagram)
        complete &= diagram.complete
        for zax, (plo, phi, vlo, vhi) in zip(zooms, (Z1, Z2)):
            zd = store.diagram(_pressure_key(effects, plo, phi, vlo, vhi, n_seeds=ZOOM_SEEDS))
            missed = _uncovered(diagram, zd)
            if missed:
                complete = False
                notes.append(f"{label} zoom: INCOMPLETE: {missed} points of the full-window curves inside the "
                             f"zoom lie on no zoom curve")
            _draw_curves(zax, zd, BAR, colour, label=label)
            for f in _located(zd, PointKind.HOPF_FOLD):
                zax.plot(f.speed * 3.6, f.value / BAR, "o", color=colour, ms=4, mfc="white")
            for s in _located(zd, PointKind.HOPF_HOPF):
                zax.plot(s.speed * 3.6, s.value / BAR, "s", color=colour, ms=4, mfc="white")
            complete &= zd.complete
            notes += _incomplete_notes(f"{label} zoom: ", zd)
    for name, zax, (plo, phi, vlo, vhi) in zip(("Z1", "Z2"), zooms, (Z1, Z2)):
        zax.set_xlim(vlo, vhi)
        zax.set_ylim(plo, phi)
        zax.set_title(f"({name})", fontsize=9)
        zax.set_xlabel("speed V [km/h]", fontsize=8)
        zax.set_ylabel("$p_i$ [bar]", fontsize=8)
        zax.tick_params(labelsize=8)
        zax.grid(alpha=0.3)
        ax.add_patch(plt.Rectangle((vlo, plo), vhi - vlo, phi - plo, fill=False, ls="--", lw=0.8, color="0.3"))
        ax.annotate(name, (vhi, phi), textcoords="offset points", xytext=(2, 2), fontsize=8)
    _speed_axis(ax)
    ax.set_ylim(*P17_BAR)
    ax.set_ylabel("inflation pressure $p_i$ [bar]")
    ax.legend(fontsize=8, loc="lower right", framealpha=0.9)
    ax.set_title("Fig. 17: Hopf curves with the tyre properties following pressure cumulatively\n"
                 "LF lateral force, HCL half-contact length, PT pneumatic trail, RL relaxation length, "
                 "VS vertical stiffness", fontsize=9)
    fig.tight_layout()
    return Drawing(fig, tuple(notes), complete)


# --- periodic-orbit figures (limit-cycle branches, simulations, cycle bifurcation curves) --------------------

FIG9_VMAX_KMH = 800.0   # HB4 of figure 9 lies at 720 km/h (t = 0.25 m) and 746 km/h (0.285 m): shown, not cut
TRAIL_FIG9 = (0.25, 0.285)


@dataclass(frozen=True)
class CycleKey:
    pressure_bar: float
    vmax_kmh: float
    params: tuple = ()          # ((name, value), ...): Table 1 entries changed from YANG2024
    effects: Effects = field(default_factory=Effects)
    vmin_kmh: float = 0.0


def _cycle_family(key: CycleKey) -> SpeedFamily:
    return SpeedFamily(ShimmyModel(effects=key.effects).with_params(**dict(key.params)))


def _store_cycles(store: DiagramStore, key: CycleKey) -> tuple[SpeedFamily, CycleDiagram]:
    """(family, cycle diagram) for ``key``, computed once per store (figures 9a, 10 and 11 share one)."""
    cache = store._cycles
    if key not in cache:
        family = _cycle_family(key)
        cache[key] = (family, cycle_diagram(family, key.pressure_bar * BAR, key.vmin_kmh * KMH,
                                            key.vmax_kmh * KMH))
    return cache[key]


def _peak(family: SpeedFamily, branch: CycleBranch, name: str):
    try:
        return branch_peak(family, branch, name)
    except ConvergenceError:
        return branch.peak(name)


def _paper(value) -> str:
    return "" if value is None else f" (paper {value:g})"


def _cycle_notes(prefix: str, family: SpeedFamily, diagram: CycleDiagram, paper_hopf=None, paper_modes=None,
                 paper_special=None, hopf_labels=None) -> list[str]:
    """Hopf speeds, per branch its peaks and frequency range, special points (S/T/PD by the paper's names)."""
    notes = []
    def ref(name):
        i = int(name[2:]) - 1 if name[2:].isdigit() else None
        return paper_hopf[i] if paper_hopf and i is not None and i < len(paper_hopf) else None
    hopf = ", ".join(f"{name} {h.speed_kmh:.2f}{_paper(ref(name))}"
                     for name, h in sorted(hopf_names(diagram, hopf_labels), key=lambda nh: nh[1].speed))
    notes.append(f"{prefix}Hopf points [km/h]: {hopf or 'none: straight running stable in the whole window'}")
    modes = list(paper_modes.items()) if paper_modes else []
    for i, b in enumerate(diagram.branches):
        ends = (f"{b.start.speed_kmh:.2f}" if b.start else "?") + " - " + \
            (f"{b.end.speed_kmh:.2f} km/h" if b.end else b.message.split(": ", 1)[-1])
        name, ref = modes[i] if i < len(modes) else (f"branch {i + 1}", {})
        if not b.points:
            notes.append(f"{prefix}{name} ({ends}): INCOMPLETE, no cycle computed: {b.message}")
            continue
        th, ps = _peak(family, b, "theta1"), _peak(family, b, "psi")
        f_lo, f_hi = b.frequency_range
        f_ref = ref.get("frequency_hz")
        notes.append(
            f"{prefix}{name} (from {ends}): peak max|theta1| {np.degrees(th.max_abs('theta1')):.3f} deg"
            f"{_paper(ref.get('theta1_deg'))} at {th.speed_kmh:.2f} km/h, peak max|psi| "
            f"{np.degrees(ps.max_abs('psi')):.3f} deg{_paper(ref.get('psi_deg'))} at {ps.speed_kmh:.2f} km/h, "
            f"frequency {f_lo:.2f}-{f_hi:.2f} Hz" + (f" (paper {f_ref[0]:g}-{f_ref[1]:g})" if f_ref else ""))
        if not b.complete:
            notes.append(f"{prefix}{name}: INCOMPLETE: {b.message}")
    for text, p in special_point_labels(diagram):
        status = "" if p.status is PointStatus.LOCATED else f" ({p.status.value})"
        ref = (paper_special or {}).get(text)
        notes.append(f"{prefix}{text} ({p.kind.value}): {p.speed * 3.6:.2f} km/h{_paper(ref)}, max|theta1| "
                     f"{np.degrees(p.data['amplitude'][0]):.3f} deg{status}")
    return notes


def hopf_names(diagram: CycleDiagram, names: tuple[str, ...] | None = None) -> list[tuple[str, object]]:
    """(name, Hopf point) as in the paper: branch k (by its lowest speed) is bounded by HB(2k+1) below and
    HB(2k+2) above; a branch that leaves the window at its low end starts at its upper Hopf point.  ``names``
    (in speed order) overrides this where the paper keeps the names of a neighbouring diagram (figure 9b)."""
    if names is not None and len(names) == len(diagram.hopf):
        return list(zip(names, sorted(diagram.hopf, key=lambda h: h.speed)))
    out, named = [], set()
    for k, b in enumerate(diagram.branches):
        ends = [h for h in (b.start, b.end) if h is not None]
        if len(ends) == 2:
            ends.sort(key=lambda h: h.speed)
            pairs = zip(ends, (2 * k + 1, 2 * k + 2))
        else:
            upper = bool(ends) and b.points and np.mean([p.speed for p in b.points]) < ends[0].speed
            pairs = zip(ends, (2 * k + 2 if upper else 2 * k + 1,))
        for h, n in pairs:
            out.append((f"HB{n}", h))
            named.add(id(h))
    out += [(f"HB? ({h.speed_kmh:.1f})", h) for h in diagram.hopf if id(h) not in named]
    return out


def _label_cycle_hopf(axes, diagram: CycleDiagram, names: tuple[str, ...] | None, width_kmh: float) -> None:
    """Hopf points on the axis with their names; a name too close to the previous one is raised."""
    names = sorted(hopf_names(diagram, names), key=lambda nh: nh[1].speed)
    for ax in axes:
        raised = False
        speeds = [h.speed_kmh for _, h in names]
        for i, (name, h) in enumerate(names):
            ax.plot(h.speed_kmh, 0.0, "o", color="C0", ms=5, zorder=5)
            raised = (not raised and i > 0 and speeds[i] - speeds[i - 1] < 0.09 * width_kmh)
            # A label whose right neighbour is close goes left of its point.
            left = not raised and i + 1 < len(names) and speeds[i + 1] - speeds[i] < 0.09 * width_kmh
            ax.annotate(name, (h.speed_kmh, 0.0), textcoords="offset points", xytext=(-2 if left else 2,
                        16 if raised else 5), ha="right" if left else "left", fontsize=8, color="C0")
        if not names and not diagram.branches:
            ax.text(0.5, 0.5, "no Hopf point, no limit cycle:\nstraight running stable at every speed",
                    transform=ax.transAxes, ha="center", va="center", fontsize=9, color="0.3")


def _cycle_panels(store: DiagramStore, panels, vmax_kmh: float, figure_title: str, paper_args=None):
    """One column of (max|theta1|, max|psi|) axes per panel (title, CycleKey); returns (figure, notes, complete)."""
    columns = len(panels)
    fig, axes = plt.subplots(2, columns, figsize=(5.6 * columns, 6.4), sharex="col", squeeze=False)
    notes, complete = [], True
    for j, (title, key) in enumerate(panels):
        family, diagram = _store_cycles(store, key)
        # The Hopf points are labelled here with the paper's names (HB1, HB2 bound the yaw mode, HB3, HB4 the
        # second one), not by speed order as draw_cycle_diagram does.
        draw_cycle_diagram(axes[:, j], dataclasses.replace(diagram, hopf=()), family)
        _label_cycle_hopf(axes[:, j], diagram, ((paper_args or [{}] * columns)[j]).get("hopf_labels"), vmax_kmh)
        axes[0, j].set_title(title, fontsize=10)
        for ax in axes[:, j]:
            ax.set_xlim(0.0, vmax_kmh)
            ax.grid(alpha=0.3)
        prefix = f"{title.split(' ')[0]} " if columns > 1 else ""
        notes += _cycle_notes(prefix, family, diagram, **((paper_args or [{}] * columns)[j]))
        complete &= diagram.complete
    fig.suptitle(figure_title + "\nsolid: stable, dashed: unstable (straight running on the axis, cycles above)",
                 fontsize=10)
    fig.tight_layout()
    return fig, notes, complete


@register(3, "cycles_nominal", cost=2)
def draw_cycles_nominal(store: DiagramStore) -> Drawing:
    key = CycleKey(P_I0_BAR, 120.0)
    ref = paper.NOMINAL_PEAK
    fig, notes, complete = _cycle_panels(
        store, [(f"{P_I0_BAR:g} bar ($p_{{i0}}$)", key)], 120.0,
        "Fig. 3: limit cycles at nominal pressure (section 3 model)",
        [dict(paper_hopf=paper.HOPF_SPEEDS_KMH[2.5],
              paper_modes={"yaw mode": {"theta1_deg": ref["theta1_deg"], "psi_deg": ref["psi_deg"]}})])
    notes.append(f"paper: both peaks at {ref['speed_kmh']:g} km/h; "
                 + paper.KNOWN_DIFFERENCES["cycles:2.5:peak_speed"])
    return Drawing(fig, tuple(notes), complete)


@register(4, "cycles_1p5_2p7bar", cost=3)
def draw_cycles_low_high(store: DiagramStore) -> Drawing:
    panels = [("(a) 1.5 bar (0.6 $p_{i0}$)", CycleKey(1.5, VMAX_KMH)),
              ("(b) 2.7 bar (1.08 $p_{i0}$)", CycleKey(2.7, VMAX_KMH))]
    fig, notes, complete = _cycle_panels(
        store, panels, VMAX_KMH, "Fig. 4: limit cycles at low and high pressure (section 3 model)",
        [dict(paper_hopf=paper.HOPF_SPEEDS_KMH[1.5], paper_modes={
            "yaw mode": paper.LOW_PRESSURE_MODES["yaw"], "tramp mode": paper.LOW_PRESSURE_MODES["tramp"]}),
         dict(paper_hopf=paper.HOPF_SPEEDS_KMH[2.7])])
    notes.append("(a) HB1: " + paper.KNOWN_DIFFERENCES["hopf:1.5:HB1"])
    return Drawing(fig, tuple(notes), complete)


def _trail_key(t0: float) -> CycleKey:
    return CycleKey(1.5, FIG9_VMAX_KMH, (("t0", t0),))


@register(9, "cycles_trail", cost=7)
def draw_cycles_trail(store: DiagramStore) -> Drawing:
    panels = [(f"({c}) t = {t0:g} m, 1.5 bar", _trail_key(t0)) for c, t0 in zip("ab", TRAIL_FIG9)]
    fig, notes, complete = _cycle_panels(
        store, panels, FIG9_VMAX_KMH, "Fig. 9: limit cycles at two pneumatic trails, 1.5 bar (section 3 model; "
        "the window reaches 800 km/h to show HB4)",
        [dict(paper_special=paper.FIG9A, paper_modes={"yaw mode": {}, "tramp mode": {}}),
         # HB1 has moved below 0.5 km/h, where cycles are not continued: the merged mode shows HB4 only.
         dict(paper_modes={"merged mode": {}}, hopf_labels=("HB4",))])
    return Drawing(fig, tuple(notes), complete)


@register(15, "cycles_low_vertical_stiffness", cost=3)
def draw_cycles_k5(store: DiagramStore) -> Drawing:
    k5 = paper.FIG15A["k5_0_Npm"]
    panels = [(f"({c}) {p:g} bar ({p / P_I0_BAR:.3g} $p_{{i0}}$)", CycleKey(p, VMAX_KMH, (("k5_0", k5),)))
              for c, p in zip("ab", (P_I0_BAR, 2.56))]
    fig, notes, complete = _cycle_panels(
        store, panels, VMAX_KMH, f"Fig. 15: limit cycles with vertical stiffness $k_5$ = {k5:.3g} N/m",
        [dict(paper_modes={"low-speed mode": {"psi_deg": paper.FIG15A["psi_low_mode_deg"]},
                           "high-speed mode": {}}), dict(paper_modes={"low-speed mode": {}, "high-speed mode": {}})])
    return Drawing(fig, tuple(notes), complete)


# Figure 10: the speed ramps of tests/test_simulation.py (1 km/h per s through the bistable window), each
# started from the default small disturbance theta1 = 0.01 rad where only one mode is stable.
RAMP_UP_KMH = (120.0, 200.0, 80.0, 85.0)      # from, to, ramp seconds, simulated seconds
RAMP_DOWN_KMH = (200.0, 120.0, 80.0, 80.0)


def _trajectory_column(axes, tr: Trajectory, history: ModeHistory, crossing: tuple[str, float], title: str) -> list:
    name, v_cross = crossing
    speed_kmh = tr.speed * 3.6
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
        top.annotate(f"{s.before.value} → {s.after.value}\n{s.speed * 3.6:.2f} km/h", (s.time, 0.97),
                     xycoords=("data", "axes fraction"), textcoords="offset points", xytext=(3, -24), fontsize=8,
                     color="C3", zorder=6, bbox=dict(boxstyle="round,pad=0.15", fc="white", ec="none", alpha=0.85))
        notes.append(f"{title[:3]} switch {s.before.value} -> {s.after.value} at t = {s.time:.2f} s, "
                     f"{s.speed * 3.6:.2f} km/h ({name} = {v_cross:.2f} km/h)")
    if not history.switches:
        notes.append(f"{title[:3]} no mode switch detected (initial mode {history.initial.value})")
    twin = top.twinx()
    twin.plot(tr.t, speed_kmh, color="C0", lw=1.0)
    twin.set_ylabel("speed V [km/h]", color="C0")
    twin.tick_params(axis="y", colors="C0")
    top.set_title(title, fontsize=10)
    axes[-1].set_xlabel("time [s]")
    if not tr.complete:
        notes.append(f"{title[:3]} INCOMPLETE simulation: {tr.message}")
    return notes


@register(10, "mode_change_time_histories", cost=18)
def draw_mode_changes(store: DiagramStore) -> Drawing:
    family, diagram = _store_cycles(store, _trail_key(0.25))
    labels = dict(special_point_labels(diagram))
    s1, t2 = labels["S1"].speed * 3.6, labels["T2"].speed * 3.6
    model = family.model
    fig, axes = plt.subplots(2, 2, figsize=(12.0, 6.0), sharex="col")
    notes, complete = [], True
    for j, ((v0, v1, ramp, duration), crossing, title) in enumerate((
            (RAMP_UP_KMH, ("S1", s1), "(a) speed increasing"), (RAMP_DOWN_KMH, ("T2", t2), "(b) speed decreasing"))):
        tr = simulate(model, 1.5 * BAR, SpeedSchedule.ramp(v0 * KMH, v1 * KMH, ramp), duration)
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
    family, diagram = _store_cycles(store, _trail_key(0.25))
    V = paper.FIG11_SPEED_KMH * KMH
    fig, ax = plt.subplots(figsize=(6.8, 5.4))
    notes, complete = [], True
    cycles = {}
    for branch, mode in zip(diagram.branches, ("yaw", "tramp")):
        stable = [p for p in branch.points if p.stable]
        try:
            cycles[mode] = cycle_at(family, min(stable, key=lambda p: abs(p.speed - V)), V)
        except (ValueError, ConvergenceError) as exc:
            notes.append(f"continuation cycle of the {mode} mode at 180 km/h not found: {exc}")
    for name, start, colour, offset in PHASE_STARTS:
        tr = simulate(family.model, 1.5 * BAR, SpeedSchedule.constant(V), PHASE_DURATION, initial_state(start))
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


# Figure 18: the window of the two-parameter cycle continuation (tests/test_cycles_curves.py).  Below 0.2 bar T1
# and T2 run on to 0.05 bar without meeting (tests/test_cycle_curve_ends.py, slow): the paper's HH2 is not there.
FIG18_EFFECTS = "hcl,pt"
FIG18_WINDOW = (0.2, 0.6, 100.0, 300.0)     # bar, bar, km/h, km/h
FIG18_VIEW_KMH = (130.0, 230.0)
FIG18_START_BAR = 0.25                      # pressure of the one-parameter branches named HB2, HB3 in the figure


@register(18, "cycle_bifurcation_curves_hcl_pt", cost=30)
def draw_cycle_curves(store: DiagramStore) -> Drawing:
    lo_bar, hi_bar, vmin_kmh, vmax_kmh = FIG18_WINDOW
    effects = Effects.parse(FIG18_EFFECTS)
    key = _pressure_key(effects, lo_bar, hi_bar, vmin_kmh, vmax_kmh, n_seeds=21)
    hopf, family = store.diagram(key), store.family(key)
    cycles = cycle_diagram(family, FIG18_START_BAR * BAR, vmin_kmh * KMH, vmax_kmh * KMH)
    fig, ax = plt.subplots(figsize=(7.2, 5.4))
    _shade_stable(ax, family, hopf, BAR)
    _draw_curves(ax, hopf, BAR, "k", label="Hopf curves")
    notes, complete = [], hopf.complete and cycles.complete
    paper_hh = paper.SECTION5[FIG18_EFFECTS]["hopf_hopf_bar"]
    for i, hh in enumerate(_located(hopf, PointKind.HOPF_HOPF)[::-1], 1):
        _mark(ax, hh, BAR, f"HH{i}", colour="tab:red", marker="s", offset=(6, 4))
        notes.append(_point_note(f"HH{i}", hh, "bar", BAR) + (f" (paper {paper_hh:g} bar)" if i == 1 else ""))
    for i, dh in enumerate(_located(hopf, PointKind.GENERALIZED_HOPF), 1):
        _mark(ax, dh, BAR, "DH", colour="tab:blue", marker="D", offset=(8, 2))
        notes.append(_point_note("DH (HB3 turns subcritical)", dh, "bar", BAR))
    # The curves are born at the codimension-two points (branch switching from HH1 and DH), not taken from the
    # one-parameter branches; names as in the paper: T1 the torus curve at higher speed on the window's edge.
    from reduced_model.torus_switching import curves_from_codimension_two

    born: list[tuple[str, str, CycleCurve]] = []
    for origin, point in [(f"HH{i}", p) for i, p in enumerate(_located(hopf, PointKind.HOPF_HOPF)[::-1], 1)] + \
            [("DH", p) for p in _located(hopf, PointKind.GENERALIZED_HOPF)]:
        try:
            found = curves_from_codimension_two(family, point, lo_bar * BAR, hi_bar * BAR, vmin_kmh * KMH,
                                                vmax_kmh * KMH)
        except ConvergenceError as exc:
            notes.append(f"curves from {origin}: INCOMPLETE: {exc}")
            complete = False
            continue
        found = sorted(found, key=lambda c: -c.speeds[int(np.argmin(c.values))])
        letter = "T" if point.kind is PointKind.HOPF_HOPF else "S"
        for c in found:
            born.append((f"{letter}{sum(t[0].startswith(letter) for t in born) + 1}", origin, c))
    for text, origin, curve in born:
        style, colour = CURVE_STYLES[curve.kind]
        ax.plot(curve.speeds * 3.6, curve.values / BAR, style, color=colour, lw=1.6,
                label=f"{'saddle-node (S)' if curve.kind is PointKind.CYCLE_FOLD else 'torus (T)'} curves"
                if text in ("S1", "T1") else None)
        k = int(np.argmin(np.abs(curve.values - 0.5 * (FIG18_START_BAR * BAR + curve.values.max()))))
        ax.annotate(text, (curve.speeds[k] * 3.6, curve.values[k] / BAR), textcoords="offset points",
                    xytext=(5, -3) if text == "T1" else (-18, -3), fontsize=9, color=colour)
        ends = [e for e in curve.ends if e is not None]
        for v, q in ends:
            ax.plot(v * 3.6, q / BAR, "*", color=colour, ms=9, zorder=6)
        located = {(p.speed, p.value): p for p in curve.end_points if p is not None}
        end_text = "; ".join(f"amplitude vanishes at {v * 3.6:.2f} km/h, {q / BAR:.4f} bar"
                             + (f" ({located[(v, q)].kind.value.replace('_', '-')} point located on its Hopf curve)"
                                if (v, q) in located else " (extrapolated)") for v, q in ends)
        for sp in curve.special_points:    # codimension-two points of cycles found along the curve
            ax.plot(sp.speed * 3.6, sp.value / BAR, "x", color=colour, ms=7, mew=1.6, zorder=6)
            ax.annotate(sp.kind.value.replace("resonance_", "R").replace("_", ":"), (sp.speed * 3.6, sp.value / BAR),
                        textcoords="offset points", xytext=(5, 2), fontsize=8, color=colour)
            notes.append(f"{text}: {sp.kind.value.replace('_', ' ')} at {sp.speed * 3.6:.2f} km/h, "
                         f"{sp.value / BAR:.4f} bar ({sp.status.value})")
        notes.append(f"{text} ({curve.kind.value}, born at {origin}): {end_text or 'no zero-amplitude end'}; "
                     f"{' | '.join(curve.messages)}")
        complete &= curve.complete
    ax.axhline(FIG18_START_BAR, color="0.5", lw=0.7, ls=":")
    # The paper's names: HB3 turns subcritical at DH (its cycles are unstable below it), HB2 stays supercritical.
    for h in cycles.hopf:
        name = "HB3" if h.first_lyapunov > 0 else "HB2"
        ax.annotate(name, (h.speed_kmh, FIG18_START_BAR), textcoords="offset points", xytext=(4, 3), fontsize=8)
        notes.append(f"{name} at {FIG18_START_BAR:g} bar: {h.speed_kmh:.2f} km/h, first Lyapunov coefficient "
                     f"{'positive (subcritical)' if h.first_lyapunov > 0 else 'negative (supercritical)'}")
    _speed_axis(ax, FIG18_VIEW_KMH[1], FIG18_VIEW_KMH[0])
    ax.set_ylim(lo_bar, hi_bar)
    ax.set_ylabel("inflation pressure $p_i$ [bar]")
    ax.legend(fontsize=8, loc="upper right", framealpha=0.9)
    ax.set_title("Fig. 18: enlarged (V, $p_i$) diagram, effects HCL + PT; shaded: straight running stable\n"
                 f"cycle curves switched onto at HH1 and DH (stars, located); x: codimension-two points of cycles",
                 fontsize=9)
    notes.append(f"window {lo_bar:g}-{hi_bar:g} bar: T1 and T2 leave it at its lower edge; continued down to 0.05 bar "
                 "they neither cross nor end at a Hopf-Hopf point (they pass the two Hopf-Hopf points of 0.1007 bar "
                 "with max|theta1| 2.6 and 2.1 deg): no HH2 where the paper draws one (README, differences)")
    notes += _incomplete_notes("", hopf)
    return Drawing(fig, tuple(notes), complete)
