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

import os
import time
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from reduced_model import tyre
from reduced_model.family import SpeedFamily
from reduced_model.hopf import hopf_points
from reduced_model.hopf_curves import HopfCurve, HopfDiagram, hopf_diagram
from reduced_model.model import Effects, ShimmyModel
from reduced_model.parameters import YANG2024
from reduced_model.special_points import PointKind, PointStatus

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

_NEEDS_CYCLES = "periodic-orbit continuation of the reduced model (issue 3), not in this project yet"
_NEEDS_SIMULATION = "time simulation with mode detection of the reduced model (issue 3), not in this project yet"
UNAVAILABLE: dict[int, str] = {
    1: "it is a drawing of the model, not a computed result (the 3D scene of a recording shows the geometry)",
    3: _NEEDS_CYCLES,
    4: _NEEDS_CYCLES,
    9: _NEEDS_CYCLES,
    10: _NEEDS_SIMULATION,
    11: _NEEDS_SIMULATION,
    15: _NEEDS_CYCLES,
    18: "torus and saddle-node curves of periodic orbits (issue 3), not in this project yet",
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
    """Hopf diagrams by :class:`DiagramKey`, each computed once per store."""

    _diagrams: dict = field(default_factory=dict)
    _families: dict = field(default_factory=dict)

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
