"""``shimmy verify``: the full geometry's own shimmy (issue 16, item 5), at every planned case where either model
has a Hopf point.

The MBS with every assumption off is continued on Exudyn by the toolkit code the reduced model uses
(:class:`mbs_shimmy.linearisation.MbsFamily`), and what continuation finds is checked against the same model's
simulations: each Hopf point (with its first Lyapunov coefficient) is bracketed by a small oscillation that decays
on one side and grows on the other at the critical eigenvalue's real part (:mod:`mbs_shimmy.growth`); stable orbits
are what long runs settle on, unstable ones are left, special points are bracketed by runs on either side
(:mod:`comparisons.verify.orbit_checks`).  The full geometry's bistable windows come from its own branches as the
plan finds the reduced model's (:func:`mbs_shimmy.kick.bistable_windows`, straight running counted); in each, the
kick threshold (:mod:`mbs_shimmy.kick`) is bracketed by two runs from straight running that end on the two
coexisting states.  Where there is none, the row says so with its evidence: criticality and folds.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass

import numpy as np

from comparisons.axles.axle import Axle, interface_text
from comparisons.axles.units import BAR, from_kmh, kmh
from comparisons.verify.context import Context
from comparisons.verify.orbit_checks import (
    LEFT_TOL,
    ORBIT_TOL,
    bracket_special_point,
    check_orbit,
    sample_orbits,
)
from comparisons.verify.plan import VMAX, BistableCase
from comparisons.verify.report import CheckStatus, Row, Section
from mbs_shimmy.growth import DURATION
from reduced_model.bifurcation.equilibria.hopf import hopf_points
from reduced_model.bifurcation.special_points import PointKind
from reduced_model.family import SpeedFamily
from reduced_model.model import ShimmyModel

QUICK_GROWTH_S = 2.0      # s of each growth run in quick mode (4 s otherwise: mbs_shimmy.growth.DURATION)
HOPF_OFFSET_KMH = 4.0     # where each Hopf point is bracketed (less where two Hopf points are closer)
STABLE_BUDGET = 12        # stable-orbit runs over all branches of a case (at most STABLE_PER_BRANCH each)
STABLE_PER_BRANCH = 6
UNSTABLE_PER_BRANCH = 2

COLUMNS = ("case", "what", "speed_kmh", "criticality", "first_lyapunov", "eigenvalue_real", "envelope_rate",
           "continuation_theta1_deg", "simulation_theta1_deg", "theta1_diff", "continuation_hz", "simulation_hz",
           "frequency_diff", "kick_deg", "window_end_kmh", "reduced_jump_kmh")


@dataclass(frozen=True)
class Where:
    """One case of the section: an axle at tyre pressure(s), with its label in the report."""

    label: str
    axle: Axle
    pressure: float | tuple[float, float]    # Pa
    pressure_bar: float | None               # both tyres alike: the pressure in bar (the ramps need it)
    speeds: tuple[float, float] = (0.0, VMAX)   # m/s: the window the branches are continued in

    @classmethod
    def of_case(cls, axle: Axle, case) -> "Where":
        alike = case.pressure_right_bar == case.pressure_left_bar
        return cls(case.label, axle, case.pressure, case.pressure_right_bar if alike else None)

    @classmethod
    def of_bistable(cls, case: BistableCase) -> "Where":
        changed = ", ".join(f"{k} = {v:g}" for k, v in case.axle.overrides)
        return cls(f"{case.pressure_bar:g} bar" + (f", {changed}" if changed else ""), case.axle,
                   case.pressure_bar * BAR, case.pressure_bar)

    @property
    def family(self):
        from mbs_shimmy.fidelity import Fidelity
        from mbs_shimmy.linearisation import MbsFamily
        model = ShimmyModel(params=self.axle.params)
        return MbsFamily.of(model.params, model.effects, Fidelity.full(), dims=self.axle.dims,
                            pressure=self.pressure)

    @property
    def reduced_family(self) -> SpeedFamily:
        return SpeedFamily(ShimmyModel(params=self.axle.params), pressure=self.pressure)


def _finite(x: float) -> float | None:
    return float(x) if x is not None and math.isfinite(x) else None


def _deg(x: float) -> float | None:
    return _finite(math.degrees(x)) if x is not None and math.isfinite(x) else None


def hopf_offsets(speeds: list[float]) -> list[float]:
    """How far (m/s) beside each Hopf point it is bracketed: HOPF_OFFSET_KMH, or less than half the gap to the
    next one."""
    out = []
    for i, v in enumerate(speeds):
        gaps = [abs(v - w) for j, w in enumerate(speeds) if j != i]
        out.append(min([from_kmh(HOPF_OFFSET_KMH)] + [0.4 * g for g in gaps]))
    return out


def hopf_rows(family, case, points, duration: float) -> list[Row]:
    """Each Hopf point with l1, and the two simulations that bracket it: along the mode that crosses there, one
    decays and the other grows, each at the real part of that mode's eigenvalue."""
    from mbs_shimmy.growth import RATE_TOL, envelope_rate
    rows = []
    for i, (h, off) in enumerate(zip(points, hopf_offsets([h.p for h in points])), 1):
        rows.append(Row({"case": case.label, "what": f"HB{i}", "speed_kmh": kmh(h.p),
                         "criticality": h.criticality.value if h.criticality else None,
                         "first_lyapunov": _finite(h.first_lyapunov), "continuation_hz": h.frequency_hz},
                        CheckStatus.INFO, f"Hopf point of the full geometry at {h.frequency_hz:.2f} Hz"))
        sides = [envelope_rate(family, max(from_kmh(1.0), h.p + s * off), duration, near=1j * h.omega)
                 for s in (-1.0, 1.0)]
        apart = sides[0].rate * sides[1].rate < 0.0
        for side, rate in zip(("below", "above"), sides):
            ok = rate.agrees and apart
            rows.append(Row({"case": case.label, "what": f"HB{i}, {abs(kmh(rate.speed - h.p)):.1f} km/h {side}",
                             "speed_kmh": kmh(rate.speed), "eigenvalue_real": rate.real,
                             "envelope_rate": _finite(rate.rate)},
                            CheckStatus.PASS if ok else CheckStatus.FAIL,
                            ("decays" if rate.rate < 0 else "grows") + f" at Re of the crossing mode's eigenvalue "
                            f"(to {RATE_TOL:g} 1/s)" if ok else
                            "the simulation's envelope rate does not follow the eigenvalue, or does not change "
                            "sign across the Hopf point"))
    return rows


def no_hopf_rows(family, case, duration: float) -> list[Row]:
    """No Hopf point of the full geometry: the least-damped mode at its weakest speed decays, at its rate."""
    from mbs_shimmy.growth import envelope_rate
    speeds = np.linspace(max(from_kmh(5.0), case.speeds[0]), case.speeds[1], 80)
    weakest = max(speeds, key=lambda v: max(np.linalg.eigvals(family.linear_matrix(v, family.nominal)).real))
    rate = envelope_rate(family, float(weakest), duration)
    ok = rate.agrees and rate.real < 0.0
    span = f"{kmh(case.speeds[0]):.0f}-{kmh(case.speeds[1]):.0f} km/h"
    return [Row({"case": case.label, "what": f"no Hopf point ({span}); weakest mode",
                 "speed_kmh": kmh(rate.speed), "eigenvalue_real": rate.real, "envelope_rate": _finite(rate.rate)},
                CheckStatus.PASS if ok else CheckStatus.FAIL,
                "straight running is stable at every speed: at the least-damped speed a small oscillation decays "
                "at Re of the eigenvalue" if ok else "the least-damped mode does not decay at its eigenvalue")]


def _orbit_row(case, what: str, check) -> Row:
    stays = check.expect_stays
    cells = {"case": case.label, "what": what, "speed_kmh": kmh(check.speed),
             "continuation_theta1_deg": math.degrees(check.cycle.max_abs("theta1")),
             "simulation_theta1_deg": _deg(check.run.theta1), "theta1_diff": _finite(check.theta1_diff),
             "continuation_hz": check.cycle.frequency_hz, "simulation_hz": _finite(check.run.frequency_hz)}
    if stays:
        cells["frequency_diff"] = _finite(check.frequency_diff)
    return Row(cells, CheckStatus.PASS if check.ok else CheckStatus.FAIL, check.verdict)


def branch_rows(family, case, diagram, settle) -> list[Row]:
    rows = []
    stable_branches = sum(any(p.stable for p in b.points) for b in diagram.branches)
    per_branch = max(1, min(STABLE_PER_BRANCH, STABLE_BUDGET // max(1, stable_branches)))
    for b, branch in enumerate(diagram.branches, 1):
        where = f"branch {b} from {kmh(branch.start.p):.2f} km/h"
        stable = sum(p.stable for p in branch.points)
        peak = branch.peak("theta1") if branch.points else None
        rows.append(Row({"case": case.label, "what": where,
                         "speed_kmh": kmh(peak.p) if peak else None,
                         "continuation_theta1_deg": math.degrees(peak.max_abs("theta1")) if peak else None,
                         "continuation_hz": peak.frequency_hz if peak else None},
                        CheckStatus.INFO if branch.complete else CheckStatus.FAIL,
                        f"{len(branch.points)} cycles, {stable} stable; peak shown; "
                        f"{interface_text(branch.message)}" if branch.complete else
                        f"continuation stopped: {interface_text(branch.message)}"))
        for point in sample_orbits(branch, per_branch, stable=True):
            rows.append(_orbit_row(case, f"{where}: stable orbit", check_orbit(settle, point)))
        for point in sample_orbits(branch, UNSTABLE_PER_BRANCH, stable=False):
            rows.append(_orbit_row(case, f"{where}: unstable orbit", check_orbit(settle, point)))
        for s in sorted(branch.special_points, key=lambda s: s.p):
            name = s.kind.value
            rows.append(Row({"case": case.label, "what": f"{where}: {name}", "speed_kmh": kmh(s.p),
                             "continuation_theta1_deg": math.degrees(s.data["amplitude"][0])},
                            CheckStatus.INFO, f"{name} of the cycles ({s.status.value})"))
            for side, check in bracket_special_point(settle, branch, s):
                rows.append(_orbit_row(case, f"{where}: {name}, {side}", check))
    return rows


def window_rows(ctx: Context, family, case: Where, diagram) -> tuple[list[Row], list[str], list]:
    """The full geometry's bistable windows with the ramps through them and their kick thresholds, or why there
    is none; (rows, recording names, kick thresholds)."""
    from comparisons.verify.full_jumps import jump_rows
    from mbs_shimmy.kick import bistable_windows, kicks
    windows = bistable_windows(diagram, family)
    if not windows:
        crit = ", ".join(f"{kmh(h.p):.2f} km/h {h.criticality.value if h.criticality else 'undetermined'}"
                         for h in diagram.hopf) or "none"
        folds = diagram.points_of(PointKind.CYCLE_FOLD)
        fold_text = ", ".join(f"{kmh(s.p):.2f} km/h" for s in folds) or "none"
        return [Row({"case": case.label, "what": "bistable window: none"}, CheckStatus.INFO,
                    f"no two stable states coexist at any speed: Hopf points {crit}; cycle folds {fold_text}; "
                    f"no two stable stretches of the branches overlap")], [], []
    rows = [Row({"case": case.label, "what": f"bistable window {kmh(a):.2f}-{kmh(b):.2f} km/h",
                 "speed_kmh": kmh(0.5 * (a + b))}, CheckStatus.INFO,
                "two stable states coexist (from the full geometry's own branches)") for a, b in windows]
    recordings = []
    if case.pressure_bar is None:
        rows.append(Row({"case": case.label, "what": "ramps"}, CheckStatus.INFO,
                        "not run: the ramps are made with both tyres alike"))
    else:
        bistable = BistableCase(case.axle, case.pressure_bar, kmh(windows[0][0]), kmh(windows[0][1]),
                                "the full geometry's window", diagram)
        more, recordings = jump_rows(ctx, case.label, bistable, family, diagram, windows)
        rows += more
    found = kicks(family, diagram)
    rows += kick_rows(case, found, "full geometry", "continuation_theta1_deg")
    return rows, recordings, found


def kick_rows(case: Where, found, model: str, unstable_column: str | None = None) -> list[Row]:
    """A row per kick threshold of one model at this case (:mod:`comparisons.verify.kick_rows`)."""
    from comparisons.verify.kick_rows import kick_verdict
    rows = []
    for kick in found:
        cells, status, text = kick_verdict(kick, model)
        cells = {"case": case.label, "what": f"kick threshold ({model}): {kick.lower.label} -> {kick.upper.label}",
                 "speed_kmh": kmh(kick.speed), **cells}
        if unstable_column:
            cells[unstable_column] = math.degrees(kick.unstable_theta1)
        rows.append(Row(cells, status, text))
    return rows


def _figure(ctx: Context, case: Where, reduced, full, reduced_kicks=(), full_kicks=()) -> str:
    from comparisons.figures.cycle_plots import plot_model_branches
    tag = "".join(c for c in case.label.replace(".", "p").replace("/", "_") if c.isalnum() or c in "_p")
    name = f"full_geometry_{tag}.png"
    plot_model_branches([("reduced model", reduced, "C0", reduced_kicks),
                         ("full geometry, MBS", full, "C3", full_kicks)],
                        os.path.join(ctx.out, name),
                        title=f"Limit cycles at {case.label}: reduced model and full geometry")
    return name


def other_axle_rows(ctx: Context) -> list[Row]:
    """The plan's bistable case on another axle (the paper's: t0 = 0.25 m): the full geometry's Hopf points with
    their brackets, and a row saying its branches are not continued."""
    rows = []
    for b in ctx.plan.bistable:
        if b.axle.overrides == ctx.axle.overrides:
            continue
        where = Where.of_bistable(b)
        family = where.family
        ctx.progress(f"Full geometry: Hopf points at {where.label}")
        rows += hopf_rows(family, where, hopf_points(family, family.nominal, *where.speeds), DURATION)
        rows.append(Row({"case": where.label, "what": "cycle branches"}, CheckStatus.INFO,
                        "not continued at the plan's bistable case on another axle: its full-geometry branches cost "
                        "more than verify's budget (190-210 km/h alone: 36 cycles in 22 min, the stable ones below "
                        "194 km/h on up to 413 intervals); its window near the subcritical Hopf point and its kick: "
                        "'.venv/bin/shimmy cycles --model mbs --fidelity full --pressure 1.5 --set t0=0.25 "
                        "--vmin 194.5 --vmax 206 --tolerance 1e-5 --kick' (about 3 min)"))
    return rows


def full_geometry_section(ctx: Context) -> Section:
    from mbs_shimmy.kick import kicks, settle_function
    from reduced_model.bifurcation.cycles.branches import cycle_diagram
    rows, figures, recordings = [], [], []
    wheres = [Where.of_case(ctx.axle, c) for c in ctx.plan.cases]
    cases = []
    for where in wheres:
        family, reduced = where.family, where.reduced_family
        points = hopf_points(family, family.nominal, *where.speeds)
        if points or hopf_points(reduced, reduced.nominal, *where.speeds, lyapunov=False):
            cases.append((where, family, points, reduced))
    if ctx.quick:   # one case, Hopf points only: the branches cost minutes
        cases = [c for c in cases if c[2]][:1] or cases[:1]
    for case, family, points, reduced in cases:
        ctx.progress(f"Full geometry: Hopf points at {case.label}")
        duration = QUICK_GROWTH_S if ctx.quick else DURATION
        rows += hopf_rows(family, case, points, duration) if points else no_hopf_rows(family, case, duration)
        if ctx.quick:
            rows.append(Row({"case": case.label, "what": "cycle branches"}, CheckStatus.INFO,
                            "skipped in quick mode (a branch of the full geometry costs minutes)"))
            continue
        ctx.progress(f"Full geometry: cycle branches at {case.label} (minutes)")
        full = cycle_diagram(family, family.nominal, *case.speeds)
        rows += branch_rows(family, case, full, lambda v, f=family: settle_function(f, v))
        ctx.progress(f"Full geometry: bistable windows at {case.label}")
        more, recorded, full_kicks = window_rows(ctx, family, case, full)
        rows += more
        recordings += recorded
        reduced_diagram = cycle_diagram(reduced, reduced.nominal, *case.speeds)
        reduced_kicks = kicks(reduced, reduced_diagram)     # none unless the reduced model is bistable here
        rows += kick_rows(case, reduced_kicks, "reduced model")
        figures.append(_figure(ctx, case, reduced_diagram, full, reduced_kicks, full_kicks))
    if not ctx.quick:
        rows += other_axle_rows(ctx)
    if not cases:
        rows.append(Row({"what": "no Hopf point"}, CheckStatus.INFO,
                        "no planned case has a Hopf point in either model: nothing to continue"))
    return Section(
        key="full_geometry", title="The full geometry's own shimmy: continuation on the MBS against its simulations",
        columns=COLUMNS, rows=tuple(rows), figures=tuple(figures), recordings=tuple(recordings),
        text=(f"The MBS with every assumption off, continued on Exudyn, at every planned case where either model "
              f"has a Hopf point{' (quick mode: the first such case, Hopf points only)' if ctx.quick else ''}. "
              f"Checks against its own simulations: each Hopf point is bracketed by a small oscillation along the "
              f"mode crossing there, which decays on one side and grows on the other at Re of its eigenvalue; "
              f"stable orbits (up to {STABLE_PER_BRANCH} per branch, among those a 12 s run can decide by their "
              f"Floquet multipliers: not next to a Hopf point or fold) are what runs started 2 % inside them settle "
              f"on (max |theta1| and frequency to {ORBIT_TOL:.1%}); runs leave unstable orbits (end more than "
              f"{LEFT_TOL:.0%} away); cycle folds, torus and period-doubling points are bracketed by the nearest "
              f"cycles on either side (past a fold, a run on the fold's orbit must leave it). Bistable windows come "
              f"from the full geometry's own branches (straight running counted); in each, ramps up and down in "
              f"both models (the full geometry must jump at or past the window's ends) and the kick threshold "
              f"bracketed by two runs; where there is none, the row gives the criticality and the folds. Figures: "
              f"both models' branches, max |theta1| against speed (stable solid, unstable dashed)."))
