"""Which cases ``shimmy verify`` runs: the paper's for the paper's truck, a plan of its own for any other axle.

Both models are scanned over the axle's pressure window (``[operating] pressure_range_bar``) by
:mod:`comparisons.verify.scan`: the reduced model (section 3, the base model of every other check) and the MBS with
the full geometry, each with its unstable speed windows on a grid of pressures, its Hopf curves and its own
shimmy-free boundary.  For an axle file the cases are:

1. for each model and each mode, the pressure where that model's window of the mode is widest (closed windows
   first);
2. for each model with a shimmy-free boundary inside the window, 0.1 bar below it (the last mode's narrow window)
   and 0.1 bar above it (no shimmy in that model);
3. where the scan finds a pressure at which only one model shimmies and no case so far shows that, the grid
   pressure where that model's windows are widest;
4. the asymmetric case when left and right pressures are given;
5. bistable windows (the reduced model): at grid pressures where two unstable pairs overlap in speed or a Hopf point
   is subcritical (the only ways for two stable cycles to coexist near straight running), the cycle branches are
   continued and speed intervals where two stable cycles of different branches or branch parts coexist are
   collected; the widest is run through by speed ramps and the two-start experiment;
6. when neither model shimmies anywhere in the window, its ends and middle (straight running is still compared).

Every case carries both models' unstable windows at its pressures (what the verdict reports) and a reason that
says why it was chosen and which model shimmies there.  The paper's truck without an axle file keeps the paper's
cases (1.5, 2.5, 2.7 bar: both models shimmy, only the reduced model does, neither does), with rule 3 on top.
"""

from __future__ import annotations

import dataclasses
import enum
import math
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from axles.axle import AxleData
from axles.units import BAR, from_kmh, kmh
from comparisons.verify.scan import (
    TRAMP_SHARE,
    VMAX,
    BoundaryKind,
    Model,
    ModelScan,
    Window,
    scan_model,
    tramp_share,
    unstable_windows,
)
from reduced_model.family import MIN_SPEED, SpeedFamily
from axles.pressures import TyrePressures
from comparisons.verify.scan import scan_family

__all__ = ["TRAMP_SHARE", "VMAX", "Window", "tramp_share", "unstable_windows", "CaseKind", "Case", "BistableCase",
           "Plan", "paper_plan", "axle_plan", "bistable_windows"]

EDGE_BAR = 0.1        # how far beside a shimmy-free boundary the two boundary cases lie
MERGE_BAR = 0.01      # cases closer than this in both pressures are one case
BOTH = (Model.REDUCED, Model.FULL)


class CaseKind(enum.Enum):
    PAPER = "paper"                       # a case the paper prints numbers for
    MODE = "mode"                         # a shimmy mode at its widest
    BELOW_BOUNDARY = "below boundary"     # just below a shimmy-free boundary
    SHIMMY_FREE = "shimmy-free"           # just above it: no Hopf point in that model
    ONE_MODEL = "one model shimmies"      # only one of the two models shimmies here
    ASYMMETRIC = "asymmetric"             # left and right pressures as asked
    BISTABLE = "bistable"                 # where two stable cycles coexist (the jumps are run there)
    STABLE = "no shimmy"                  # neither model shimmies anywhere: straight running is still compared


@dataclass(frozen=True)
class Case:
    pressure_right_bar: float
    pressure_left_bar: float
    kind: CaseKind
    reason: str
    chosen_by: Model | None = None        # the model whose scan chose the case (None: the paper, the user)
    windows: tuple[tuple[Model, tuple[Window, ...]], ...] = ()   # each model's unstable windows here

    @property
    def pressures(self) -> TyrePressures:
        return TyrePressures(self.pressure_right_bar * BAR, self.pressure_left_bar * BAR)

    @property
    def symmetric(self) -> bool:
        return self.pressure_right_bar == self.pressure_left_bar

    @property
    def label(self) -> str:
        if self.symmetric:
            return f"{self.pressure_right_bar:g} bar"
        return f"R {self.pressure_right_bar:g} / L {self.pressure_left_bar:g} bar"

    def windows_of(self, model: Model) -> tuple[Window, ...] | None:
        """That model's unstable windows here, None when not computed."""
        return next((w for m, w in self.windows if m is model), None)

    def shimmies(self, model: Model) -> bool:
        return bool(self.windows_of(model))

    def to_json(self) -> dict:
        return {"pressure_left_bar": self.pressure_left_bar, "pressure_right_bar": self.pressure_right_bar,
                "kind": self.kind.value, "reason": self.reason,
                "chosen_by": None if self.chosen_by is None else self.chosen_by.value,
                "windows": {m.value: [x.to_json() for x in w] for m, w in self.windows}}


@dataclass(frozen=True)
class BistableCase:
    """A speed window [low, high] (km/h) where two stable cycles coexist, at one pressure of one axle."""

    axle: AxleData
    pressure_bar: float
    low_kmh: float
    high_kmh: float
    reason: str
    value_diagram: object = field(default=None, compare=False, repr=False)   # the CycleDiagram it came from

    def to_json(self) -> dict:
        return {"pressure_left_bar": self.pressure_bar, "pressure_right_bar": self.pressure_bar,
                "kind": "bistable", "window_kmh": [self.low_kmh, self.high_kmh], "reason": self.reason,
                "overrides": {k: v for k, v in self.axle.overrides}}


@dataclass(frozen=True)
class Plan:
    cases: tuple[Case, ...]
    bistable: tuple[BistableCase, ...]
    notes: tuple[str, ...] = ()
    boundary_bar: float | None = None     # the reduced model's shimmy-free boundary, if in the window
    scans: tuple[ModelScan, ...] = ()     # what each model says over the pressure window

    def scan_of(self, model: Model) -> ModelScan | None:
        return next((s for s in self.scans if s.model is model), None)

    def to_json(self) -> list[dict]:
        return [c.to_json() for c in self.cases] + [b.to_json() for b in self.bistable]


# --- what the cases share -----------------------------------------------------------------------------------

def case_windows(axle: AxleData, case: Case, models=BOTH, vmax: float = VMAX) -> Case:
    """``case`` with each model's unstable windows at its pressures and, in its reason, which model shimmies."""
    found = []
    for model in models:
        family = scan_family(axle, model, pressures=case.pressures)
        windows, _ = unstable_windows(family, family.nominal, vmax, lyapunov=False)
        found.append((model, tuple(windows)))
    case = dataclasses.replace(case, windows=tuple(found))
    return dataclasses.replace(case, reason=f"{case.reason}; {shimmy_text(case, models)}")


def shimmy_text(case: Case, models=BOTH) -> str:
    who = [m for m in models if case.shimmies(m)]
    if len(models) == 1:
        return f"{models[0].label} shimmies here" if who else f"{models[0].label} does not shimmy here"
    if len(who) == 2:
        return "both models shimmy here"
    if who:
        return f"only {who[0].label} shimmies here"
    return "neither model shimmies here"


def _add(cases: list[Case], case: Case) -> None:
    """Add a case, or merge its reason into a case at the same pressures to :data:`MERGE_BAR` (the first one keeps
    its pressures and kind)."""
    same = next((c for c in cases if abs(c.pressure_right_bar - case.pressure_right_bar) < MERGE_BAR and
                 abs(c.pressure_left_bar - case.pressure_left_bar) < MERGE_BAR), None)
    if same is None:
        cases.append(case)
    else:
        cases[cases.index(same)] = dataclasses.replace(same, reason=same.reason + "; " + case.reason)


def scans_of(axle: AxleData, quick: bool, models=BOTH, vmax: float = VMAX, progress=None) -> tuple[ModelScan, ...]:
    """Both models over the axle's pressure window: 7 grid pressures with ``quick``, 13 without; the full
    geometry's Hopf curves only without ``quick`` (its boundary then comes from the growth rate's root)."""
    lo, hi = axle.pressure_range_bar
    grid = np.linspace(lo, hi, 7 if quick else 13)
    return tuple(scan_model(axle, m, grid, vmax, curves=m is Model.REDUCED or not quick,
                            n_seeds=5 if quick or m is Model.FULL else 9, progress=progress) for m in models)


def one_model_cases(axle: AxleData, scans: tuple[ModelScan, ...], cases: list[Case], vmax: float = VMAX) -> list[Case]:
    """Rule 3: for each model, the grid pressure where only it shimmies (its windows widest there), unless a case
    already shows that."""
    if len(scans) < 2:
        return []
    added = []
    by_model = {s.model: s for s in scans}
    for model, other in ((Model.FULL, Model.REDUCED), (Model.REDUCED, Model.FULL)):
        if any(c.shimmies(model) and not c.shimmies(other) for c in cases + added):
            continue
        only = [(sum(w.high - w.low for w in g.windows), g) for g, h in zip(by_model[model].grid, by_model[other].grid)
                if g.windows and not h.windows]
        if not only:
            continue
        width, g = max(only, key=lambda x: x[0])
        text = (f"only {model.label} shimmies at this grid pressure ({', '.join(w.text() for w in g.windows)}); "
                f"{other.label} runs straight")
        added.append(case_windows(axle, Case(g.pressure_bar, g.pressure_bar, CaseKind.ONE_MODEL, text, model),
                                  vmax=vmax))
    return added


# --- the paper's plan ---------------------------------------------------------------------------------------

def paper_plan(axle: AxleData, asymmetric: tuple[float, float] | None = None, quick: bool = True, models=BOTH,
               progress: Callable[[str], None] | None = None) -> Plan:
    """The cases the paper prints numbers for: section 3 at 1.5, 2.5 and 2.7 bar, figures 9a-11 at t0 = 0.25 m;
    both models scanned over the window for the verdict, with rule 3 of the module docstring on top."""
    cases = [Case(1.5, 1.5, CaseKind.PAPER, "figure 4a: both modes (HB1-HB4 printed)"),
             Case(2.5, 2.5, CaseKind.PAPER, "figure 3: nominal pressure, yaw mode only (HB1, HB2 printed)"),
             Case(2.7, 2.7, CaseKind.PAPER, "figure 4b: above the shimmy-free boundary F1, no Hopf point")]
    if asymmetric is not None:
        cases.append(_asymmetric_case(*asymmetric))
    t0_axle = axle.with_overrides({"t0": 0.25})
    bistable = (BistableCase(t0_axle, 1.5, math.nan, math.nan,
                             "figures 9a, 10 and 11: t0 = 0.25 m at 1.5 bar, stable yaw and tramp cycles coexist "
                             "between T2 and S1"),)
    scans = scans_of(axle, quick, models, progress=progress)
    cases = [case_windows(axle, c, models) for c in cases]
    cases += one_model_cases(axle, scans, cases)
    reduced = next((s for s in scans if s.model is Model.REDUCED), None)
    boundary = reduced.boundary.pressure_bar if reduced is not None else None
    return Plan(tuple(cases), bistable, ("the paper's truck: the paper's own cases",), boundary, scans)


def _asymmetric_case(right: float, left: float) -> Case:
    return Case(right, left, CaseKind.ASYMMETRIC, f"asked for: right tyre {right:g} bar, left tyre {left:g} bar")


# --- a plan for any axle -------------------------------------------------------------------------------------

def _overlapping_pairs(family: SpeedFamily, q: float, windows: list[Window]) -> bool:
    """Two eigenvalue pairs unstable at one speed somewhere in the windows (modes overlap: tori can appear)."""
    for w in windows:
        for V in np.linspace(w.low, w.high, 9)[1:-1]:
            values = np.linalg.eigvals(family.linear_matrix(V, q))
            if np.sum((values.real > 0.0) & (values.imag > 0.0)) >= 2:
                return True
    return False


def bistable_windows(diagram) -> list[tuple[float, float]]:
    """Speed intervals (m/s) where two stable cycles coexist (:func:`comparisons.studies.kick.bistable_windows`, straight
    running not counted)."""
    from comparisons.studies.kick import bistable_windows as coexisting
    return coexisting(diagram, min_width=from_kmh(0.5))


def _mode_cases(scan: ModelScan, cases: list[Case], notes: list[str]) -> None:
    """Rule 1: for each mode, the pressure where this model's window of it is widest (closed windows first)."""
    lo, hi = scan.window_bar
    for mode in ("yaw", "tramp"):
        best = None
        for g in scan.grid:
            for w in g.windows:
                key = (w.closed, w.high - w.low)
                if w.mode == mode and (best is None or key > best[0]):
                    best = (key, g.pressure_bar, w)
        if best is None:
            notes.append(f"{scan.model.label}: no {mode} mode anywhere in {lo:g}-{hi:g} bar")
            continue
        _, p, w = best
        text = (f"{mode} mode of {scan.model.label} widest here: unstable {kmh(w.low):.1f}-{kmh(w.high):.1f} km/h "
                f"at {w.frequency_hz:.1f} Hz" + ("" if w.closed else " (reaches the edge of the speed window)"))
        _add(cases, Case(p, p, CaseKind.MODE, text, scan.model))


def _boundary_cases(scan: ModelScan, cases: list[Case], notes: list[str]) -> None:
    """Rule 2: 0.1 bar below and above this model's shimmy-free boundary."""
    lo, hi = scan.window_bar
    b = scan.boundary
    name = scan.model.label
    if b.kind is BoundaryKind.SHIMMY_FREE_ABOVE:
        below, above = round(max(lo, b.pressure_bar - EDGE_BAR), 4), round(min(hi, b.pressure_bar + EDGE_BAR), 4)
        where = (f"fold of the Hopf curves at {b.speed_kmh:.1f} km/h" if b.speed_kmh is not None
                 else b.method.value)
        _add(cases, Case(below, below, CaseKind.BELOW_BOUNDARY,
                         f"{EDGE_BAR:g} bar below the shimmy-free boundary of {name} at {b.pressure_bar:.4f} bar "
                         f"({where}): its last mode's narrow window", scan.model))
        _add(cases, Case(above, above, CaseKind.SHIMMY_FREE,
                         f"{EDGE_BAR:g} bar above the shimmy-free boundary of {name}: no Hopf point in it",
                         scan.model))
    elif b.kind is BoundaryKind.SHIMMY_AT_TOP:
        notes.append(f"{name} shimmies at the top of the pressure window ({hi:g} bar): no shimmy-free boundary "
                     f"inside it")
    else:
        notes.append(f"{name}: no shimmy anywhere in {lo:g}-{hi:g} bar")
    for p, v in scan.folds:
        if b.method is None or b.speed_kmh is None or (p, v) != (b.pressure_bar, b.speed_kmh):
            notes.append(f"{name}: a mode is born or vanishes at {p:.4f} bar, {v:.1f} km/h (fold of the Hopf "
                         f"curves)")


def axle_plan(axle: AxleData, quick: bool, asymmetric: tuple[float, float] | None = None,
              vmax: float = VMAX, progress=None, models=BOTH) -> Plan:
    """The cases to verify for any axle (see the module docstring for the rules)."""
    from bifurcation.cycles.branches import cycle_diagram

    lo, hi = axle.pressure_range_bar
    scans = scans_of(axle, quick, models, vmax, progress)
    reduced = next(s for s in scans if s.model is Model.REDUCED)
    notes: list[str] = []
    cases: list[Case] = []
    for scan in scans:
        _mode_cases(scan, cases, notes)
    for scan in scans:
        _boundary_cases(scan, cases, notes)
    if asymmetric is not None:
        cases.append(_asymmetric_case(*asymmetric))
    if not any(s.shimmies_somewhere() for s in scans):
        for p, where in ((lo, "low end"), (0.5 * (lo + hi), "middle"), (hi, "high end")):
            p = round(p, 4)
            _add(cases, Case(p, p, CaseKind.STABLE, f"no shimmy anywhere in {lo:g}-{hi:g} bar in either model: "
                                                   f"straight running compared at the window's {where}"))
    if progress is not None:
        progress("plan: both models' windows at the planned cases")
    cases = [case_windows(axle, c, models, vmax) for c in cases]
    cases += one_model_cases(axle, scans, cases, vmax)

    # Bistable windows where cycles can coexist (the reduced model: the jumps compare it with the MBS).
    # Subcritical points first (cycle folds bound a bistable window), then overlapping modes (tori).
    family = scan_family(axle, Model.REDUCED)
    scored = []
    for g in reduced.grid:
        if not g.windows:
            continue
        sub = sum(h.first_lyapunov > 0.0 for h in g.points)
        if sub or _overlapping_pairs(family, g.pressure_bar * BAR, list(g.windows)):
            scored.append((-sub, abs(g.pressure_bar - 0.5 * (lo + hi)), g.pressure_bar))
    limit = 2 if quick else 4
    candidates = [p for _, _, p in sorted(scored)[:limit]]
    best = None
    for p in candidates:
        if progress is not None:
            progress(f"plan: cycle branches at {p:.3g} bar (bistability)")
        cd = cycle_diagram(family, p * BAR, MIN_SPEED, vmax)
        for a, b in bistable_windows(cd):
            if best is None or b - a > best[2] - best[1]:
                best = (p, a, b, cd)
    bistable = ()
    if best is not None:
        p, a, b, cd = best
        reason = (f"two stable cycles coexist at {kmh(a):.1f}-{kmh(b):.1f} km/h (widest such window found at the "
                  f"pressures where modes overlap or a Hopf point is subcritical)")
        bistable = (BistableCase(axle, p, kmh(a), kmh(b), reason, cd),)
        if not any(c.pressure_right_bar == p == c.pressure_left_bar for c in cases):
            cases.append(case_windows(axle, Case(p, p, CaseKind.BISTABLE, reason, Model.REDUCED), models, vmax))
    elif candidates:
        notes.append("no bistable window at the pressures where modes overlap or a Hopf point is subcritical")
    else:
        notes.append("no pressure with overlapping modes or a subcritical Hopf point: no bistable window near "
                     "straight running")
    return Plan(tuple(cases), bistable, tuple(notes), reduced.boundary.pressure_bar, scans)
