"""``shimmy verify``: the full geometry's own shimmy (issue 16, item 5), at every planned case where either model
has a Hopf point.

The MBS with every assumption off is continued on Exudyn by the toolkit code the reduced model uses
(:class:`mbs_shimmy.linearisation.MbsFamily`), and what continuation finds is checked against the same model's
simulations: each Hopf point (with its first Lyapunov coefficient) is bracketed by a small oscillation that decays
on one side and grows on the other at the critical eigenvalue's real part (:mod:`comparisons.studies.growth`); stable orbits
are what long runs settle on, unstable ones are left, special points are bracketed by runs on either side
(:mod:`comparisons.verify.orbit_checks`).  The full geometry's bistable windows come from its own branches as the
plan finds the reduced model's (:func:`comparisons.studies.kick.bistable_windows`, straight running counted); in each, the
kick threshold (:mod:`comparisons.studies.kick`) is bracketed by two runs from straight running that end on the two
coexisting states.  Where there is none, the row says so with its evidence: criticality and folds.
"""

from __future__ import annotations

import time

from comparisons.verify.context import Context
from comparisons.verify.full_geometry_rows import (
    COLUMNS,
    QUICK_GROWTH_S,
    STABLE_PER_BRANCH,
    Where,
    branch_rows,
    branches_figure,
    hopf_rows,
    kick_rows,
    no_hopf_rows,
    window_rows,
)
from comparisons.verify.orbit_checks import LEFT_TOL, ORBIT_TOL
from comparisons.verify.other_axle import ONSET_TOLERANCE
from comparisons.verify.report import CheckStatus, Row, Section
from comparisons.studies.growth import DURATION
from bifurcation.equilibria.hopf import find_hopf_points


# --quick's budget for the full geometry's branches at its one case.  The paper's axle needs 30 cycles of at most 40
# mesh intervals (2.8 s); an axle whose orbits lift a wheel or reach walking pace needs up to 640 intervals and
# minutes.  The mesh and the count stop such a run early and alike on every machine; the time is the last resort.
QUICK_MAX_INTERVALS = 60
QUICK_MAX_CYCLES = 120
QUICK_BRANCH_BUDGET_S = 15.0


class _OverBudget(Exception):
    """The branches ran past --quick's budget."""


def _budget(seconds: float = QUICK_BRANCH_BUDGET_S):
    """An accept hook for :func:`cycle_diagram` that stops it at a cycle of more than :data:`QUICK_MAX_INTERVALS`
    mesh intervals, after :data:`QUICK_MAX_CYCLES` cycles, or once ``seconds`` have passed."""
    end, count = time.monotonic() + seconds, [0]

    def hook(cycle) -> None:
        count[0] += 1
        if (cycle.orbit.intervals > QUICK_MAX_INTERVALS or count[0] > QUICK_MAX_CYCLES
                or time.monotonic() > end):
            raise _OverBudget()
    return hook


def full_geometry_section(ctx: Context) -> Section:
    from comparisons.studies.kick import kicks, settle_function
    from bifurcation.cycles.branches import cycle_diagram
    rows, figures, recordings = [], [], []
    quick_text = " (quick mode: the first such case, with fewer runs and no ramps or kicks)" if ctx.quick else ""
    wheres = [Where.of_case(ctx.axle, c) for c in ctx.plan.cases]
    cases = []
    for where in wheres:
        family, reduced = where.family, where.reduced_family
        points = find_hopf_points(family, family.nominal, *where.speeds)
        if points or find_hopf_points(reduced, reduced.nominal, *where.speeds, lyapunov=False):
            cases.append((where, family, points, reduced))
    if ctx.quick:   # one case, its branches with fewer runs
        cases = [c for c in cases if c[2]][:1] or cases[:1]
    for case, family, points, reduced in cases:
        ctx.progress(f"Full geometry: Hopf points at {case.label}")
        duration = QUICK_GROWTH_S if ctx.quick else DURATION
        ctx.progress(f"Full geometry: cycle branches at {case.label}")
        try:
            full = cycle_diagram(family, family.nominal, *case.speeds,
                                 accept_hook=_budget() if ctx.quick else None)
        except _OverBudget:
            full = None
        rows += (hopf_rows(family, case, points, duration, full) if points else
                 no_hopf_rows(family, case, duration))
        if full is None:
            rows.append(Row({"case": case.label, "what": "cycle branches"}, CheckStatus.INFO,
                            f"skipped in quick mode: past its budget for them ({QUICK_MAX_INTERVALS} mesh intervals a "
                            f"cycle, {QUICK_MAX_CYCLES} cycles, {QUICK_BRANCH_BUDGET_S:g} s); the full verify "
                            f"continues them"))
            continue
        rows += branch_rows(family, case, full, lambda v, f=family: settle_function(f, v), quick=ctx.quick)
        ctx.progress(f"Full geometry: bistable windows at {case.label}")
        more, recorded, full_kicks = window_rows(ctx, family, case, full, runs=not ctx.quick)
        rows += more
        recordings += recorded
        if ctx.quick:
            continue
        reduced_diagram = cycle_diagram(reduced, reduced.nominal, *case.speeds)
        reduced_kicks = kicks(reduced, reduced_diagram)     # none unless the reduced model is bistable here
        rows += kick_rows(case, reduced_kicks, "reduced model")
        figures.append(branches_figure(ctx, case, reduced_diagram, reduced_kicks, [(full, full_kicks)]))
    if not ctx.quick:
        from comparisons.verify.other_axle import other_axle_results
        for result in other_axle_results(ctx):
            rows += result.rows
            recordings += result.recordings
            figures += result.figures
    if not cases:
        rows.append(Row({"what": "no Hopf point"}, CheckStatus.INFO,
                        "no planned case has a Hopf point in either model: nothing to continue"))
    return Section(
        key="full_geometry", title="The full geometry's own shimmy: continuation on the MBS against its simulations",
        columns=COLUMNS, rows=tuple(rows), figures=tuple(figures), recordings=tuple(recordings),
        text=(f"The MBS with every assumption off, continued on Exudyn, at every planned case where either model "
              f"has a Hopf point{quick_text}. "
              f"Checks against its own simulations: each Hopf point is bracketed by a small oscillation along the "
              f"mode crossing there, which decays on one side and grows on the other at Re of its eigenvalue; "
              f"stable orbits (up to {STABLE_PER_BRANCH} per branch, among those a 12 s run can decide by their "
              f"Floquet multipliers: not next to a Hopf point or fold) are what runs started 2 % inside them settle "
              f"on (max |theta1| and frequency to {ORBIT_TOL:.1%}); runs leave unstable orbits (end more than "
              f"{LEFT_TOL:.0%} away); cycle folds, torus and period-doubling points are bracketed by the nearest "
              f"cycles on either side (past a fold, a run on the fold's orbit must leave it). Bistable windows come "
              f"from the full geometry's own branches (straight running counted); in each, ramps up and down in "
              f"both models (information: a ramp's jump speed is not well posed) and the kick threshold "
              f"bracketed by two runs; where there is none, the row gives the criticality and the folds. At the "
              f"plan's bistable case on another axle (the paper's truck: t0 = 0.25 m) the whole 0-400 km/h diagram "
              f"costs too much: there the branches are continued from each subcritical Hopf point over the speeds "
              f"where straight running is stable, at collocation tolerance {ONSET_TOLERANCE:g}, in a second "
              f"process while the sections before this one run (two stable cycles coexisting away from a "
              f"subcritical Hopf point would not be found there). Figures: "
              f"both models' branches, max |theta1| against speed (stable solid, unstable dashed)."))
