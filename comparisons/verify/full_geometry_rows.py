"""The rows of ``verify``'s ``full_geometry`` section (:mod:`comparisons.verify.full_geometry`) and their checks:
the full geometry's Hopf points bracketed by growth runs, its branches' orbits and special points against its own
simulations, its bistable windows with ramps and kicks, and the figure of both models' branches at a case.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass

import numpy as np

from axles.axle import AxleData, interface_text
from axles.pressures import TyrePressures
from axles.units import BAR, from_kmh, kmh
from comparisons.verify.context import Context
from comparisons.verify.file_names import case_file_name
from comparisons.verify.orbit_checks import (
    bracket_special_point,
    check_orbit,
    sample_orbits,
    undecided_sides,
)
from comparisons.verify.plan import VMAX, BistableCase
from comparisons.verify.report import CheckStatus, Row
from comparisons.studies.limit_cycle import SETTLE
from bifurcation.special_points import PointKind
from comparisons.studies.onset import branch_onset, has_kink, onset_criticality
from reduced_model.family import SpeedFamily

QUICK_GROWTH_S = 2.0      # s of each growth run in quick mode (4 s otherwise: comparisons.studies.growth.DURATION)
HOPF_OFFSET_KMH = 4.0     # where each Hopf point is bracketed (less where two Hopf points are closer)
STABLE_BUDGET = 12        # stable-orbit runs over all branches of a case (at most STABLE_PER_BRANCH each)
STABLE_PER_BRANCH = 6
UNSTABLE_PER_BRANCH = 2
QUICK_STABLE_PER_BRANCH = 1    # --quick: the branches cost seconds on the twin, the runs that check them more
MIN_WINDOW_KMH = 0.5      # narrower bistable windows (next to a degenerate Hopf point) get no ramps and no kick

COLUMNS = ("case", "what", "speed_kmh", "criticality", "first_lyapunov", "eigenvalue_real", "envelope_rate",
           "continuation_theta1_deg", "simulation_theta1_deg", "theta1_diff", "continuation_hz", "simulation_hz",
           "frequency_diff", "kick_deg", "window_end_kmh", "reduced_jump_kmh")


@dataclass(frozen=True)
class Where:
    """One case of the section: an axle at tyre pressure(s), with its label in the report."""

    label: str
    axle: AxleData
    pressures: TyrePressures
    pressure_bar: float | None               # both tyres alike: the pressure in bar (the ramps need it)
    speeds: tuple[float, float] = (0.0, VMAX)   # m/s: the window the branches are continued in
    overrides: tuple = ()                    # the axle's entries that the label names ((name, interface value))

    @classmethod
    def of_case(cls, axle: AxleData, case) -> "Where":
        alike = case.pressure_right_bar == case.pressure_left_bar
        return cls(case.label, axle, case.pressures, case.pressure_right_bar if alike else None)

    @classmethod
    def of_bistable(cls, case: BistableCase) -> "Where":
        changed = ", ".join(f"{k} = {v:g}" for k, v in case.axle.overrides)
        return cls(f"{case.pressure_bar:g} bar" + (f", {changed}" if changed else ""), case.axle,
                   TyrePressures.uniform(case.pressure_bar * BAR), case.pressure_bar,
                   overrides=tuple(case.axle.overrides))

    @property
    def shown(self) -> str:
        """The case for a figure: its pressures and the axle entries the label names, each with its unit."""
        from axles.axle import interface_unit
        changed = "".join(f", {k} = {v:g} {interface_unit(k)[0]}" for k, v in self.overrides)
        return self.label.split(",")[0] + changed

    @property
    def family(self):
        from comparisons.api import Axle
        return Axle(self.axle).mbs(fidelity="full").problem(self.pressures)

    @property
    def reduced_family(self) -> SpeedFamily:
        from comparisons.api import Axle
        return Axle(self.axle).reduced().problem(self.pressures)


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


def hopf_rows(family, case, points, duration: float, diagram=None) -> list[Row]:
    """Each Hopf point with l1 (and with ``diagram``, what its cycle branch says: :func:`branch_onset`), and the two
    simulations that bracket it: along the mode that crosses there, one decays and the other grows, each at the
    real part of that mode's eigenvalue."""
    from comparisons.studies.growth import RATE_TOL, envelope_rate
    from mbs_shimmy.linearisation import L1_NOT_WELL_POSED
    rows = []
    kinked = bool(points) and has_kink(family, points[0])
    for i, (h, off) in enumerate(zip(points, hopf_offsets([h.p for h in points])), 1):
        onset = branch_onset(diagram, h)
        criticality, _ = onset_criticality(h, onset, kinked)
        rows.append(Row({"case": case.label, "what": f"HB{i}", "speed_kmh": kmh(h.p),
                         "criticality": criticality.value if criticality else None,
                         "first_lyapunov": _finite(h.first_lyapunov), "continuation_hz": h.frequency_hz},
                        CheckStatus.INFO, "; ".join(
                            [f"Hopf point of the full geometry at {h.frequency_hz:.2f} Hz"]
                            + ([L1_NOT_WELL_POSED + " (the criticality column is the branch's)"] if kinked else [])
                            + ([onset.text] if onset else []))))
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
    from comparisons.studies.growth import envelope_rate
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


def branch_rows(family, case, diagram, settle, quick: bool = False) -> list[Row]:
    """A row per branch, then its orbits and special points each checked by runs; ``quick``: at most
    :data:`QUICK_STABLE_PER_BRANCH` stable orbits and one unstable one per branch."""
    rows = []
    stable_branches = sum(any(p.stable for p in b.points) for b in diagram.branches)
    per_branch = max(1, min(STABLE_PER_BRANCH, STABLE_BUDGET // max(1, stable_branches)))
    if quick:
        per_branch = min(per_branch, QUICK_STABLE_PER_BRANCH)
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
        for point in sample_orbits(branch, 1 if quick else UNSTABLE_PER_BRANCH, stable=False):
            rows.append(_orbit_row(case, f"{where}: unstable orbit", check_orbit(settle, point)))
        for s in sorted(branch.special_points, key=lambda s: s.p):
            name = s.kind.value
            rows.append(Row({"case": case.label, "what": f"{where}: {name}", "speed_kmh": kmh(s.p),
                             "continuation_theta1_deg": math.degrees(s.data["amplitude"][0])},
                            CheckStatus.INFO, f"{name} of the cycles ({s.status.value})"))
            for side, check in bracket_special_point(settle, branch, s):
                rows.append(_orbit_row(case, f"{where}: {name}, {side}", check))
            for side in undecided_sides(branch, s):
                rows.append(Row({"case": case.label, "what": f"{where}: {name}, {side}"}, CheckStatus.INFO,
                                f"not run: the computed cycles next to it have a Floquet multiplier so near 1 that a "
                                f"{SETTLE:g} s run cannot decide"))
    return rows


def _onset_text(family, diagram, h) -> str:
    """'39.23 km/h supercritical by its branch (the cycles born there are stable)' for the no-window row; by l1
    only where l1 is well posed."""
    onset = branch_onset(diagram, h)
    criticality, by = onset_criticality(h, onset, has_kink(family, h))
    text = f"{kmh(h.p):.2f} km/h {criticality.value if criticality else 'undetermined'} by " + (
        "l1" if by == "l1" else "its branch")
    if onset is not None:
        text += f" ({onset.text if by == 'l1' else onset.detail})"
    return text


def window_rows(ctx: Context, family, case: Where, diagram, runs: bool = True) -> tuple[list[Row], list[str], list]:
    """The full geometry's bistable windows with the ramps through them and their kick thresholds (not with
    ``runs`` False: the windows alone), or why there is none; (rows, recording names, kick thresholds)."""
    from comparisons.verify.full_jumps import jump_rows
    from comparisons.studies.kick import bistable_windows, kicks
    windows = bistable_windows(diagram, family)
    if not windows:
        crit = ", ".join(_onset_text(family, diagram, h) for h in diagram.hopf) or "none"
        folds = diagram.points_of(PointKind.CYCLE_FOLD)
        fold_text = ", ".join(f"{kmh(s.p):.2f} km/h" for s in folds) or "none"
        return [Row({"case": case.label, "what": "bistable window: none"}, CheckStatus.INFO,
                    f"no two stable states coexist at any speed: Hopf points {crit}; cycle folds {fold_text}; "
                    f"no two stable stretches of the branches overlap")], [], []
    rows = [Row({"case": case.label, "what": f"bistable window {kmh(a):.2f}-{kmh(b):.2f} km/h",
                 "speed_kmh": kmh(0.5 * (a + b))}, CheckStatus.INFO,
                "two stable states coexist (from the full geometry's own branches)"
                + ("" if kmh(b - a) >= MIN_WINDOW_KMH else
                   f"; narrower than {MIN_WINDOW_KMH:g} km/h, which the ramps (1 km/h per s) and a kick cannot "
                   f"resolve: neither is run")) for a, b in windows]
    windows = [(a, b) for a, b in windows if kmh(b - a) >= MIN_WINDOW_KMH]
    recordings = []
    if not windows:
        return rows, [], []
    if not runs:
        rows.append(Row({"case": case.label, "what": "ramps and kick"}, CheckStatus.INFO,
                        "not run in quick mode"))
        return rows, [], []
    if case.pressure_bar is None:
        rows.append(Row({"case": case.label, "what": "ramps"}, CheckStatus.INFO,
                        "not run: the ramps are made with both tyres alike"))
    else:
        bistable = BistableCase(case.axle, case.pressure_bar, kmh(windows[0][0]), kmh(windows[0][1]),
                                "the full geometry's window", diagram)
        more, recordings = jump_rows(ctx, case.label, bistable, family, diagram, windows)
        rows += more
    found = kicks(family, diagram, from_kmh(MIN_WINDOW_KMH))
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


def branches_figure(ctx: Context, case: Where, reduced, reduced_kicks, full) -> str:
    """Both models' branches at one case; ``full``: the full geometry's (diagram, kicks), one per window it was
    continued in."""
    from comparisons.figures.cycle_plots import plot_model_branches
    name = case_file_name("full_geometry", "png", case.pressures.right / BAR, case.pressures.left / BAR,
                          case.overrides)
    several = len(full) > 1
    plot_model_branches([("reduced model", reduced, "C0", reduced_kicks)] +
                        [("full geometry, MBS" + (f" ({kmh(d.p_min):.1f}-{kmh(d.p_max):.1f} km/h)" if several else ""),
                          d, f"C{3 + i}", k) for i, (d, k) in enumerate(full)],
                        os.path.join(ctx.out, name),
                        title=f"Limit cycles at {case.shown}: reduced model and full geometry")
    return name
