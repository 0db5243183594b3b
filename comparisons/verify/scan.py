"""What each model says over an axle's pressure window: its unstable speed windows on a grid of pressures, its Hopf
curves and its own shimmy-free boundary.

The two models are the reduced model (section 3, the paper's equations) and the MBS with the full geometry (every
assumption of the reduced model off, :meth:`mbs_shimmy.fidelity.Fidelity.full`).  Both are toolkit families, so
the same functions scan both:

- an unstable speed window at one pressure runs between two Hopf points of straight running (or a Hopf point and
  an end of the speed window); its mode is named by the critical eigenvector's tramp share
  |psi| / max(|theta1|, |theta2|) against :data:`TRAMP_SHARE`;
- the shimmy-free boundary is the highest pressure where a window exists: the highest fold of the Hopf curves in
  (V, p) (:func:`bifurcation.equilibria.hopf_curves.hopf_diagram`), where a mode's window shrinks to
  a point; without the curves (the full geometry in ``verify --quick``: its curves cost about two minutes of Exudyn
  Jacobians), the root in pressure of the largest growth rate of straight running over speed,
  ``g(p) = max_V max Re lambda(V, p)``, between the highest grid pressure that shimmies and the next one (the same
  point: at the fold the critical pair touches the imaginary axis at one speed).
"""

from __future__ import annotations

import enum
import math
import time
from dataclasses import dataclass, field

import numpy as np

from axles.units import BAR, from_kmh, kmh
from bifurcation.equilibria.hopf import find_hopf_points
from reduced_model.family import MIN_SPEED
from reduced_model.modes import TRAMP_SHARE, tramp_share
from axles.pressures import TyrePressures

VMAX = from_kmh(400)
# |psi| / max|theta| of the critical eigenvector above which a window is the tramp mode: the split the simulation's
# mode classifier uses for cycles, so that a planned mode and a simulated one carry the same name.
BOUNDARY_XTOL_BAR = 1e-4      # the growth-rate root's tolerance in pressure
GROWTH_SPEEDS = 161           # speed grid of g(p) before the local refinement of its maximum


class Model(enum.Enum):
    """The two models a plan and a verdict speak of (the value is the JSON key)."""

    REDUCED = "reduced"
    FULL = "full"

    @property
    def label(self) -> str:
        return {"reduced": "the reduced model", "full": "the full geometry"}[self.value]


@dataclass(frozen=True)
class Window:
    """An unstable speed window of straight running at one pressure (m/s), with its mode."""

    low: float
    high: float
    mode: str
    frequency_hz: float
    closed: bool        # both ends are Hopf points inside the speed window
    # every growing oscillation at the window's middle, by mode (the verdict's per-mode ranges); ``mode`` is the
    # fastest growing one
    unstable: tuple[str, ...] = ()

    def modes(self) -> tuple[str, ...]:
        return self.unstable or (self.mode,)

    def text(self) -> str:
        """"from 47.5 to 71.5 km/h (yaw)", saying so where the window reaches an end of the speed window."""
        if self.closed:
            end = ""
        elif self.low <= MIN_SPEED:
            end = ", from the lowest speed"
        else:
            end = ", up to the top of the speed window"
        return f"from {kmh(self.low):.1f} to {kmh(self.high):.1f} km/h ({self.mode}{end})"

    def to_json(self) -> dict:
        return {"low_kmh": kmh(self.low), "high_kmh": kmh(self.high), "mode": self.mode,
                "frequency_hz": self.frequency_hz, "closed": self.closed}



def unstable_windows(family, q: float, vmax: float = VMAX, lyapunov: bool = True) -> tuple[list[Window], tuple]:
    """Unstable speed windows of straight running at q, each with the mode of its critical eigenvector (the
    family's first states are the reduced model's, as in both models' families)."""
    points = find_hopf_points(family, q, 0.0, vmax, lyapunov=lyapunov)
    edges = [MIN_SPEED] + [h.p for h in points] + [vmax]
    windows = []
    for a, b in zip(edges[:-1], edges[1:]):
        if b - a < 1e-6:
            continue
        values, vectors = np.linalg.eig(family.linear_matrix(0.5 * (a + b), q))
        k = int(np.argmax(values.real))
        if values[k].real <= 0.0:
            continue

        def mode_of(i: int) -> str:
            return "tramp" if tramp_share(vectors[:, i]) > TRAMP_SHARE else "yaw"
        growing = [i for i in range(len(values)) if values[i].real > 0.0 and values[i].imag > 0.0]
        windows.append(Window(a, b, mode_of(k), abs(values[k].imag) / (2 * math.pi),
                              closed=a > MIN_SPEED and b < vmax,
                              unstable=tuple(sorted({mode_of(i) for i in growing}, key=("yaw", "tramp").index))))
    return windows, points


def peak_growth_rate(family, q: float, vmax: float = VMAX) -> float:
    """g(q) = max over MIN_SPEED <= V <= vmax of the largest real part of the eigenvalues of straight running (1/s):
    positive exactly where some speed shimmies (or diverges)."""
    from scipy.optimize import minimize_scalar

    def growth(V: float) -> float:
        return float(np.max(np.linalg.eigvals(family.linear_matrix(V, q)).real))

    speeds = np.linspace(MIN_SPEED, vmax, GROWTH_SPEEDS)
    values = [growth(V) for V in speeds]
    k = int(np.argmax(values))
    lo, hi = speeds[max(k - 1, 0)], speeds[min(k + 1, len(speeds) - 1)]
    best = minimize_scalar(lambda V: -growth(V), bounds=(lo, hi), method="bounded", options={"xatol": 1e-3})
    return max(values[k], -float(best.fun))


def scan_family(axle, model: Model, param: str = "pressure", pressures: TyrePressures | None = None):
    """The toolkit family of one model of ``axle`` over ``param`` (section 3 model, no pressure effects; the
    MBS at full fidelity) at ``pressures`` (default 2.5 bar)."""
    from comparisons.api import Axle
    chosen = Axle(axle).reduced() if model is Model.REDUCED else Axle(axle).mbs(fidelity="full")
    return chosen.problem(pressures or TyrePressures.uniform(2.5e5), param)


class BoundaryKind(enum.Enum):
    SHIMMY_FREE_ABOVE = "shimmy-free above"
    SHIMMY_AT_TOP = "shimmies up to the top of the window"
    NO_SHIMMY = "no shimmy in the window"


class BoundaryMethod(enum.Enum):
    FOLD = "highest fold of the Hopf curves"
    GROWTH_ROOT = "root of the largest growth rate over speed"


@dataclass(frozen=True)
class Boundary:
    """A model's shimmy-free boundary in pressure: the pressure above which it shimmies at no speed."""

    kind: BoundaryKind
    pressure_bar: float | None = None     # SHIMMY_FREE_ABOVE only
    speed_kmh: float | None = None        # where the last window closes (the fold's speed), if known
    method: BoundaryMethod | None = None

    def to_json(self) -> dict:
        return {"kind": self.kind.name.lower(), "pressure_bar": self.pressure_bar, "speed_kmh": self.speed_kmh,
                "method": None if self.method is None else self.method.name.lower()}


@dataclass(frozen=True)
class GridPoint:
    pressure_bar: float
    windows: tuple[Window, ...]
    points: tuple = ()                    # the Hopf points (toolkit HopfPoint)


@dataclass(frozen=True)
class ModelScan:
    """One model over the pressure window: the grid scan, the folds of its Hopf curves, its boundary."""

    model: Model
    window_bar: tuple[float, float]
    grid: tuple[GridPoint, ...]
    boundary: Boundary
    folds: tuple[tuple[float, float], ...] = ()      # (bar, km/h) of every fold of the Hopf curves found
    curves: bool = False                             # the Hopf curves were continued
    seconds: float = 0.0
    diagram: object = field(default=None, compare=False, repr=False)   # the HopfDiagram, when continued

    def shimmies_somewhere(self) -> bool:
        return any(g.windows for g in self.grid) or self.boundary.kind is not BoundaryKind.NO_SHIMMY

    def to_json(self) -> dict:
        return {"model": self.model.value, "boundary": self.boundary.to_json(), "curves": self.curves,
                "seconds": self.seconds, "folds": [{"pressure_bar": p, "speed_kmh": v} for p, v in self.folds],
                "grid": [{"pressure_bar": g.pressure_bar, "windows": [w.to_json() for w in g.windows]}
                         for g in self.grid]}


def growth_root(family, shimmy_bar: float, free_bar: float, vmax: float = VMAX) -> float:
    """The pressure between ``shimmy_bar`` (g > 0) and ``free_bar`` (g <= 0) where g(p) = 0, bar."""
    from scipy.optimize import brentq
    g_hi = peak_growth_rate(family, free_bar * BAR, vmax)
    if g_hi > 0.0:        # the grid's windows missed a narrow one: the boundary lies higher up
        return free_bar
    return brentq(lambda p: peak_growth_rate(family, p * BAR, vmax), shimmy_bar, free_bar, xtol=BOUNDARY_XTOL_BAR)


def scan_model(axle, model: Model, grid, vmax: float = VMAX, curves: bool = True, n_seeds: int = 5,
               progress=None) -> ModelScan:
    """Scan one model of ``axle`` over ``grid`` (bar): windows at each pressure, Hopf curves (if ``curves``), the
    shimmy-free boundary (module docstring)."""
    from bifurcation.equilibria.hopf_curves import hopf_diagram
    from bifurcation.special_points import PointKind
    say = progress or (lambda message: None)
    start = time.perf_counter()
    family = scan_family(axle, model)
    lo, hi = float(grid[0]), float(grid[-1])
    # The Lyapunov coefficients feed the reduced model's bistability search only; the MBS's cost Exudyn calls.
    lyapunov = model is Model.REDUCED
    points = []
    for i, p in enumerate(grid):
        windows, hopf = unstable_windows(family, p * BAR, vmax, lyapunov=lyapunov)
        points.append(GridPoint(float(p), tuple(windows), tuple(hopf)))
        say(f"plan: Hopf points of {model.label} at {p:.3g} bar ({i + 1}/{len(grid)})")
    diagram, folds = None, ()
    if curves:
        say(f"plan: Hopf curves of {model.label} over {lo:g}-{hi:g} bar")
        diagram = hopf_diagram(family, lo * BAR, hi * BAR, MIN_SPEED, vmax, n_seeds=n_seeds)
        folds = tuple(sorted((s.q / BAR, kmh(s.p)) for s in diagram.special_points
                             if s.kind is PointKind.HOPF_FOLD))
    boundary = _boundary(family, points, folds, vmax, say, model)
    return ModelScan(model, (lo, hi), tuple(points), boundary, folds, curves, time.perf_counter() - start, diagram)


def _boundary(family, points: list[GridPoint], folds, vmax: float, say, model: Model) -> Boundary:
    if points[-1].windows:
        return Boundary(BoundaryKind.SHIMMY_AT_TOP)
    if folds:
        p, v = folds[-1]
        return Boundary(BoundaryKind.SHIMMY_FREE_ABOVE, p, v, BoundaryMethod.FOLD)
    shimmy = [i for i, g in enumerate(points) if g.windows]
    if not shimmy:
        return Boundary(BoundaryKind.NO_SHIMMY)
    k = shimmy[-1]
    say(f"plan: shimmy-free boundary of {model.label} between {points[k].pressure_bar:.3g} and "
        f"{points[k + 1].pressure_bar:.3g} bar")
    p = growth_root(family, points[k].pressure_bar, points[k + 1].pressure_bar, vmax)
    return Boundary(BoundaryKind.SHIMMY_FREE_ABOVE, p, None, BoundaryMethod.GROWTH_ROOT)
