"""Where in (speed, pressure) a kick sets shimmy off while straight running is stable: the bistable regions of one
model over a pressure window, and the pressure above which it has no stable shimmy at any speed.

At one pressure the cycle branches in speed (:func:`bifurcation.cycles.branches.cycle_diagram`) give the speed
intervals where two stable states coexist (:func:`comparisons.studies.kick.bistable_windows`): a stable cycle
beside stable straight running (past a subcritical Hopf point, up to the cycle fold), or two stable cycles.  Those
intervals on a grid of pressures are joined into regions where they overlap from one grid pressure to the next;
a region's pressure ends are bracketed by the grid (the last pressure with the interval and the next without), and
the highest pressure with a stable cycle by bisection on "a stable cycle exists at some speed".  The region's
boundaries are the cycle-fold, torus and subcritical Hopf curves in (V, p) (Kuznetsov 2004, section 8.3); the
slices meet them, they do not follow them: a region narrower in pressure than the grid spacing between two grid
pressures is missed, which the grid spacing in the result says.
"""

from __future__ import annotations

import enum
import math
import time
from dataclasses import dataclass
from typing import Callable, Sequence

from axles.units import BAR, from_kmh, kmh
from bifurcation.cycles.branches import cycle_diagram
from bifurcation.problem import Family
from comparisons.studies.budget import DeadlineWatch, OutOfTime
from comparisons.studies.kick import bistable_windows

MIN_WIDTH = from_kmh(0.5)           # m/s: a narrower interval is the spacing of two computed cycles
STABLE_XTOL_BAR = 0.01            # bisection tolerance of the stable-shimmy-free pressure


class MapStatus(enum.Enum):
    COMPLETE = "complete"                  # every slice's branches ended as they should
    INCOMPLETE = "incomplete"              # a slice's continuation stopped early: the map may miss a region
    OVER_BUDGET = "over_budget"            # the time budget ran out: a slice stopped, or was not computed

    @property
    def is_complete(self) -> bool:
        return self is MapStatus.COMPLETE


@dataclass(frozen=True)
class Slice:
    """One pressure of the grid (Pa): the bistable speed intervals (m/s) there, whether any stable cycle exists at
    some speed (a computed one: True is a fact even where the slice is incomplete, False only where it is complete),
    and whether every branch of its diagram is complete; ``over_budget``: stopped, or not started, by the map's
    time budget (its intervals are then empty: not computed)."""

    pressure: float
    intervals: tuple[tuple[float, float], ...]
    stable_cycle: bool
    complete: bool
    message: str = ""
    over_budget: bool = False


@dataclass(frozen=True)
class BistableRegion:
    """Consecutive grid pressures whose bistable speed intervals overlap: ``slices`` are (pressure Pa, low m/s,
    high m/s) by pressure; the region's pressure ends lie in ``low_bracket`` and ``high_bracket`` (Pa)."""

    slices: tuple[tuple[float, float, float], ...]
    low_bracket: tuple[float, float]
    high_bracket: tuple[float, float]

    @property
    def speed_range(self) -> tuple[float, float]:
        return min(s[1] for s in self.slices), max(s[2] for s in self.slices)

    def text(self) -> str:
        lo, hi = self.speed_range
        p_lo = self.slices[0][0] / BAR
        p_hi = self.slices[-1][0] / BAR
        where = f"{p_lo:g} bar" if p_lo == p_hi else f"{p_lo:g}-{p_hi:g} bar"
        return f"{where}, {kmh(lo):.1f}-{kmh(hi):.1f} km/h"

    def to_json(self) -> dict:
        return {"pressure_bar": [self.slices[0][0] / BAR, self.slices[-1][0] / BAR],
                "pressure_low_bracket_bar": [p / BAR for p in self.low_bracket],
                "pressure_high_bracket_bar": [p / BAR for p in self.high_bracket],
                "speed_kmh": [kmh(v) for v in self.speed_range],
                "slices": [{"pressure_bar": p / BAR, "speed_kmh": [kmh(a), kmh(b)]} for p, a, b in self.slices]}


@dataclass(frozen=True)
class BistableMap:
    """A model's bistable regions over a pressure window and its stable-shimmy-free pressure: above
    ``stable_shimmy_free`` (Pa) no stable cycle exists at any speed of the window (None where one exists up to the
    top of the window; the lowest pressure where none exists at all)."""

    label: str
    window: tuple[float, float]                  # m/s
    slices: tuple[Slice, ...]
    regions: tuple[BistableRegion, ...]
    stable_shimmy_free: float | None
    stable_shimmy_free_bracket: tuple[float, float] | None
    status: MapStatus
    budget_s: float | None = None                # the time budget it was computed within (None: none)
    free_determined: bool = True                 # False: a slice above the last stable cycle is incomplete
    probes: tuple[Slice, ...] = ()               # the bisection's slices that stopped early (off the grid)

    @property
    def spacing(self) -> float:
        """The grid's largest pressure step (Pa): a region narrower than this can lie between two grid pressures."""
        p = [s.pressure for s in self.slices]
        return max((b - a for a, b in zip(p[:-1], p[1:])), default=0.0)

    def text(self) -> str:
        regions = ("no bistable region" if not self.regions else
                   "bistable at " + "; ".join(r.text() for r in self.regions))
        free = self.stable_shimmy_free
        top = self.slices[-1].pressure / BAR
        stable = ("the stable-shimmy-free pressure is not determined (a slice above the last stable cycle is "
                  "incomplete)" if not self.free_determined else
                  f"no stable shimmy at any speed above {free / BAR:.2f} bar" if free is not None and
                  free > self.slices[0].pressure else
                  "no stable shimmy at any speed of the window" if free is not None else
                  f"stable shimmy up to the top of the window ({top:g} bar)")
        return f"{self.label}: {regions}; {stable}{self._missing()}"

    def _missing(self) -> str:
        if self.status.is_complete:
            return ""
        stopped = [s for s in self.slices + self.probes if s.over_budget]
        early = [s for s in self.slices + self.probes if not s.complete and not s.over_budget]
        parts = []
        if early:
            parts.append("a continuation stopped early at " + ", ".join(f"{s.pressure / BAR:.4g} bar" for s in early)
                         + f" ({early[0].message})")
        if stopped:
            parts.append(f"the time budget of {self.budget_s:g} s ran out at " + ", ".join(
                f"{s.pressure / BAR:g} bar" for s in stopped) + f" ({stopped[0].message})")
        return " (INCOMPLETE: " + "; ".join(parts) + ")"

    def to_json(self) -> dict:
        return {"status": self.status.value, "grid_step_bar": self.spacing / BAR, "budget_s": self.budget_s,
                "stable_shimmy_free_determined": self.free_determined,
                "regions": [r.to_json() for r in self.regions],
                "stable_shimmy_free_above_bar": None if self.stable_shimmy_free is None
                else self.stable_shimmy_free / BAR,
                "stable_shimmy_free_bracket_bar": None if self.stable_shimmy_free_bracket is None
                else [p / BAR for p in self.stable_shimmy_free_bracket],
                "text": self.text()}


def slice_at(family: Family, q: float, p_min: float, p_max: float, deadline: float = math.inf) -> Slice:
    """The bistable speed intervals of ``family`` at its second parameter ``q``, stopped when ``time.monotonic()``
    passes ``deadline`` (then an over-budget slice, which says where its branch was)."""
    if time.monotonic() >= deadline:
        return Slice(q, (), False, False, "not started: the budget was spent", over_budget=True)
    watch = DeadlineWatch(deadline, family.state_names)
    try:
        diagram = cycle_diagram(family, q, p_min, p_max, accept_hook=watch)
    except OutOfTime as stop:
        return Slice(q, (), watch.stable, False, f"stopped on {stop}", over_budget=True)
    incomplete = [b for b in diagram.branches if not b.complete]
    return Slice(q, tuple(bistable_windows(diagram, family, MIN_WIDTH)),
                 any(p.stable for b in diagram.branches for p in b.points), not incomplete,
                 "; ".join(str(b.message) for b in incomplete))


def regions_of(slices: Sequence[Slice]) -> tuple[BistableRegion, ...]:
    """Regions: the connected sets of bistable intervals, two intervals of neighbouring grid pressures being
    connected where they overlap in speed."""
    pieces = [(i, lo, hi) for i, s in enumerate(slices) for lo, hi in s.intervals]
    parent = list(range(len(pieces)))

    def root(k: int) -> int:
        while parent[k] != k:
            k = parent[k]
        return k

    for a, (i, lo, hi) in enumerate(pieces):
        for b, (j, lo2, hi2) in enumerate(pieces):
            if j == i + 1 and lo < hi2 and lo2 < hi:
                parent[root(b)] = root(a)
    groups: dict[int, list[tuple[int, float, float]]] = {}
    for k, piece in enumerate(pieces):
        groups.setdefault(root(k), []).append(piece)
    out = []
    for group in groups.values():
        first, last = min(g[0] for g in group), max(g[0] for g in group)
        below = slices[max(first - 1, 0)].pressure
        above = slices[min(last + 1, len(slices) - 1)].pressure
        out.append(BistableRegion(tuple(sorted((slices[i].pressure, lo, hi) for i, lo, hi in group)),
                                  (below, slices[first].pressure), (slices[last].pressure, above)))
    return tuple(sorted(out, key=lambda r: (r.slices[0][0], r.slices[0][1])))


def bistable_map(family_at: Callable[[float], Family], pressures: Sequence[float], p_min: float, p_max: float,
                 label: str, xtol: float = STABLE_XTOL_BAR * BAR,
                 progress: Callable[[str], None] = lambda text: None, budget_s: float | None = None) -> BistableMap:
    """The bistable regions of the families ``family_at(pressure)`` (Pa, both tyres) on the grid ``pressures``
    (Pa, rising) over the speed window [p_min, p_max] (m/s), and the stable-shimmy-free pressure, bisected to
    ``xtol`` between the highest grid pressure with a stable cycle and the next; within ``budget_s`` seconds of
    wall clock (module docstring; the bisection gets what the grid left, and stops with a wider bracket)."""
    end = math.inf if budget_s is None else time.monotonic() + budget_s
    slices = []
    for i, pressure in enumerate(pressures):
        progress(f"{label}: cycles at {pressure / BAR:g} bar")
        family = family_at(pressure)
        now = time.monotonic()
        share = now + (end - now) / (len(pressures) - i) if math.isfinite(end) else math.inf
        slices.append(slice_at(family, family.nominal, p_min, p_max, share))
    stable = [s for s in slices if s.stable_cycle]
    free = bracket = None
    above = slices[slices.index(stable[-1]) + 1:] if stable else slices
    determined = all(s.complete for s in above)
    if not determined:
        pass                            # no slice above the last stable cycle may be read as having none
    elif not stable:
        free, bracket = slices[0].pressure, None
    elif stable[-1] is not slices[-1]:
        lo = stable[-1].pressure
        hi = slices[slices.index(stable[-1]) + 1].pressure
        while hi - lo > xtol:
            mid = 0.5 * (lo + hi)
            progress(f"{label}: stable shimmy at {mid / BAR:.3f} bar?")
            family = family_at(mid)
            s = slice_at(family, family.nominal, p_min, p_max, end)
            if s.stable_cycle:
                lo = mid                # a computed stable cycle, complete slice or not
            elif s.complete:
                hi = mid
            else:
                slices.append(s)        # reported as incomplete: the bracket is kept as it is
                break
        free, bracket = hi, (lo, hi)
    grid = sorted((s for s in slices if s.pressure in pressures), key=lambda s: s.pressure)
    probes = tuple(s for s in slices if s.pressure not in pressures)
    status = (MapStatus.COMPLETE if all(s.complete for s in slices) else
              MapStatus.OVER_BUDGET if any(s.over_budget for s in slices) else MapStatus.INCOMPLETE)
    return BistableMap(label, (p_min, p_max), tuple(grid), regions_of(grid), free, bracket, status, budget_s,
                       determined, probes)
