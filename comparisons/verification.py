"""What ``shimmy verify`` checks: each section function returns one report section (:mod:`comparisons.report`).

Equivalence checks (reduced model against the MBS with every assumption of the reduced model switched on) can
fail and make ``verify`` exit non-zero; comparisons with the paper pass to its printed digits, or are known
differences listed in ``paper_reference.KNOWN_DIFFERENCES``; what the full geometry changes is reported as
information.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass

import numpy as np

from reduced_model.family import SpeedFamily
from reduced_model.hopf import hopf_points
from reduced_model.model import Effects, ShimmyModel
from reduced_model.special_points import PointKind

from .paper_reference import FIG9A, HOPF_SPEEDS_KMH, KNOWN_DIFFERENCES
from .report import CheckStatus, Report, Row, Section

VMAX = 400 / 3.6
PRESSURES = (1.5, 2.5, 2.7)
MODEL_SETS = (("section 3", Effects()), ("extended (all effects)", Effects.parse("all")))
HOPF_TOL_KMH = 0.01          # MBS (reduced fidelity) against the reduced model
AMPLITUDE_TOL = 0.005        # relative, MBS steady amplitude against the continuation branch
BISTABLE_T0 = 0.25           # m, figure 9a / 10 / 11
BISTABLE_BAR = 1.5


@dataclass(frozen=True)
class Context:
    out: str
    quick: bool


def _mbs():
    import mbs_shimmy
    return mbs_shimmy


def printed_decimals(value: float) -> int:
    text = repr(value)
    return len(text.split(".")[1]) if "." in text else 0


def agrees_to_printed_digits(printed: float, computed: float) -> bool:
    digits = printed_decimals(printed)
    return abs(round(computed, digits) - printed) < 0.5 * 10 ** -digits


def _worst(*statuses: CheckStatus) -> CheckStatus:
    for s in (CheckStatus.FAIL, CheckStatus.KNOWN_DIFFERENCE, CheckStatus.PASS):
        if s in statuses:
            return s
    return CheckStatus.INFO


# --- Hopf speeds ------------------------------------------------------------------------------------------

def paper_status(key: str, printed: float | None, computed: float | None) -> tuple[CheckStatus, str]:
    if printed is None:
        return CheckStatus.INFO, ""
    if computed is None:
        return CheckStatus.FAIL, "printed in the paper, not found"
    if agrees_to_printed_digits(printed, computed):
        return CheckStatus.PASS, "paper: agrees to the printed digits"
    if key in KNOWN_DIFFERENCES:
        return CheckStatus.KNOWN_DIFFERENCE, "paper: " + KNOWN_DIFFERENCES[key]
    return CheckStatus.FAIL, f"paper: differs by {computed - printed:+.3f} km/h"


def hopf_section(ctx: Context) -> Section:
    mbs = _mbs()
    rows = []
    for label, effects in MODEL_SETS:
        model = ShimmyModel(effects=effects)
        for p in PRESSURES:
            reduced = hopf_points(SpeedFamily(model), p * 1e5, 0.0, VMAX)
            by_fidelity = {}
            for name in ("reduced", "full"):
                family = mbs.MbsFamily.of(model.params, effects, mbs.Fidelity.parse(name))
                by_fidelity[name] = mbs.match_hopf(reduced, hopf_points(family, p * 1e5, 0.0, VMAX,
                                                                       lyapunov=False))
            printed = HOPF_SPEEDS_KMH.get(p, ()) if not effects.names else None
            n = max(len(reduced), len(by_fidelity["full"]))
            if n == 0:
                status = CheckStatus.PASS if printed == () else CheckStatus.INFO
                rows.append(Row({"model": label, "pressure_bar": p, "point": "none"}, status,
                                "no Hopf point in any model" + (", as in the paper" if printed == () else "")))
                continue
            same = len(by_fidelity["reduced"]) == len(reduced)
            full_by_reduced = {s.reduced_kmh: s for s in by_fidelity["full"] if s.reduced_kmh is not None}
            full_only = [s for s in by_fidelity["full"] if s.reduced_kmh is None]
            for i, h in enumerate(reduced):
                red = next(s for s in by_fidelity["reduced"] if s.reduced_kmh == h.speed_kmh)
                full = full_by_reduced.get(h.speed_kmh)
                ref = printed[i] if printed and i < len(printed) else None
                s_paper, note = paper_status(f"hopf:{p}:HB{i + 1}", ref, h.speed_kmh)
                ok = same and red.mbs_kmh is not None and abs(red.mbs_kmh - h.speed_kmh) <= HOPF_TOL_KMH
                note = "; ".join(x for x in (note, "" if ok else "MBS (reduced fidelity) does not match") if x)
                rows.append(Row({"model": label, "pressure_bar": p, "point": f"HB{i + 1}", "paper_kmh": ref,
                                 "reduced_kmh": h.speed_kmh, "mbs_reduced_kmh": red.mbs_kmh,
                                 "mbs_full_kmh": full.mbs_kmh if full else None,
                                 "full_shift_kmh": full.shift_kmh if full else None,
                                 "frequency_hz": h.frequency_hz,
                                 "criticality": h.criticality.value if h.criticality else None},
                                _worst(s_paper, CheckStatus.PASS if ok else CheckStatus.FAIL), note))
            for s in full_only:
                rows.append(Row({"model": label, "pressure_bar": p, "point": "MBS full only",
                                 "mbs_full_kmh": s.mbs_kmh}, CheckStatus.INFO,
                                 "a Hopf point of the full geometry with no reduced-model partner"))
    return Section(
        key="hopf", title="Hopf speeds: paper, reduced model, MBS",
        columns=("model", "pressure_bar", "point", "paper_kmh", "reduced_kmh", "mbs_reduced_kmh", "mbs_full_kmh",
                 "full_shift_kmh", "frequency_hz", "criticality"),
        rows=tuple(rows),
        text=(f"Hopf points of straight running, 0-400 km/h. Check: the MBS with every assumption of the reduced "
              f"model on (`mbs_reduced`) has the same Hopf points to {HOPF_TOL_KMH} km/h; paper values to their "
              f"printed digits. `mbs_full` (all assumptions off) is information: what the full geometry changes."))


# --- limit cycles -----------------------------------------------------------------------------------------

def _sample_stable(branch, count: int) -> list:
    stable = [p for p in branch.points if p.stable]
    if len(stable) <= count:
        return stable
    idx = np.unique(np.linspace(1, len(stable) - 2, count).round().astype(int))
    return [stable[i] for i in idx]


def cycles_section(ctx: Context) -> Section:
    from reduced_model.cycles import cycle_diagram

    from .cycle_plots import plot_cycle_overlay
    mbs = _mbs()
    per_branch = 2 if ctx.quick else 10
    settle = 6.0 if ctx.quick else 12.0
    rows, figures = [], []
    model = ShimmyModel()
    for p in (2.5, 1.5):
        family = SpeedFamily(model)
        diagram = cycle_diagram(family, p * 1e5, 0.0, VMAX)
        overlay = {"reduced": [], "full": []}
        for b, branch in enumerate(diagram.branches, 1):
            for point in _sample_stable(branch, per_branch):
                x0 = point.orbit.nodes[0]
                got = {}
                for name in ("reduced", "full"):
                    got[name] = mbs.mbs_steady_amplitude(model.params, model.effects, mbs.Fidelity.parse(name),
                                                         p * 1e5, point.speed, x0, settle=settle)
                    overlay[name].append((point.speed, got[name].theta1, got[name].psi))
                ref = point.max_abs("theta1")
                red = got["reduced"].theta1
                rel = abs(red - ref) / ref if math.isfinite(red) else math.inf
                ok = rel <= AMPLITUDE_TOL
                full = got["full"].theta1
                rows.append(Row({"pressure_bar": p, "branch": f"from HB at {branch.start.speed_kmh:.2f} km/h",
                                 "speed_kmh": point.speed_kmh, "continuation_theta1_deg": math.degrees(ref),
                                 "mbs_reduced_theta1_deg": math.degrees(red) if math.isfinite(red) else None,
                                 "relative_diff": rel if math.isfinite(rel) else None,
                                 "mbs_full_theta1_deg": math.degrees(full) if math.isfinite(full) else None},
                                CheckStatus.PASS if ok else CheckStatus.FAIL,
                                "" if ok else f"MBS steady amplitude off by more than {AMPLITUDE_TOL:.1%}"))
        name = f"cycles_{str(p).replace('.', 'p')}bar.png"
        plot_cycle_overlay(diagram, family, overlay, os.path.join(ctx.out, name),
                           title=f"Limit cycles at {p:g} bar: continuation (lines) and MBS simulations (markers)")
        figures.append(name)
    return Section(
        key="cycles", title="Limit cycles: continuation of the reduced model and long MBS simulations",
        columns=("pressure_bar", "branch", "speed_kmh", "continuation_theta1_deg", "mbs_reduced_theta1_deg",
                 "relative_diff", "mbs_full_theta1_deg"),
        rows=tuple(rows), figures=tuple(figures),
        text=(f"At {per_branch} speeds per stable branch the MBS is started on the reduced model's cycle and run "
              f"until its amplitude settles ({settle:g} s windows). Check: the MBS with every assumption on keeps "
              f"max|theta1| within {AMPLITUDE_TOL:.1%} of the continuation; the full geometry's steady amplitude is "
              f"information (it may settle on a different cycle, or decay where its own Hopf points moved)."))


# --- bistable jumps ---------------------------------------------------------------------------------------

def _bistable_points():
    from reduced_model.cycles import cycle_diagram
    model = ShimmyModel().with_params(t0=BISTABLE_T0)
    diagram = cycle_diagram(SpeedFamily(model), BISTABLE_BAR * 1e5, 0.0, VMAX)
    folds = sorted(diagram.points_of(PointKind.CYCLE_FOLD), key=lambda s: -s.speed)
    tori = sorted(diagram.points_of(PointKind.TORUS), key=lambda s: -s.speed)
    return model, {"S1": folds[0].speed * 3.6, "T1": tori[0].speed * 3.6, "T2": tori[1].speed * 3.6,
                   "S2": folds[1].speed * 3.6}


def _run_both(model, schedule, x0, duration: float):
    """(reduced trajectory, MBS trajectory with every assumption on)."""
    from reduced_model.simulation import simulate
    mbs = _mbs()
    reduced = simulate(model, BISTABLE_BAR * 1e5, schedule, duration, x0)
    multibody = mbs.simulate(model.params, model.effects, mbs.Fidelity.reduced(), BISTABLE_BAR * 1e5, schedule, x0,
                             duration, poses=True)
    return reduced, multibody


def _record(ctx: Context, name: str, trajectory, history, title: str, model) -> str:
    from .recording import write_recording
    path = os.path.join(ctx.out, name)
    write_recording(path, trajectory, history.segments(), history.switches, title=title, model=model,
                    pressure=BISTABLE_BAR * 1e5)
    return name


def jumps_section(ctx: Context) -> Section:
    from reduced_model.modes import Mode, ModeClassifier
    from reduced_model.simulation import initial_state
    from reduced_model.trajectory import SpeedSchedule

    model, points = _bistable_points()
    classify = ModeClassifier().classify
    rows, recordings = [], []
    for key, label in (("S1", "S1"), ("T1", "T1"), ("T2", "T2"), ("S2", "S2")):
        ref = FIG9A[key]
        ok = agrees_to_printed_digits(ref, points[key])
        known = KNOWN_DIFFERENCES.get(f"cycles:fig9a:{key}")
        status = CheckStatus.PASS if ok else CheckStatus.KNOWN_DIFFERENCE if known else CheckStatus.FAIL
        rows.append(Row({"run": f"continuation {label}", "paper_kmh": ref, "reduced_kmh": points[key]}, status,
                        "" if ok else known or "differs from the paper"))
    ramp_time = 40.0 if ctx.quick else 80.0
    runs = (("ramp up", SpeedSchedule.ramp(120 / 3.6, 200 / 3.6, ramp_time), Mode.YAW, Mode.TRAMP, "S1"),
            ("ramp down", SpeedSchedule.ramp(200 / 3.6, 120 / 3.6, ramp_time), Mode.TRAMP, Mode.YAW, "T2"))
    for name, schedule, before, after, anchor in runs:
        trajectories = _run_both(model, schedule, initial_state(), ramp_time + 10.0)
        found = {}
        for traj in trajectories:
            history = classify(traj)
            jumps = [s for s in history.switches if s.before is before and s.after is after]
            found[traj.model] = jumps[0].speed * 3.6 if jumps else None
            recordings.append(_record(ctx, f"{name.replace(' ', '_')}_{traj.model}.rrd", traj, history,
                                      f"{name}, {traj.model} model, t0 = {BISTABLE_T0} m, {BISTABLE_BAR} bar", model))
        beyond = (lambda v: v is not None and v >= points["S1"] - 0.5) if anchor == "S1" else \
            (lambda v: v is not None and v <= points["T2"] + 0.5)
        ok = all(beyond(v) for v in found.values())
        rows.append(Row({"run": f"{name} {ramp_time:g} s, {before.value}->{after.value}",
                         "continuation_kmh": points[anchor], "reduced_kmh": found["reduced"],
                         "mbs_reduced_kmh": found["mbs"],
                         "model_diff_kmh": (found["mbs"] - found["reduced"]) if None not in found.values() else None},
                        CheckStatus.PASS if ok else CheckStatus.FAIL,
                        f"both models jump {'after' if anchor == 'S1' else 'below'} {anchor} (delayed by the slow "
                        f"passage)" if ok else f"a model did not jump {before.value}->{after.value} past {anchor}"))
    # Figure 11: two starts at 180 km/h settle on different cycles.
    duration = 20.0 if ctx.quick else 40.0
    starts = (("L1", initial_state()), ("L2", initial_state({"theta1": 0.2, "psi": 0.01})))
    finals = {}
    for label, x0 in starts:
        for traj in _run_both(model, SpeedSchedule.constant(180 / 3.6), x0, duration):
            history = classify(traj)
            finals[(label, traj.model)] = history.final_mode
            recordings.append(_record(ctx, f"fig11_{label}_{traj.model}.rrd", traj, history,
                                      f"figure 11 start {label} at 180 km/h, {traj.model} model", model))
    for m in ("reduced", "mbs"):
        a, b = finals[("L1", m)], finals[("L2", m)]
        ok = a is not b and Mode.NONE not in (a, b)
        rows.append(Row({"run": f"180 km/h, starts L1 / L2 ({m})", "final_L1": a.value, "final_L2": b.value},
                        CheckStatus.PASS if ok else CheckStatus.FAIL,
                        "two different stable cycles" if ok else "the two starts did not settle on different cycles"))
    return Section(
        key="jumps", title=f"Bistable jumps at t0 = {BISTABLE_T0} m, {BISTABLE_BAR} bar",
        columns=("run", "paper_kmh", "continuation_kmh", "reduced_kmh", "mbs_reduced_kmh", "model_diff_kmh",
                 "final_L1", "final_L2"),
        rows=tuple(rows), recordings=tuple(recordings),
        text=("Cycle folds and torus points from continuation; speed ramps (120-200 km/h) up and down in both models "
              "with the detected mode switches (the jump lags S1 / T2 because the state passes a slowly changing "
              "instability: the lag depends on the ramp rate); the figure-11 experiment at 180 km/h."))


# --- assumptions ------------------------------------------------------------------------------------------

def assumptions_section(ctx: Context) -> Section:
    mbs = _mbs()
    model = ShimmyModel()
    rows = []
    for p in (1.5, 2.5):
        study = mbs.assumption_study(model.params, model.effects, p * 1e5, cycles=not ctx.quick)
        for r in study.rows:
            shifts = ", ".join("-" if h.shift_kmh is None else f"{h.shift_kmh:+.2f}" for h in r.hopf)
            rows.append(Row({"pressure_bar": p, "assumption_off": r.assumption, "hopf_shifts_kmh": shifts,
                             "peak_theta1_shift_deg": r.peak_theta1_shift_deg}, CheckStatus.INFO))
    return Section(
        key="assumptions", title="What each assumption of the reduced model costs (MBS, one switch off at a time)",
        columns=("pressure_bar", "assumption_off", "hopf_shifts_kmh", "peak_theta1_shift_deg"), rows=tuple(rows),
        text=("Shift of every Hopf speed (MBS minus reduced, in the order of the reduced model's Hopf points; '-' where "
              "a point has no partner) and of the peak limit-cycle amplitude, from `shimmy assumptions`. Rows named "
              "after a geometric element of the full axle (no_kingpin_inclination, ..., rigid_steering_gear): full "
              "geometry minus full geometry without that element."
              + (" Quick mode skips the amplitudes." if ctx.quick else "")))


SECTIONS = [
    ("Hopf speeds", hopf_section),
    ("Limit cycles", cycles_section),
    ("Bistable jumps", jumps_section),
    ("Assumptions", assumptions_section),
]


def run_verification(out: str, quick: bool, progress=None) -> Report:
    ctx = Context(out=out, quick=quick)
    sections = []
    for i, (title, make) in enumerate(SECTIONS):
        try:
            sections.append(make(ctx))
        except Exception as exc:  # a failed sub-check is reported in the table, never swallowed
            sections.append(Section(key=title.lower().replace(" ", "_"), title=title, columns=("error",),
                                    rows=(Row({"error": f"{type(exc).__name__}: {exc}"}, CheckStatus.FAIL),),
                                    text="This part of the verification could not be completed."))
        if progress is not None:
            progress(i + 1, len(SECTIONS))
    return Report(sections=tuple(sections), quick=quick)
