"""The registry of the paper's figures: figure number -> drawing recipe, the store of computed diagrams that
recipes share, and making figures (in worker processes when asked)."""

from __future__ import annotations

import os
import time
from dataclasses import dataclass, field
from typing import Callable

from axles.units import BAR, KMH
from comparisons.figures.plots import save_figure
from comparisons.files import interrupts_blocked, worker_signals
from bifurcation.cycles.branches import cycle_diagram
from bifurcation.cycles.problem import CycleDiagram
from bifurcation.equilibria.hopf_curves import HopfDiagram, hopf_diagram
from reduced_model.family import SpeedFamily
from mbs_shimmy.fidelity import Fidelity
from reduced_model.model import Effects, ShimmyModel
from axles.parameters import YANG2024
from axles.pressures import TyrePressures
from comparisons.api import family_of

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
# The figures recomputed for the MBS beside the reduced model (``shimmy figures --model mbs``): their recipes
# take (store, fidelity); the figures without one say why in UNAVAILABLE_BESIDE.
BESIDE: dict[int, FigureEntry] = {}
UNAVAILABLE_BESIDE: dict[int, str] = {}


def register(number: int, name: str, cost: float = 1.0, beside: bool = False):
    """Decorator: make ``draw(store) -> Drawing`` the recipe of the paper's figure ``number``; with ``beside``,
    ``draw(store, fidelity) -> Drawing`` its recipe for the MBS at ``fidelity`` beside the reduced model."""
    def wrap(draw: Callable[..., Drawing]):
        (BESIDE if beside else REGISTRY)[number] = FigureEntry(number, name, PAPER_TITLES[number], draw, cost)
        return draw
    return wrap


def available_figures(fidelity: Fidelity | None = None) -> tuple[int, ...]:
    """The figures that can be made for the reduced model, or with ``fidelity`` for the MBS beside it."""
    return tuple(sorted(n for n in PAPER_TITLES if unavailable_reason(n, fidelity) is None))


def unavailable_reason(number: int, fidelity: Fidelity | None = None) -> str | None:
    """Why figure ``number`` cannot be made (for the reduced model, or with ``fidelity`` for the MBS beside it),
    or None if it can; unknown numbers raise KeyError."""
    if number not in PAPER_TITLES:
        raise KeyError(f"the paper has no figure {number} (it has figures 1-{max(PAPER_TITLES)})")
    registry, unavailable = (REGISTRY, UNAVAILABLE) if fidelity is None else (BESIDE, UNAVAILABLE_BESIDE)
    if number in UNAVAILABLE or number in unavailable:
        return UNAVAILABLE.get(number) or unavailable[number]
    if number not in registry:
        return "no recipe registered" if fidelity is None else (
            "drawn for the reduced model only; for the MBS beside it: figures "
            + ", ".join(str(n) for n in sorted(BESIDE) if n not in UNAVAILABLE_BESIDE))
    return None


def beside_file_name(entry: FigureEntry, fidelity: Fidelity) -> str:
    """``fig05_pressure_hopf_curves_mbs_full.png``: the figure's name and the MBS fidelity it shows."""
    label = fidelity.label.replace(",", "+")
    return entry.file_name.replace(".png", f"_mbs_{label}.png")


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
    fidelity: Fidelity | None = None    # None: the reduced model; else the MBS at this fidelity
    branch_budget_s: float | None = None    # wall clock per branch (comparisons.studies.budget.BranchBudget)


@dataclass
class DiagramStore:
    """Hopf diagrams by :class:`DiagramKey` and cycle diagrams by :class:`CycleKey`, each computed once per
    store."""

    _diagrams: dict = field(default_factory=dict)
    _families: dict = field(default_factory=dict)
    _cycles: dict = field(default_factory=dict)      # CycleKey -> (family, CycleDiagram)

    def family(self, key: DiagramKey) -> SpeedFamily:
        fkey = (key.effects, key.param, key.pressure_bar, key.fidelity)
        if fkey not in self._families:
            self._families[fkey] = model_family(key.effects, (), key.fidelity,
                                                TyrePressures.uniform(key.pressure_bar * BAR), key.param)
        return self._families[fkey]

    def diagram(self, key: DiagramKey) -> HopfDiagram:
        if key not in self._diagrams:
            self._diagrams[key] = hopf_diagram(self.family(key), key.lo, key.hi, key.vmin_kmh * KMH,
                                               key.vmax_kmh * KMH, n_seeds=key.n_seeds)
        return self._diagrams[key]


def model_family(effects: Effects, params: tuple, fidelity: Fidelity | None, pressures: TyrePressures,
                 param: str = "pressure"):
    """The family of the reduced model (``fidelity`` None) or of the MBS at ``fidelity``, with the paper's axle
    changed by ``params`` ((Table 1 name, SI value), ...), through :func:`comparisons.api.family_of`."""
    if fidelity is None:
        return family_of(ShimmyModel(effects=effects).with_params(**dict(params)), pressures, param)
    from comparisons.api import Axle
    axle = Axle(Axle.paper().data.with_values(dict(params)))
    return axle.mbs(fidelity, effects=effects).problem(pressures, param)


def make_figure(number: int, out_dir: str, store: DiagramStore | None = None,
                fidelity: Fidelity | None = None) -> FigureResult:
    """Draw figure ``number`` into ``out_dir`` (atomic write); with ``fidelity``, the MBS at that fidelity beside
    the reduced model (:data:`BESIDE`); raises :class:`FigureUnavailable`."""
    reason = unavailable_reason(number, fidelity)
    if reason is not None:
        raise FigureUnavailable(f"figure {number} ({PAPER_TITLES[number]}) cannot be made: {reason}")
    entry = REGISTRY[number] if fidelity is None else BESIDE[number]
    store = store if store is not None else DiagramStore()
    start = time.perf_counter()
    drawing = entry.draw(store) if fidelity is None else entry.draw(store, fidelity)
    path = os.path.join(out_dir, entry.file_name if fidelity is None else beside_file_name(entry, fidelity))
    save_figure(drawing.figure, path)
    return FigureResult(number=number, name=entry.name, path=path, seconds=time.perf_counter() - start,
                        complete=drawing.complete, notes=drawing.notes)


def make_figures(numbers, out_dir: str, jobs: int = 1, on_done: Callable[[FigureResult], None] | None = None,
                 fidelity: Fidelity | None = None) -> list[FigureResult]:
    """Make the listed (available) figures into ``out_dir``, with ``jobs`` worker processes; results by number;
    with ``fidelity``, the MBS at that fidelity beside the reduced model.

    Workers are spawned (not forked: the parent may run a progress-bar thread) and each keeps its own
    :class:`DiagramStore`, so figures sharing a diagram share it only when they land on the same worker.
    """
    numbers = sorted(set(numbers))
    for n in numbers:
        reason = unavailable_reason(n, fidelity)
        if reason is not None:
            raise FigureUnavailable(f"figure {n} ({PAPER_TITLES[n]}) cannot be made: {reason}")
    results = []
    if jobs <= 1 or len(numbers) <= 1:
        store = DiagramStore()
        for n in numbers:
            results.append(make_figure(n, out_dir, store, fidelity))
            if on_done is not None:
                on_done(results[-1])
        return sorted(results, key=lambda r: r.number)
    import concurrent.futures
    import multiprocessing
    ordered = sorted(numbers, key=lambda n: -(REGISTRY if fidelity is None else BESIDE)[n].cost)
    with concurrent.futures.ProcessPoolExecutor(max_workers=min(jobs, len(numbers)),
                                                mp_context=multiprocessing.get_context("spawn"),
                                                initializer=worker_signals) as pool:
        with interrupts_blocked():
            futures = [pool.submit(_make_in_worker, n, out_dir, fidelity) for n in ordered]
        for future in concurrent.futures.as_completed(futures):
            results.append(future.result())
            if on_done is not None:
                on_done(results[-1])
    return sorted(results, key=lambda r: r.number)


_WORKER_STORE: DiagramStore | None = None


def _make_in_worker(number: int, out_dir: str, fidelity: Fidelity | None = None) -> FigureResult:
    global _WORKER_STORE
    if _WORKER_STORE is None:
        _WORKER_STORE = DiagramStore()
    return make_figure(number, out_dir, _WORKER_STORE, fidelity)


FIG9_VMAX_KMH = 800.0   # HB4 of figure 9 lies at 720 km/h (t = 0.25 m) and 746 km/h (0.285 m): shown, not cut
TRAIL_FIG9 = (0.25, 0.285)


@dataclass(frozen=True)
class CycleKey:
    pressure_bar: float
    vmax_kmh: float
    params: tuple = ()          # ((name, value), ...): Table 1 entries changed from YANG2024
    effects: Effects = field(default_factory=Effects)
    vmin_kmh: float = 0.0
    fidelity: Fidelity | None = None    # None: the reduced model; else the MBS at this fidelity
    branch_budget_s: float | None = None    # wall clock per branch (comparisons.studies.budget.BranchBudget)


def _cycle_family(key: CycleKey) -> SpeedFamily:
    return model_family(key.effects, key.params, key.fidelity, TyrePressures.uniform(2.5e5))


def store_cycles(store: DiagramStore, key: CycleKey) -> tuple[SpeedFamily, CycleDiagram]:
    """(family, cycle diagram) for ``key``, computed once per store (figures 9a, 10 and 11 share one)."""
    cache = store._cycles
    if key not in cache:
        family = _cycle_family(key)
        budget = {}
        if key.branch_budget_s is not None:
            from comparisons.studies.budget import BranchBudget
            hook = BranchBudget(key.branch_budget_s, family.state_names)
            budget = {"accept_hook": hook, "progress": hook.next_branch}
        cache[key] = (family, cycle_diagram(family, key.pressure_bar * BAR, key.vmin_kmh * KMH,
                                            key.vmax_kmh * KMH, **budget))
    return cache[key]
