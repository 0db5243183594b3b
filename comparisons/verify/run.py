"""``shimmy verify`` as a whole: the plan, then every section in turn (one failing section becomes a FAIL row, not
a crash), the report written at the end.
"""

from __future__ import annotations

import dataclasses
from typing import Callable

from axles.axle import AxleData, interface_text
from comparisons.verify.background import Background
from comparisons.verify.bistable_rows import start_full_map
from comparisons.verify.context import Context
from comparisons.verify.jump_experiments import start_jump_runs
from comparisons.verify.other_axle import start_other_axles
from comparisons.verify.plan import BOTH, Plan
from comparisons.verify.report import CheckStatus, Report, Row, Section
from comparisons.verify.sections import (
    assumptions_section,
    hopf_section,
    paper_section,
    plan_section,
    transient_section,
)


def sections_for(ctx: Context) -> list[tuple[str, Callable[[Context], Section]]]:
    from comparisons.verify.cycles import cycles_section, jumps_section
    steps = [("Plan", plan_section)]
    if ctx.axle.is_paper:
        steps.append(("Paper", paper_section))
    from comparisons.verify.margin_checks import margins_section
    steps += [("Hopf speeds", hopf_section), ("Stability margins", margins_section), ("Transient", transient_section),
              ("Limit cycles", cycles_section)]
    if ctx.plan.bistable:
        steps.append(("Bistable jumps", jumps_section))
    from comparisons.verify.bistable_rows import bistable_section
    steps.append(("Bistable regions", bistable_section))
    from comparisons.verify.full_geometry import full_geometry_section
    steps.append(("Full geometry", full_geometry_section))
    steps.append(("Assumptions", assumptions_section))
    from comparisons.verify.braking import braking_section
    steps.append(("Under braking", braking_section))
    from comparisons.verify.robustness import robustness_section
    steps.append(("Robustness", robustness_section))
    return steps


def make_plan(axle: AxleData, quick: bool, asymmetric: tuple[float, float] | None, from_file: bool,
              progress: Callable[[str], None], models=BOTH) -> Plan:
    """The paper's cases for the paper's truck (no axle file), a plan of its own otherwise; ``models``: which
    models are scanned (the reduced model alone where only its cases are needed)."""
    from comparisons.verify.plan import axle_plan, paper_plan
    if not from_file and axle.is_paper:
        return paper_plan(axle, asymmetric, quick, models, progress=progress)
    return axle_plan(axle, quick, asymmetric, progress=progress, models=models)


# Sections that collect a second process's work (comparisons/verify/background.py): computed after the others, so
# that the main process works while that process runs instead of waiting for it (in --quick the jumps' runs were a
# 15 s wait); the report keeps the order of sections_for.
COLLECTING = ("Bistable jumps", "Bistable regions", "Full geometry")


def computation_order(steps: list) -> list:
    """``steps`` with the sections that collect background work last, in their own order."""
    return ([s for s in steps if s[0] not in COLLECTING] + [s for s in steps if s[0] in COLLECTING])


def run_sections(ctx: Context, announce: Callable[[list[str]], None] | None = None) -> list[Section]:
    """Every section, those that collect background work last (:data:`COLLECTING`), returned in the report's
    order; one that raises becomes a FAIL row with its error.  ``announce(titles)`` is told the sections in the
    order they are computed before the first starts."""
    done: dict[str, Section] = {}
    report_order = sections_for(ctx)
    steps = computation_order(report_order)
    if announce is not None:
        announce([title for title, _ in steps])
    for title, make in steps:
        ctx.progress(f"{title}")      # the Plan's start was announced before the plan was made: kept
        try:
            section = make(ctx)
            if not section.rows:       # never an empty table that reads as passed
                section = dataclasses.replace(section, rows=(Row({}, CheckStatus.COULD_NOT_CHECK,
                                                                 "the section found nothing to compare"),))
            done[title] = section
        except Exception as exc:  # a failed sub-check is reported in the table, never swallowed
            error = f"{type(exc).__name__}: {interface_text(exc)}"
            done[title] = Section(key=title.lower().replace(" ", "_"), title=title, columns=("error",),
                                  rows=(Row({"error": error}, CheckStatus.FAIL,
                                            "a computation failed: the section could not be completed"),),
                                  text="This part of the verification could not be completed.")
        ctx.progress(f"done: {title}")
    return [done[title] for title, _ in report_order]


def run_verification(out: str, quick: bool, axle: AxleData | None = None, asymmetric: tuple[float, float] | None = None,
                     from_file: bool = False, recordings: bool = True,
                     progress: Callable[[str], None] | None = None,
                     announce: Callable[[list[str]], None] | None = None, braking=None) -> Report:
    """Plan, then run every section; a section that raises is reported as a FAIL row with its error.

    ``progress(message)`` is called as each step starts (and with "done: ..." as it ends); ``announce(titles)``
    with the sections' titles once the plan is made (a progress bar's total); ``braking``
    (:class:`~axles.braking.Braking`) replaces the "Under braking" section's planned levels."""
    from comparisons.verify.verdict import verdict_of
    progress = progress or (lambda message: None)
    axle = axle or AxleData()
    # The Plan step starts here, with the scans: its section only formats the plan made now (the steps to come
    # depend on the plan, so the first announcement names the Plan alone and the full list follows).
    if announce is not None:
        announce(["Plan"])
    progress("Plan")
    plan = make_plan(axle, quick, asymmetric, from_file, progress)
    verdict = verdict_of(plan)
    with Background() as background:   # jobs that overlap the sections on a second core
        ctx = Context(out=out, quick=quick, axle=axle, plan=plan, recordings=recordings, progress=progress,
                      background=background, braking=braking)
        start_jump_runs(ctx)
        start_other_axles(ctx)
        start_full_map(ctx)
        sections = run_sections(ctx, announce)
    from comparisons.verify.bistable_rows import BistableFact
    from comparisons.verify.verdict import RobustnessShare
    facts = [f for s in sections for f in s.verdict_facts]
    shares = tuple(f for f in facts if isinstance(f, RobustnessShare))
    bistable = tuple(f for f in facts if isinstance(f, BistableFact))
    margins = tuple(f for f in facts if not isinstance(f, (RobustnessShare, BistableFact)))
    return Report(sections=tuple(sections), quick=quick, plan=plan, axle=axle,
                  verdict=dataclasses.replace(verdict, margins=verdict.margins + margins,
                                              robustness=verdict.robustness + shares,
                                              bistable=verdict.bistable + bistable))
