"""``shimmy verify``: the full geometry at the plan's bistable case on another axle (the paper's truck: t0 = 0.25 m,
1.5 bar), continued on Exudyn in a second process while the sections before it run
(:mod:`comparisons.verify.background`).

Its whole 0-400 km/h diagram is beyond verify's budget (at t0 = 0.25 m, 190-210 km/h alone took 22 min: the
stable cycles below 194 km/h need up to 413 intervals).  Its branches are continued where a bistable window beside
straight running lies: a subcritical Hopf point's unstable cycles grow on the side where straight running is stable,
and the window reaches from the Hopf point to their cycle fold.  So each subcritical Hopf point is continued over the
speeds on its stable side, up to the next Hopf point, and :data:`PAST_HOPF_KMH` past itself, where the stable
cycles coming back from the fold leave the window.  Two stable cycles coexisting away from any subcritical Hopf
point would not be found: the section's text says so.  These branches are continued at the collocation tolerance
:data:`ONSET_TOLERANCE` (1e-6 elsewhere): at t0 = 0.25 m their fold moves by 0.08 km/h against 1e-6
(docs/results.md), at a third of the cost.

Each branch then gets the checks of :mod:`comparisons.verify.full_geometry_rows`: orbits against the full geometry's own
simulations, its special points bracketed, its bistable windows with ramps through them in both models (side by
side recordings ``full_*``) and the kick threshold bracketed by two runs from straight running.
"""

from __future__ import annotations

import os
from dataclasses import dataclass

from axles.units import from_kmh, kmh
from comparisons.verify.context import Context
from comparisons.verify.plan import BistableCase
from comparisons.verify.report import CheckStatus, Row

ONSET_TOLERANCE = 1e-5
PAST_HOPF_KMH = 0.15      # how far past its subcritical Hopf point a branch is followed
JOB = "other_axles"       # the background job's key


@dataclass(frozen=True)
class OtherAxleResult:
    rows: tuple[Row, ...]
    recordings: tuple[str, ...]
    figures: tuple[str, ...]


def full_geometry_at(case: BistableCase, out: str, recordings: bool) -> OtherAxleResult:
    """Everything the section reports at one bistable case on another axle; the background job."""
    from comparisons.verify.full_geometry_rows import Where, branch_rows, branches_figure, hopf_rows, window_rows
    from comparisons.verify.jump_experiments import bistable_diagram
    from comparisons.verify.plan import VMAX
    from comparisons.studies.growth import DURATION
    from comparisons.studies.kick import kicks, settle_function
    from comparisons.studies.onset import onset_windows
    from bifurcation.cycles.branches import cycle_diagram
    from bifurcation.cycles.problem import CycleSettings
    from bifurcation.equilibria.hopf import find_hopf_points
    ctx = Context(out=out, quick=False, axle=case.axle, recordings=recordings)
    where = Where.of_bistable(case)
    family = where.family
    points = find_hopf_points(family, family.nominal, 0.0, VMAX)
    rows = hopf_rows(family, where, points, DURATION)
    windows = onset_windows(family, family.nominal, points, family.primary_min, VMAX, from_kmh(PAST_HOPF_KMH))
    crit = ", ".join(f"{kmh(h.p):.2f} km/h {h.criticality.value if h.criticality else 'undetermined'}"
                     for h in points) or "none"
    if not windows:
        rows.append(Row({"case": where.label, "what": "cycle branches"}, CheckStatus.INFO,
                        f"not continued: no subcritical Hopf point of the full geometry (Hopf points: {crit}), so "
                        f"no bistable window beside straight running"))
        return OtherAxleResult(tuple(rows), (), ())
    reduced = where.reduced_family
    reduced_diagram = bistable_diagram(case)
    reduced_kicks = kicks(reduced, reduced_diagram)
    found_recordings, figures, full = [], [], []
    for a, b in windows:
        ctx_where = Where(f"{where.label}, {kmh(a):.2f}-{kmh(b):.2f} km/h", case.axle, where.pressures,
                          where.pressure_bar, (a, b), where.overrides)
        rows.append(Row({"case": ctx_where.label, "what": "cycle branches"}, CheckStatus.INFO,
                        f"continued from the subcritical Hopf point over its stable side only, at collocation "
                        f"tolerance {ONSET_TOLERANCE:g} (Hopf points over 0-{kmh(VMAX):.0f} km/h: {crit})"))
        diagram = cycle_diagram(family, family.nominal, a, b, CycleSettings(tolerance=ONSET_TOLERANCE))
        rows += branch_rows(family, ctx_where, diagram, lambda v, f=family: settle_function(f, v))
        more, recorded, full_kicks = window_rows(ctx, family, ctx_where, diagram)
        rows += more
        found_recordings += recorded
        full.append((diagram, full_kicks))
    figures.append(branches_figure(ctx, where, reduced_diagram, reduced_kicks, full))
    return OtherAxleResult(tuple(rows), tuple(found_recordings), tuple(figures))


def start_other_axles(ctx: Context) -> None:
    """Start the full geometry at the plan's bistable cases on other axles in the background (full mode)."""
    cases = other_cases(ctx)
    if cases and ctx.background is not None and not ctx.quick:
        ctx.background.submit(JOB, other_axles_job, cases, ctx.out, ctx.recordings)


def other_cases(ctx: Context) -> tuple[BistableCase, ...]:
    return tuple(b for b in ctx.plan.bistable if b.axle.overrides != ctx.axle.overrides)


def other_axles_job(cases: tuple[BistableCase, ...], out: str, recordings: bool) -> list[OtherAxleResult]:
    os.makedirs(out, exist_ok=True)
    return [full_geometry_at(case, out, recordings) for case in cases]


def other_axle_results(ctx: Context) -> list[OtherAxleResult]:
    """The background job's results, or the same computed here when it was not started."""
    if ctx.background is not None and ctx.background.started(JOB):
        ctx.progress("Full geometry: waiting for the other axle's branches (continued in a second process)")
        return ctx.background.result(JOB)
    return other_axles_job(other_cases(ctx), ctx.out, ctx.recordings)
