"""What ``shimmy verify`` checks: each section function returns one report section (:mod:`comparisons.verify.report`).

The cases come from a plan (:mod:`comparisons.verify.plan`): the paper's own cases for the paper's truck, a plan made
from the axle's Hopf curves and cycles for any axle file.  Equivalence checks (reduced model against the MBS with
every assumption of the reduced model switched on) can fail and make ``verify`` exit non-zero; comparisons with the
paper (only for the paper's axle) pass to its printed digits, or are known differences listed in
``paper_reference.KNOWN_DIFFERENCES``; what the full geometry changes is reported as information.
"""

from __future__ import annotations

import math
import os

import numpy as np

from comparisons import assumption_shifts as shifts
from axles.paper_reference import HOPF_SPEEDS_KMH, KNOWN_DIFFERENCES
from axles.units import BAR, from_kmh, kmh
from comparisons.verify.context import (
    EIGEN_SPEEDS_KMH,
    EIGEN_TOL,
    HOPF_TOL_KMH,
    MODEL_SETS,
    Context,
    agrees_to_printed_digits,
    shimmy_cases,
)
from comparisons.verify.plan import VMAX, CaseKind
from comparisons.verify.report import CheckStatus, Row, Section
from bifurcation.equilibria.hopf import find_hopf_points
from reduced_model.model import ShimmyModel
from axles.pressures import TyrePressures
from comparisons.api import family_of

# --- the plan -------------------------------------------------------------------------------------------------

def plan_section(ctx: Context) -> Section:
    rows = [Row({"case": f"C{i}", "pressure_right_bar": c.pressure_right_bar, "pressure_left_bar": c.pressure_left_bar,
                 "kind": c.kind.value + ("" if c.chosen_by is None else f" ({c.chosen_by.label})"),
                 "reason": c.reason}, CheckStatus.INFO)
            for i, c in enumerate(ctx.plan.cases, 1)]
    for b in ctx.plan.bistable:
        window = "" if math.isnan(b.low_kmh) else f" ({b.low_kmh:.1f}-{b.high_kmh:.1f} km/h)"
        rows.append(Row({"case": "B", "pressure_right_bar": b.pressure_bar, "pressure_left_bar": b.pressure_bar,
                         "kind": "bistable" + window, "reason": b.reason}, CheckStatus.INFO))
    text = "; ".join(ctx.plan.notes)
    return Section(key="plan", title=f"Plan: the cases verified for axle {ctx.axle.shown_name}",
                   columns=("case", "pressure_right_bar", "pressure_left_bar", "kind", "reason"), rows=tuple(rows),
                   text=("Wheel 1 (theta1) is the right wheel. " + (text + "." if text else "")).strip())


# --- the paper's printed numbers (the paper's axle only) -----------------------------------------------------

def paper_status(key: str, printed: float | None, computed: float | None) -> tuple[CheckStatus, str]:
    if printed is None:
        return CheckStatus.INFO, ""
    if computed is None:
        return CheckStatus.FAIL, "printed in the paper, not found"
    if agrees_to_printed_digits(printed, computed):
        return CheckStatus.PASS, "agrees to the printed digits"
    if key in KNOWN_DIFFERENCES:
        return CheckStatus.KNOWN_DIFFERENCE, KNOWN_DIFFERENCES[key]
    return CheckStatus.FAIL, f"differs by {computed - printed:+.3f} km/h"


def paper_section(ctx: Context) -> Section:
    """Section 3 Hopf speeds printed in the paper against the reduced model (figure 9a's points are checked with
    the bistable jumps, where their continuation is made)."""
    rows = []
    family = family_of(ShimmyModel(params=ctx.axle.params), TyrePressures.uniform(2.5e5))
    for p, printed in HOPF_SPEEDS_KMH.items():
        computed = find_hopf_points(family, p * BAR, 0.0, VMAX)
        if not printed:
            ok = not computed
            rows.append(Row({"quantity": f"Hopf points at {p:g} bar", "paper": "none",
                             "computed": "none" if ok else ", ".join(f"{kmh(h.p):.2f}" for h in computed)},
                            CheckStatus.PASS if ok else CheckStatus.FAIL,
                            "no shimmy at any speed, as in the paper" if ok else "the paper has none"))
            continue
        for i, ref in enumerate(printed):
            h = computed[i] if i < len(computed) else None
            status, note = paper_status(f"hopf:{p}:HB{i + 1}", ref, kmh(h.p) if h else None)
            rows.append(Row({"quantity": f"HB{i + 1} at {p:g} bar (km/h)", "paper": ref,
                             "computed": kmh(h.p) if h else None}, status, note))
        if len(computed) != len(printed):
            rows.append(Row({"quantity": f"number of Hopf points at {p:g} bar", "paper": len(printed),
                             "computed": len(computed)}, CheckStatus.FAIL, "a different number of Hopf points"))
    return Section(key="paper", title="The paper's printed numbers against the reduced model",
                   columns=("quantity", "paper", "computed"), rows=tuple(rows),
                   text="Section 3 model (figures 3 and 4). Only for the paper's axle.")


# --- Hopf speeds and eigenvalues ------------------------------------------------------------------------------

def _eigen_check(model: ShimmyModel, fidelity, pressures, dims) -> float:
    """Largest relative difference of the MBS's eigenvalues from the reduced model's at a few speeds."""
    from mbs_shimmy.model import MbsModel
    family = family_of(MbsModel(model.params, model.effects, fidelity, dims), pressures)
    reduced = family_of(model, pressures)
    worst_rel = 0.0
    for v in EIGEN_SPEEDS_KMH:
        a = np.sort_complex(np.linalg.eigvals(reduced.linear_matrix(from_kmh(v), reduced.nominal)))
        b = np.sort_complex(np.linalg.eigvals(family.linear_matrix(from_kmh(v), family.nominal)))
        worst_rel = max(worst_rel, float(np.max(np.abs(a - b)) / np.max(np.abs(a))))
    return worst_rel


def hopf_section(ctx: Context) -> Section:
    from comparisons.studies.assumption_study import match_hopf
    from mbs_shimmy.fidelity import Fidelity
    from mbs_shimmy.model import MbsModel
    rows = []
    dims = ctx.axle.dims
    speeds = {}     # figure: model set -> source -> [(pressure bar, km/h)] at the symmetric cases
    for label, effects in MODEL_SETS:
        model = ShimmyModel(params=ctx.axle.params, effects=effects)
        for case in ctx.plan.cases:
            ctx.progress(f"Hopf speeds: {label} model, {case.label}")
            family = family_of(model, case.pressures)
            reduced = find_hopf_points(family, family.nominal, 0.0, VMAX)
            by_fidelity = {}
            for name in ("reduced", "full"):
                mfam = family_of(MbsModel(model.params, effects, Fidelity.parse(name), dims), case.pressures)
                by_fidelity[name] = match_hopf(reduced, find_hopf_points(mfam, mfam.nominal, 0.0, VMAX,
                                                                    lyapunov=False))
            rel = _eigen_check(model, Fidelity.reduced(), case.pressures, dims)
            eig_ok = rel <= EIGEN_TOL
            base = {"model": label, "case": case.label}
            rows.append(Row({**base, "point": "eigenvalues", "relative_diff": rel},
                            CheckStatus.PASS if eig_ok else CheckStatus.FAIL,
                            f"MBS (reduced fidelity) against the reduced model at "
                            f"{', '.join(f'{v:g}' for v in EIGEN_SPEEDS_KMH)} km/h (tolerance {EIGEN_TOL:g})"))
            if not reduced:
                extra = [s for s in by_fidelity["reduced"] if s.reduced_speed is None]
                ok = not extra
                rows.append(Row({**base, "point": "none"}, CheckStatus.PASS if ok else CheckStatus.FAIL,
                                "no Hopf point in the reduced model nor in the MBS (reduced fidelity)" if ok else
                                "the MBS (reduced fidelity) has Hopf points the reduced model lacks"))
            full_by_reduced = {s.reduced_speed: s for s in by_fidelity["full"] if s.reduced_speed is not None}
            for i, h in enumerate(reduced):
                red = next((s for s in by_fidelity["reduced"] if s.reduced_speed == h.p), None)
                full = full_by_reduced.get(h.p)
                red_kmh = shifts.mbs_kmh(red) if red else None
                ok = red_kmh is not None and abs(red_kmh - kmh(h.p)) <= HOPF_TOL_KMH
                _collect_hopf_speeds(speeds, label, case, kmh(h.p), red, full)
                rows.append(Row({**base, "point": f"HB{i + 1}", "reduced_kmh": kmh(h.p),
                                 "mbs_reduced_kmh": red_kmh,
                                 "mbs_full_kmh": shifts.mbs_kmh(full) if full else None,
                                 "full_shift_kmh": shifts.shift_kmh(full) if full else None,
                                 "frequency_hz": h.frequency_hz,
                                 "criticality": h.criticality.value if h.criticality else None},
                                CheckStatus.PASS if ok else CheckStatus.FAIL,
                                "" if ok else f"MBS (reduced fidelity) differs by more than {HOPF_TOL_KMH} km/h"))
            for s in by_fidelity["full"]:
                if s.reduced_speed is None:
                    rows.append(Row({**base, "point": "MBS full only", "mbs_full_kmh": shifts.mbs_kmh(s)},
                                    CheckStatus.INFO,
                                    "a Hopf point of the full geometry with no reduced-model partner"))
    figures = _hopf_figure(ctx, speeds)
    return Section(
        key="hopf", title="Hopf speeds and eigenvalues: reduced model and MBS", figures=figures,
        columns=("model", "case", "point", "reduced_kmh", "mbs_reduced_kmh", "mbs_full_kmh", "full_shift_kmh",
                 "frequency_hz", "criticality", "relative_diff"),
        rows=tuple(rows),
        text=(f"Hopf points of straight running, 0-400 km/h, at every planned case. Check: the MBS with every "
              f"assumption of the reduced model on (`mbs_reduced`) has the same eigenvalues (relative "
              f"{EIGEN_TOL:g}) and the same Hopf points to {HOPF_TOL_KMH} km/h. `mbs_full` (all assumptions off) is "
              f"information: what the full geometry changes."))


def _collect_hopf_speeds(speeds: dict, label: str, case, reduced_kmh: float, red, full) -> None:
    if case.pressure_right_bar != case.pressure_left_bar:
        return
    p = case.pressure_right_bar
    by_source = speeds.setdefault(label, {})
    by_source.setdefault("reduced", []).append((p, reduced_kmh))
    by_source.setdefault("mbs_reduced", []).append((p, shifts.mbs_kmh(red) if red else None))
    by_source.setdefault("mbs_full", []).append((p, shifts.mbs_kmh(full) if full else None))


def _hopf_figure(ctx: Context, speeds: dict) -> tuple[str, ...]:
    """Hopf speeds of the paper, the reduced model and both MBS fidelities against pressure, per model set, over
    the reduced model's Hopf curves in (pressure, speed)."""
    from comparisons.verify.report_figures import plot_hopf_speeds
    if not speeds:
        return ()
    if ctx.axle.is_paper and MODEL_SETS[0][0] in speeds:
        speeds[MODEL_SETS[0][0]]["paper"] = [(p, v) for p, printed in HOPF_SPEEDS_KMH.items() for v in printed]
    ctx.progress("Hopf speeds: the reduced model's Hopf curves in pressure")
    curves = {label: _pressure_curves(ctx, effects, speeds[label]) for label, effects in MODEL_SETS if label in speeds}
    ctx.progress("Hopf speeds: figure")
    plot_hopf_speeds(speeds, os.path.join(ctx.out, "hopf_speeds.png"),
                     title=f"Hopf speeds against tyre pressure, axle {ctx.axle.shown_name} (both tyres alike)",
                     curves=curves)
    return ("hopf_speeds.png",)


def _pressure_curves(ctx: Context, effects, sources: dict) -> list[tuple[np.ndarray, np.ndarray]]:
    """The reduced model's Hopf curves over the figure's pressures (0.5 bar either side of its points), as
    (pressures bar, speeds km/h)."""
    from bifurcation.equilibria.hopf_curves import hopf_diagram
    bars = [p for points in sources.values() for p, _ in points]
    if not bars:
        return []
    lo, hi = max(min(bars) - 0.5, 0.3), max(bars) + 0.5
    family = family_of(ShimmyModel(params=ctx.axle.params, effects=effects),
                       TyrePressures.uniform(0.5 * (lo + hi) * BAR), "pressure")
    diagram = hopf_diagram(family, lo * BAR, hi * BAR, 0.0, VMAX)
    return [(c.qs / BAR, kmh(c.ps)) for c in diagram.curves]


# --- assumptions ------------------------------------------------------------------------------------------

def assumptions_section(ctx: Context) -> Section:
    from comparisons.verify.report_figures import AssumptionShift, plot_assumption_tornado
    from comparisons.studies.assumption_study import assumption_study
    model = ShimmyModel(params=ctx.axle.params)
    rows, tornado = [], []
    cases = [c for c in shimmy_cases(ctx) if c.kind is not CaseKind.ASYMMETRIC][:2]
    if not cases:
        rows.append(Row({}, CheckStatus.COULD_NOT_CHECK, "no planned case where the reduced model shimmies: no Hopf speed "
                                                 "to shift"))
    for case in cases:
        ctx.progress(f"Assumptions at {case.label}")
        # The peaks need every row's branches continued (5-30 s a row, minutes a case): verify keeps to the Hopf
        # shifts and points to the command that continues them.
        study = assumption_study(model.params, model.effects, case.pressures, dims=ctx.axle.dims, cycles=False)
        for r in study.rows:
            hopf = [shifts.shift_kmh(h) for h in r.hopf]
            text = ", ".join("-" if v is None else f"{v:+.2f}" for v in hopf)
            peak = shifts.peak_theta1_shift_deg(r)
            note = (f"peaks not computed here: .venv/bin/shimmy assumptions --pressure {case.pressure_right_bar:g} "
                    f"continues them")
            rows.append(Row({"case": case.label, "assumption_off": r.assumption, "hopf_shifts_kmh": text,
                             "peak_theta1_shift_deg": peak}, CheckStatus.INFO, note))
            tornado.append(AssumptionShift(case.pressure_right_bar, r.assumption, hopf, peak))
    figures = ()
    if tornado:
        plot_assumption_tornado(tornado, os.path.join(ctx.out, "assumptions.png"),
                                title=f"What each assumption of the reduced model costs, axle {ctx.axle.shown_name}")
        figures = ("assumptions.png",)
    return Section(
        key="assumptions", title="What each assumption of the reduced model costs (MBS, one switch off at a time)",
        figures=figures,
        columns=("case", "assumption_off", "hopf_shifts_kmh", "peak_theta1_shift_deg"), rows=tuple(rows),
        text=("Shift of every Hopf speed (MBS minus reduced, in the order of the reduced model's Hopf points; '-' where "
              "a point has no partner) and of the peak limit-cycle amplitude, from `shimmy assumptions`, at the first "
              "two planned cases with shimmy. Rows named after a geometric element of the full axle "
              "(no_kingpin_inclination, ..., rigid_steering_gear): full geometry minus full geometry without that "
              "element. The peak limit-cycle amplitudes per row come from every row's own continued cycle branches "
              "(the MBS variant's on Exudyn), which take 5-30 s a row: `.venv/bin/shimmy assumptions --pressure BAR` computes "
              "them; the report keeps to the Hopf shifts."))


# --- a transient ------------------------------------------------------------------------------------------

def transient_cases(ctx: Context) -> list:
    """Where the transient is compared: the plan's no-shimmy cases when it has them (the only time check of a
    stable axle), else its first case; quick: one case."""
    stable = [c for c in ctx.plan.cases if c.kind is CaseKind.STABLE]
    cases = stable or list(ctx.plan.cases[:1])
    return cases[:1] if ctx.quick else cases[:3]


def transient_section(ctx: Context) -> Section:
    from comparisons.verify.transient import KICK_RAD, TRANSIENT_TOL, transient_check
    duration = 1.0 if ctx.quick else 2.0
    speeds = (60.0,) if ctx.quick else (60.0, 150.0)
    rows = []
    for case in transient_cases(ctx):
        for v in speeds:
            ctx.progress(f"Transient: both models at {case.label}, {v:g} km/h")
            check = transient_check(ctx.axle, case.pressures, v, duration)
            motion = (f"the kick {'decays' if check.decays else 'does not decay'} in both models "
                      f"(|angles| at {duration:g} s / at the start: reduced {check.decay_reduced:.3g}, "
                      f"MBS {check.decay_mbs:.3g})" if check.complete else f"MBS run stopped: {check.message}")
            rows.append(Row({"case": case.label, "speed_kmh": v,
                             "relative_diff": check.worst_relative if check.complete else None},
                            CheckStatus.PASS if check.ok else CheckStatus.FAIL,
                            motion if check.ok else f"{motion}; differs by more than {TRANSIENT_TOL:g} of a state's "
                                                    f"amplitude"))
    if not rows:
        rows.append(Row({}, CheckStatus.COULD_NOT_CHECK, "no planned case"))
    return Section(
        key="transient", title="Transient: a kick in both models", columns=("case", "speed_kmh", "relative_diff"),
        rows=tuple(rows),
        labels={"relative_diff": "largest difference of a state, MBS against the reduced model, over its amplitude "
                                 "[relative, not %]"},
        text=(f"From a yaw angle of {KICK_RAD:g} rad of wheel 1 at constant speed, {duration:g} s of the MBS with "
              f"every assumption of the reduced model on (Exudyn, RK67) against the reduced model (DOP853, rtol "
              f"1e-12). Check: every state within {TRANSIENT_TOL:g} of its amplitude. At the plan's no-shimmy cases "
              f"when it has them, else at its first case."))

