"""Which cases ``shimmy verify`` runs: the paper's for the paper's truck, a plan of its own for any other axle.

For an axle file the plan is made from the reduced model (section 3, the base model of every other check):

1. the pressure window of the axle (``[operating] pressure_range_bar``) is scanned for Hopf points of straight
   running on a grid of pressures; each unstable speed window is given a mode by its critical eigenvector (the
   tramp share |psi| / max(|theta1|, |theta2|) against :data:`TRAMP_SHARE`),
2. the Hopf curves in (V, p) are continued over the window (:func:`reduced_model.bifurcation.equilibria.hopf_curves.hopf_diagram`); their
   folds are where a mode is born or vanishes, the highest one is the shimmy-free boundary,
3. cases: for each mode, the pressure where its speed window is widest (all its Hopf points inside the speed
   window); just below the shimmy-free boundary (the last mode's narrow window); just above it (no shimmy: both
   models must find none); the asymmetric case when left and right pressures are given,
4. bistable windows: at grid pressures where two unstable pairs overlap in speed or a Hopf point is subcritical (the
   only ways for two stable cycles to coexist near straight running), the cycle branches are continued and speed
   intervals where two stable cycles of different branches or branch parts coexist are collected; the widest is
   run through by speed ramps and the two-start experiment.
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass, field

import numpy as np

from comparisons.axles.axle import Axle
from comparisons.axles.units import BAR, from_kmh, kmh
from reduced_model.bifurcation.equilibria.hopf import hopf_points
from reduced_model.family import MIN_SPEED, SpeedFamily
from reduced_model.model import STATE_NAMES, ShimmyModel
from reduced_model.modes import ModeClassifier

VMAX = from_kmh(400)
# |psi| / max|theta| of the critical eigenvector above which a window is the tramp mode: the split the simulation's
# mode classifier uses for cycles, so that a planned mode and a simulated one carry the same name.
TRAMP_SHARE = ModeClassifier().ratio_split
EDGE_BAR = 0.1        # how far beside the shimmy-free boundary the two boundary cases lie
_I_TH1, _I_TH2, _I_PSI = (STATE_NAMES.index(n) for n in ("theta1", "theta2", "psi"))


class CaseKind(enum.Enum):
    PAPER = "paper"                       # a case the paper prints numbers for
    MODE = "mode"                         # a shimmy mode at its widest
    BELOW_BOUNDARY = "below boundary"     # just below the shimmy-free boundary
    SHIMMY_FREE = "shimmy-free"           # just above it: no Hopf point in either model
    ASYMMETRIC = "asymmetric"             # left and right pressures as asked
    BISTABLE = "bistable"                 # where two stable cycles coexist (the jumps are run there)


@dataclass(frozen=True)
class Case:
    pressure_right_bar: float
    pressure_left_bar: float
    kind: CaseKind
    reason: str

    @property
    def pressure(self) -> float | tuple[float, float]:
        """Pa, one value when both tyres are alike."""
        r, l = self.pressure_right_bar * BAR, self.pressure_left_bar * BAR
        return r if r == l else (r, l)

    @property
    def label(self) -> str:
        if self.pressure_right_bar == self.pressure_left_bar:
            return f"{self.pressure_right_bar:g} bar"
        return f"R {self.pressure_right_bar:g} / L {self.pressure_left_bar:g} bar"

    def to_json(self) -> dict:
        return {"pressure_left_bar": self.pressure_left_bar, "pressure_right_bar": self.pressure_right_bar,
                "kind": self.kind.value, "reason": self.reason}


@dataclass(frozen=True)
class BistableCase:
    """A speed window [low, high] (km/h) where two stable cycles coexist, at one pressure of one axle."""

    axle: Axle
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
    boundary_bar: float | None = None     # shimmy-free boundary (highest fold of the Hopf curves), if in the window

    def to_json(self) -> list[dict]:
        return [c.to_json() for c in self.cases] + [b.to_json() for b in self.bistable]


# --- the paper's plan ---------------------------------------------------------------------------------------

def paper_plan(axle: Axle, asymmetric: tuple[float, float] | None = None) -> Plan:
    """The cases the paper prints numbers for: section 3 at 1.5, 2.5 and 2.7 bar, figures 9a-11 at t0 = 0.25 m."""
    cases = [Case(1.5, 1.5, CaseKind.PAPER, "figure 4a: both modes (HB1-HB4 printed)"),
             Case(2.5, 2.5, CaseKind.PAPER, "figure 3: nominal pressure, yaw mode only (HB1, HB2 printed)"),
             Case(2.7, 2.7, CaseKind.PAPER, "figure 4b: above the shimmy-free boundary F1, no Hopf point")]
    if asymmetric is not None:
        cases.append(_asymmetric_case(*asymmetric))
    t0_axle = axle.with_overrides({"t0": 0.25})
    bistable = (BistableCase(t0_axle, 1.5, math.nan, math.nan,
                             "figures 9a, 10 and 11: t0 = 0.25 m at 1.5 bar, stable yaw and tramp cycles coexist "
                             "between T2 and S1"),)
    return Plan(tuple(cases), bistable, ("the paper's truck: the paper's own cases",))


def _asymmetric_case(right: float, left: float) -> Case:
    return Case(right, left, CaseKind.ASYMMETRIC, f"asked for: right tyre {right:g} bar, left tyre {left:g} bar")


# --- a plan for any axle -------------------------------------------------------------------------------------

@dataclass(frozen=True)
class Window:
    """An unstable speed window of straight running at one pressure (m/s), with its mode."""

    low: float
    high: float
    mode: str
    frequency_hz: float
    closed: bool        # both ends are Hopf points inside the speed window


def tramp_share(vector: np.ndarray) -> float:
    v = np.abs(vector)
    return float(v[_I_PSI] / max(v[_I_TH1], v[_I_TH2], 1e-300))


def unstable_windows(family: SpeedFamily, q: float, vmax: float = VMAX) -> tuple[list[Window], tuple]:
    """Unstable speed windows of straight running at q, each with the mode of its critical eigenvector."""
    points = hopf_points(family, q, 0.0, vmax)
    edges = [MIN_SPEED] + [h.p for h in points] + [vmax]
    windows = []
    for a, b in zip(edges[:-1], edges[1:]):
        if b - a < 1e-6:
            continue
        values, vectors = np.linalg.eig(family.linear_matrix(0.5 * (a + b), q))
        k = int(np.argmax(values.real))
        if values[k].real <= 0.0:
            continue
        mode = "tramp" if tramp_share(vectors[:, k]) > TRAMP_SHARE else "yaw"
        windows.append(Window(a, b, mode, abs(values[k].imag) / (2 * math.pi),
                              closed=a > MIN_SPEED and b < vmax))
    return windows, points


def _overlapping_pairs(family: SpeedFamily, q: float, windows: list[Window]) -> bool:
    """Two eigenvalue pairs unstable at one speed somewhere in the windows (modes overlap: tori can appear)."""
    for w in windows:
        for V in np.linspace(w.low, w.high, 9)[1:-1]:
            values = np.linalg.eigvals(family.linear_matrix(V, q))
            if np.sum((values.real > 0.0) & (values.imag > 0.0)) >= 2:
                return True
    return False


def stable_segments(diagram) -> list[tuple[float, float, int]]:
    """(low, high, branch index) speed intervals (m/s) of consecutive stable cycles on each branch."""
    out = []
    for i, b in enumerate(diagram.branches):
        run: list[float] = []
        for p in list(b.points) + [None]:
            if p is not None and p.stable:
                run.append(p.p)
                continue
            if len(run) >= 2:
                out.append((min(run), max(run), i))
            run = []
    return out


def bistable_windows(diagram) -> list[tuple[float, float]]:
    """Speed intervals (m/s) where two stable segments overlap."""
    segs = stable_segments(diagram)
    found = []
    for j in range(len(segs)):
        for k in range(j + 1, len(segs)):
            lo, hi = max(segs[j][0], segs[k][0]), min(segs[j][1], segs[k][1])
            if hi - lo > from_kmh(0.5):
                found.append((lo, hi))
    return found


def axle_plan(axle: Axle, quick: bool, asymmetric: tuple[float, float] | None = None,
              vmax: float = VMAX, progress=None) -> Plan:
    """The cases to verify for any axle (see the module docstring for the rules)."""
    from reduced_model.bifurcation.cycles.branches import cycle_diagram
    from reduced_model.bifurcation.equilibria.hopf_curves import hopf_diagram
    from reduced_model.bifurcation.special_points import PointKind

    lo, hi = axle.pressure_range_bar
    model = ShimmyModel(params=axle.params)
    family = SpeedFamily(model, "pressure")
    n_grid = 7 if quick else 13
    grid = np.linspace(lo, hi, n_grid)
    scan = []
    for i, p in enumerate(grid):
        windows, points = unstable_windows(family, p * BAR, vmax)
        scan.append((float(p), windows, points))
        if progress is not None:
            progress(f"plan: Hopf points at {p:.3g} bar ({i + 1}/{n_grid})")
    notes = []
    cases: list[Case] = []

    # Mode cases: where each mode's window is widest (closed windows first).
    for mode in ("yaw", "tramp"):
        best = None
        for p, windows, _ in scan:
            for w in windows:
                if w.mode != mode:
                    continue
                key = (w.closed, w.high - w.low)
                if best is None or key > best[0]:
                    best = (key, p, w)
        if best is None:
            notes.append(f"no {mode} mode anywhere in {lo:g}-{hi:g} bar")
            continue
        (_, width), p, w = best
        same = next((c for c in cases if c.pressure_right_bar == p), None)
        text = (f"{mode} mode widest here: unstable {kmh(w.low):.1f}-{kmh(w.high):.1f} km/h at "
                f"{w.frequency_hz:.1f} Hz" + ("" if w.closed else " (reaches the edge of the speed window)"))
        if same is not None:
            cases[cases.index(same)] = Case(p, p, CaseKind.MODE, same.reason + "; " + text)
        else:
            cases.append(Case(p, p, CaseKind.MODE, text))

    # The shimmy-free boundary from the folds of the Hopf curves.
    if progress is not None:
        progress("plan: Hopf curves over the pressure window")
    diagram = hopf_diagram(family, lo * BAR, hi * BAR, MIN_SPEED, vmax, n_seeds=5 if quick else 9)
    folds = sorted(s.q / BAR for s in diagram.special_points if s.kind is PointKind.HOPF_FOLD)
    shimmy_at_top = any(w for w in scan[-1][1])
    boundary = None
    if folds and not shimmy_at_top:
        boundary = folds[-1]
        fold = max((s for s in diagram.special_points if s.kind is PointKind.HOPF_FOLD), key=lambda s: s.q)
        below = max(lo, boundary - EDGE_BAR)
        above = min(hi, boundary + EDGE_BAR)
        cases.append(Case(round(below, 4), round(below, 4), CaseKind.BELOW_BOUNDARY,
                          f"{EDGE_BAR:g} bar below the shimmy-free boundary at {boundary:.4f} bar (fold of the Hopf "
                          f"curves at {kmh(fold.p):.1f} km/h): the last mode's narrow window"))
        cases.append(Case(round(above, 4), round(above, 4), CaseKind.SHIMMY_FREE,
                          f"{EDGE_BAR:g} bar above the shimmy-free boundary: no Hopf point in either model"))
    elif shimmy_at_top:
        notes.append(f"shimmy at the top of the pressure window ({hi:g} bar): no shimmy-free boundary inside it")
    else:
        notes.append("no fold of the Hopf curves in the pressure window")
    for s in diagram.special_points:
        if s.kind is PointKind.HOPF_FOLD and (boundary is None or s.q / BAR != boundary):
            notes.append(f"a mode is born or vanishes at {s.q / BAR:.4f} bar, {kmh(s.p):.1f} km/h "
                         f"(fold of the Hopf curves)")
    if asymmetric is not None:
        cases.append(_asymmetric_case(*asymmetric))

    # Bistable windows where cycles can coexist.
    # Subcritical points first (cycle folds bound a bistable window), then overlapping modes (tori).
    scored = []
    for p, windows, points in scan:
        if not windows:
            continue
        sub = sum(h.first_lyapunov > 0.0 for h in points)
        if sub or _overlapping_pairs(family, p * BAR, windows):
            scored.append((-sub, abs(p - 0.5 * (lo + hi)), p, windows, points))
    limit = 2 if quick else 4
    candidates = [(p, w, pts) for _, _, p, w, pts in sorted(scored, key=lambda s: s[:2])[:limit]]
    best = None
    for p, _, _ in candidates:
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
            cases.append(Case(p, p, CaseKind.BISTABLE, reason))
    elif candidates:
        notes.append("no bistable window at the pressures where modes overlap or a Hopf point is subcritical")
    else:
        notes.append("no pressure with overlapping modes or a subcritical Hopf point: no bistable window near "
                     "straight running")
    return Plan(tuple(cases), bistable, tuple(notes), boundary)
