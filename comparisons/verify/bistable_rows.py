"""``verify``'s section "Bistable regions": where in (speed, pressure) a kick sets shimmy off while straight running
is stable, for each model (:mod:`comparisons.studies.bistable_map`), each region checked by runs of the same model.

The check of a region: at its widest slice, the smallest kick that leaves the lower state is bracketed by
simulation (:func:`comparisons.studies.kick.kick_threshold`); that kick must leave it there (found by the bisection
itself), and the same kick must return to straight running just outside the region, at a speed the map calls
monostable (straight running stable, no stable cycle).  A run that does not settle is "could not check"; a kick
that does not return where the map says nothing else is stable is a FAIL: the continuation and the simulation of one
model disagree.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np

from axles.axle import interface_text
from axles.pressures import TyrePressures
from axles.units import BAR, from_kmh, kmh
from comparisons.studies.bistable_map import MIN_WIDTH, STABLE_XTOL_BAR, BistableMap, BistableRegion, bistable_map
from comparisons.verify.context import Context
from comparisons.verify.report import CheckStatus, Row, Section
from comparisons.verify.scan import VMAX, Model, scan_family

STEP_BAR = 0.25             # the pressure grid of the map (quick: QUICK_STEP_BAR)
QUICK_STEP_BAR = 0.5
QUICK_XTOL_BAR = 0.05       # the stable-shimmy-free pressure's bisection tolerance in a quick run
KICK_TOL = 0.02             # the kick threshold's bracket, relative (quick: QUICK_KICK_TOL)
QUICK_KICK_TOL = 0.1
AMPLITUDE_TOL = 0.01        # a run's max|theta1| against the one stable cycle's (relative)
OUTSIDE_KMH = 2.0           # how far beyond a bistable interval the kick is repeated
# Each model's map within a time budget (wall clock): the paper's axle needs 8 s (quick grid) and 13 s (full grid)
# for its full geometry, but branches of violent cycles that lift a wheel take minutes (a random plausible axle's
# at 0.5 bar: 112 s, peak max|theta1| 49 deg); past its budget a map is reported incomplete, never as "no region"
# (studies.bistable_map).
QUICK_BUDGET_S = 30.0
BUDGET_S = 120.0


@dataclass(frozen=True)
class BistableFact:
    """One model's bistable map, as the verdict adds it to that model (JSON key ``bistable``), or why there is
    none (``map`` None, ``reason`` says why: never read as "no region")."""

    model: Model
    map: BistableMap | None
    reason: str = ""

    def text(self) -> str:
        if self.map is None:
            return f"{self.model.label}: bistable regions not computed ({self.reason})"
        return self.map.text()

    def to_json(self) -> dict:
        if self.map is None:
            return {"status": "not_computed", "reason": self.reason, "text": self.text()}
        return self.map.to_json()


def pressure_grid(window_bar: tuple[float, float], step_bar: float) -> list[float]:
    """Pa, from the window's low end to its high end in steps of about ``step_bar`` (both ends included)."""
    lo, hi = window_bar
    n = max(2, int(round((hi - lo) / step_bar)) + 1)
    return [float(p) * BAR for p in np.linspace(lo, hi, n)]


def family_at(axle, model: Model):
    return lambda pressure: scan_family(axle, model, pressures=TyrePressures.uniform(pressure))


def outside_points(axle, model: Model, region: BistableRegion, pressure: float, low: float, high: float):
    """Candidates (pressure Pa, speed m/s) just outside the region, nearest first: beyond the interval's ends in
    speed at its pressure, then at its speed on the grid pressures that bracket the region."""
    yield pressure, high + from_kmh(OUTSIDE_KMH)
    yield pressure, low - from_kmh(OUTSIDE_KMH)
    for beyond in (region.high_bracket[1], region.low_bracket[0]):
        if beyond not in (s[0] for s in region.slices):
            yield beyond, 0.5 * (low + high)


def monostable_outside(axle, model: Model, region: BistableRegion, pressure: float, low: float, high: float,
                       diagram):
    """The first of :func:`outside_points` where the model has one stable state (straight running or one cycle):
    (pressure, speed, family, that state); None if there is none."""
    from bifurcation.cycles.branches import cycle_diagram
    from comparisons.studies.kick import states_at
    diagrams = {pressure: (family_at(axle, model)(pressure), diagram)}
    for p, speed in outside_points(axle, model, region, pressure, low, high):
        if speed <= from_kmh(0.5):
            continue
        if p not in diagrams:
            family = family_at(axle, model)(p)
            diagrams[p] = (family, cycle_diagram(family, family.nominal, from_kmh(0.5), VMAX))
        family, d = diagrams[p]
        stable, _ = states_at(family, d, speed)
        if len(stable) == 1:
            return p, speed, family, stable[0]
    return None


def state_text(state) -> str:
    """A stable state by name and size: two stable stretches of one branch carry one name."""
    return state.label if state.theta1 == 0.0 else f"{state.label} (max|theta1| {math.degrees(state.theta1):.2f} deg)"


def region_row(axle, model: Model, region: BistableRegion, kick_tol: float = KICK_TOL) -> Row:
    """The kick check of one region (module docstring)."""
    from bifurcation.cycles.branches import cycle_diagram
    from comparisons.studies.kick import coexisting_states, kick_start, kick_threshold, settle_function
    from comparisons.studies.limit_cycle import DECAYED
    pressure, low, high = max(region.slices, key=lambda s: s[2] - s[1])
    family = family_at(axle, model)(pressure)
    inside = 0.5 * (low + high)
    cells = {"model": model.value, "pressure_bar": pressure / BAR, "region_kmh": f"{kmh(low):.1f}-{kmh(high):.1f}",
             "inside_kmh": kmh(inside)}
    # the whole window: a branch born at a Hopf point far from the interval can be one of its stable states
    diagram = cycle_diagram(family, family.nominal, from_kmh(0.5), VMAX)
    found = coexisting_states(family, diagram, inside)
    if found is None:
        return Row(cells, CheckStatus.FAIL, "the map says two stable states coexist here, but the branches at this "
                                            "speed give fewer than two")
    threshold = kick_threshold(settle_function(family, inside), inside, *found, rel_tol=kick_tol)
    cells["kick_deg"] = math.degrees(threshold.leaves)
    if not threshold.status.is_complete:
        return Row(cells, CheckStatus.COULD_NOT_CHECK, f"the kick threshold was not bracketed "
                                                       f"({threshold.status.value})")
    found_outside = monostable_outside(axle, model, region, pressure, low, high, diagram)
    if found_outside is None:
        return Row(cells, CheckStatus.COULD_NOT_CHECK, f"no point with a single stable state within {OUTSIDE_KMH:g} "
                                                       f"km/h of the interval or on the neighbouring grid pressures to "
                                                       f"repeat the kick at")
    p_out, outside, family_out, single = found_outside
    cells["outside"] = f"{p_out / BAR:g} bar, {kmh(outside):.1f} km/h"
    run = settle_function(family_out, outside)(kick_start(threshold.leaves))
    if not run.settled:
        return Row(cells, CheckStatus.COULD_NOT_CHECK, "the run outside the region did not settle")
    if single.theta1 == 0.0:
        returned = run.theta1 < DECAYED
    else:
        returned = abs(run.theta1 - single.theta1) <= AMPLITUDE_TOL * single.theta1
    what = (f"a kick of {math.degrees(threshold.leaves):.2f} deg leaves {state_text(threshold.lower)} for "
            f"{state_text(threshold.upper)} at {kmh(inside):.1f} km/h ({math.degrees(threshold.stays):.2f} deg stays)")
    if returned:
        return Row(cells, CheckStatus.PASS, f"{what}; at {cells['outside']} the same kick ends on "
                                            f"{state_text(single)}, the one stable state there")
    return Row(cells, CheckStatus.FAIL, f"{what}; at {cells['outside']}, where the branches have {single.label} as "
                                        f"the one stable state (max|theta1| {math.degrees(single.theta1):.3g} deg), the "
                                        f"same kick ends at max|theta1| {math.degrees(run.theta1):.3g} deg")


FULL_JOB = "full_geometry_bistable_map"     # the background job's key (full verify)


def map_settings(ctx: Context) -> tuple[float, list[float], float, float]:
    """(grid step bar, grid pressures Pa, the stable-shimmy-free pressure's bisection tolerance Pa, each map's
    time budget s)."""
    step = QUICK_STEP_BAR if ctx.quick else STEP_BAR
    return (step, pressure_grid(ctx.axle.pressure_range_bar, step),
            (QUICK_XTOL_BAR if ctx.quick else STABLE_XTOL_BAR) * BAR, QUICK_BUDGET_S if ctx.quick else BUDGET_S)


def model_map(axle, model: Model, grid: list[float], xtol: float, budget_s: float | None = None,
              progress=lambda text: None) -> tuple[BistableMap, float]:
    """(the model's bistable map over ``grid`` within ``budget_s`` seconds, seconds it took)."""
    start = time.perf_counter()
    found = bistable_map(family_at(axle, model), grid, from_kmh(0.5), VMAX, model.label, xtol=xtol, progress=progress,
                         budget_s=budget_s)
    return found, time.perf_counter() - start


def start_full_map(ctx: Context) -> None:
    """Start the full geometry's map in a second process: its cycle branches at every grid pressure, continued on
    the MBS's compiled twin, overlap the sections before this one."""
    if ctx.background is not None:
        _, grid, xtol, budget = map_settings(ctx)
        ctx.background.submit(FULL_JOB, model_map, ctx.axle, Model.FULL, grid, xtol, budget)


def full_map(ctx: Context) -> tuple[BistableMap, float]:
    """The background job's map, or the same computed here when it was not started."""
    if ctx.background is not None and ctx.background.started(FULL_JOB):
        ctx.progress("Bistable regions: waiting for the full geometry's map (computed in a second process)")
        return ctx.background.result(FULL_JOB)
    _, grid, xtol, budget = map_settings(ctx)
    return model_map(ctx.axle, Model.FULL, grid, xtol, budget,
                     lambda text: ctx.progress(f"Bistable regions: {text}"))


def model_rows(ctx: Context, model: Model, found: BistableMap, seconds: float, step: float
               ) -> tuple[list[Row], BistableFact]:
    """The map's row and one kick-check row per region."""
    rows = [Row({"model": model.value, "grid_step_bar": step},
                CheckStatus.INFO if found.status.is_complete else CheckStatus.COULD_NOT_CHECK,
                f"{found.text()} ({seconds:.0f} s)")]
    for region in found.regions:
        ctx.progress(f"Bistable regions: kicks in {model.label} at {region.text()}")
        rows.append(region_row(ctx.axle, model, region, QUICK_KICK_TOL if ctx.quick else KICK_TOL))
    return rows, BistableFact(model, found)


def not_computed(model: Model, reason: str) -> tuple[list[Row], BistableFact]:
    return ([Row({"model": model.value}, CheckStatus.COULD_NOT_CHECK,
                 f"{model.label}'s map is not computed: {reason}")],
            BistableFact(model, None, reason))


def bistable_section(ctx: Context) -> Section:
    step, grid, xtol, budget = map_settings(ctx)
    rows: list[Row] = []
    facts = []
    found, seconds = model_map(ctx.axle, Model.REDUCED, grid, xtol, budget,
                               lambda text: ctx.progress(f"Bistable regions: {text}"))
    more, fact = model_rows(ctx, Model.REDUCED, found, seconds, step)
    rows += more
    facts.append(fact)
    try:
        more, fact = model_rows(ctx, Model.FULL, *full_map(ctx), step)
    except Exception as exc:      # a continuation that failed: said so, never read as "no region"
        more, fact = not_computed(Model.FULL, f"a continuation failed: {type(exc).__name__}: {interface_text(exc)}")
    rows += more
    facts.append(fact)
    return Section(
        key="bistable", title="Bistable regions: where a kick sets shimmy off",
        columns=("model", "grid_step_bar", "pressure_bar", "region_kmh", "inside_kmh", "kick_deg", "outside"),
        rows=tuple(rows),
        labels={"kick_deg": "smallest kick that leaves [deg]"},
        text=(f"Each model's cycle branches in speed on a grid of pressures {step:g} bar apart over the axle's "
              f"window (the full geometry's continued on its compiled twin, in a second process), each map within "
              f"{budget:g} s of wall clock; a region joins "
              f"the speed intervals where a stable cycle coexists with stable straight running "
              f"(or two stable cycles) from one grid pressure to the next. A region narrower in pressure than the "
              f"grid step can be missed, and an interval narrower than {kmh(MIN_WIDTH):g} km/h is not one. Each "
              f"region is checked by runs of the same model (the full geometry's by Exudyn): the smallest kick that "
              f"leaves straight running at the middle of its widest interval, then the same kick where the map has "
              f"one stable state ({OUTSIDE_KMH:g} km/h beyond the interval, else at the same speed on the grid "
              f"pressure beyond the region), where it must end on that state (a cycle's max|theta1| within "
              f"{100 * AMPLITUDE_TOL:g} %)."),
        verdict_facts=tuple(facts))
