"""``shimmy verify``: limit cycles and bistable jumps in both models, at the planned cases.

Limit cycles: the reduced model's branches by continuation (with their cycle folds and torus points) against the
steady amplitudes of long MBS runs started on the cycle.  Bistable jumps: in a window where two stable cycles
coexist, constant-speed runs just past each of its ends from the cycle that ends there and two starts inside it, in
both models, which must end in the same mode; speed ramps up and down through it are information (the jump speed of
a slow passage is a delayed loss of stability, set by numerical noise: not well posed).
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass

import numpy as np

from axles.axle import interface_text
from axles.paper_reference import FIG9A, KNOWN_DIFFERENCES
from axles.units import BAR, kmh
from comparisons.verify.context import Context, agrees_to_printed_digits, shimmy_cases
from comparisons.verify.file_names import case_file_name
from comparisons.verify.jump_experiments import PAST_END_KMH, JumpSetup
from comparisons.verify.plan import VMAX, BistableCase
from comparisons.verify.report import CheckStatus, Column, Row, Section
from reduced_model.model import ShimmyModel
from axles.pressures import TyrePressures
from comparisons.api import family_of

AMPLITUDE_TOL = 0.005        # relative, MBS steady amplitude against the continuation branch


def sample_stable(branch, count: int) -> list:
    stable = [p for p in branch.points if p.stable]
    if len(stable) <= count:
        return stable
    idx = np.unique(np.linspace(1, len(stable) - 2, count).round().astype(int))
    return [stable[i] for i in idx]


@dataclass(frozen=True)
class CycleCheck:
    """The MBS (every assumption of the reduced model on) started on a continuation cycle and run until steady."""

    reference: float          # max|theta1| of the continuation's cycle, rad
    mbs: object               # comparisons.studies.limit_cycle.SteadyAmplitude
    relative_diff: float      # inf when the MBS run stopped

    @property
    def ok(self) -> bool:
        return self.relative_diff <= AMPLITUDE_TOL


def cycle_amplitude_check(model: ShimmyModel, point, pressure, dims, settle: float, x0=None) -> CycleCheck:
    """The MBS steady amplitude at the speed of ``point`` (a continuation cycle of ``model``) against the cycle's
    max|theta1|; the run starts on the cycle unless ``x0`` is given."""
    from mbs_shimmy.fidelity import Fidelity
    from comparisons.studies.limit_cycle import mbs_steady_amplitude
    start = point.orbit.nodes[0] if x0 is None else x0
    got = mbs_steady_amplitude(model.params, model.effects, Fidelity.reduced(), pressure, point.p, start,
                               settle=settle, dims=dims)
    ref = point.max_abs("theta1")
    rel = abs(got.theta1 - ref) / ref if math.isfinite(got.theta1) else math.inf
    return CycleCheck(ref, got, rel)


def cycles_section(ctx: Context) -> Section:
    from comparisons.figures.cycle_plots import plot_cycle_overlay
    from mbs_shimmy.fidelity import Fidelity
    from comparisons.studies.limit_cycle import mbs_steady_amplitude
    from bifurcation.cycles.branches import cycle_diagram
    settle = 6.0 if ctx.quick else 12.0
    rows, figures = [], []
    model = ShimmyModel(params=ctx.axle.params)
    diagrams = []
    for case in shimmy_cases(ctx):
        ctx.progress(f"Limit cycles: continuation at {case.label}")
        family = family_of(model, case.pressures)
        diagrams.append((case, family, cycle_diagram(family, family.nominal, 0.0, VMAX)))
    # MBS runs are the cost: a budget over all stable branches keeps verify's time bounded for any plan.
    stable_branches = sum(any(p.stable for p in b.points) for _, _, d in diagrams for b in d.branches)
    budget, most = (6, 2) if ctx.quick else (28, 8)
    per_branch = max(1, min(most, budget // max(1, stable_branches)))
    if not diagrams:
        rows.append(Row({}, CheckStatus.COULD_NOT_CHECK, "no planned case where the reduced model shimmies: no limit cycle "
                                                 "to compare"))
    for case, family, diagram in diagrams:
        overlay = {"reduced": [], "full": []}
        for b, branch in enumerate(diagram.branches, 1):
            where = f"from HB at {kmh(branch.start.p):.2f} km/h"
            for s in sorted(branch.special_points, key=lambda s: s.p):
                rows.append(Row({"case": case.label, "branch": where, "speed_kmh": kmh(s.p),
                                 "point": s.kind.value, "continuation_theta1_deg": math.degrees(s.data["amplitude"][0])},
                                CheckStatus.INFO, f"{s.kind.value} of the cycles ({s.status.value})"))
            if not branch.complete:
                rows.append(Row({"case": case.label, "branch": where, "point": "branch"}, CheckStatus.FAIL,
                                f"continuation stopped: {interface_text(branch.message)}"))
            for point in sample_stable(branch, per_branch):
                ctx.progress(f"Limit cycles: MBS runs at {case.label}, {kmh(point.p):.1f} km/h")
                check = cycle_amplitude_check(model, point, case.pressures, ctx.axle.dims, settle)
                full_run = mbs_steady_amplitude(model.params, model.effects, Fidelity.parse("full"),
                                                case.pressures, point.p, point.orbit.nodes[0], settle=settle,
                                                dims=ctx.axle.dims)
                full = full_run.theta1
                overlay["reduced"].append((point.p, check.mbs.theta1, check.mbs.psi))
                overlay["full"].append((point.p, full_run.theta1, full_run.psi))
                red, rel = check.mbs.theta1, check.relative_diff
                rows.append(Row({"case": case.label, "branch": where, "point": "stable cycle",
                                 "speed_kmh": kmh(point.p), "continuation_theta1_deg": math.degrees(check.reference),
                                 "mbs_reduced_theta1_deg": math.degrees(red) if math.isfinite(red) else None,
                                 "relative_diff": rel if math.isfinite(rel) else None,
                                 "mbs_full_theta1_deg": math.degrees(full) if math.isfinite(full) else None},
                                CheckStatus.PASS if check.ok else CheckStatus.FAIL,
                                "" if check.ok else f"MBS steady amplitude off by more than {AMPLITUDE_TOL:.1%}"))
        name = case_file_name("cycles", "png", case.pressure_right_bar, case.pressure_left_bar)
        plot_cycle_overlay(diagram, family, overlay, os.path.join(ctx.out, name),
                           title=f"Limit cycles at {case.label}: continuation (lines) and MBS simulations (markers)")
        figures.append(name)
    return Section(
        key="cycles", title="Limit cycles: continuation of the reduced model and long MBS simulations",
        columns=("case", "branch", "point", "speed_kmh", "continuation_theta1_deg", "mbs_reduced_theta1_deg",
                 "relative_diff", "mbs_full_theta1_deg"),
        rows=tuple(rows), figures=tuple(figures),
        text=(f"Every planned case with shimmy. At {per_branch} speed(s) per stable branch (at most {budget} runs in "
              f"all) the MBS is started on the "
              f"reduced model's cycle and run until its amplitude settles ({settle:g} s windows). Check: the MBS with "
              f"every assumption on keeps max|theta1| within {AMPLITUDE_TOL:.1%} of the continuation; cycle folds and "
              f"torus points of the branches are listed; the full geometry's steady amplitude is information (it may "
              f"settle on a different cycle, or decay where its own Hopf points moved)."))


# --- bistable jumps ---------------------------------------------------------------------------------------

def _record(ctx: Context, name: str, trajectory, history, title: str, case: BistableCase) -> str | None:
    if not ctx.recordings:
        return None
    from comparisons.recordings.writer import write_recording
    path = os.path.join(ctx.out, name)
    write_recording(path, trajectory, history.segments(), history.switches, title=title,
                    model=ShimmyModel(params=case.axle.params), pressures=TyrePressures.uniform(case.pressure_bar * BAR))
    return name


def _record_both(ctx: Context, name: str, both, title: str, case: BistableCase,
                 mbs_title: str = "MBS, all assumptions on (Exudyn)") -> list[str]:
    """The side-by-side recording of one experiment in both models (besides one file per model); ``mbs_title``
    names the MBS run in the recording's views."""
    if not ctx.recordings:
        return []
    from comparisons.recordings.writer import ComparedRun, write_comparison
    write_comparison(os.path.join(ctx.out, name), [ComparedRun(t, h.segments(), h.switches,
                                                               mbs_title if t.model == "mbs" else "")
                                                   for t, h in both],
                     title, model=ShimmyModel(params=case.axle.params), pressures=TyrePressures.uniform(case.pressure_bar * BAR))
    return [name]


def _experiment(title: str, both, marks: dict):
    from comparisons.verify.report_figures import Experiment, RunHistory
    runs = [RunHistory(t.model, t.t, kmh(t.speed), np.degrees(t.state("theta1")), np.degrees(t.state("psi")),
                       [(s.time, kmh(s.speed), f"{s.before.value} -> {s.after.value}") for s in h.switches])
            for t, h in both]
    return Experiment(title, runs, marks)


def _jump_figure(ctx: Context, experiments, case: BistableCase, paper: bool) -> str:
    from comparisons.verify.report_figures import plot_jump_histories
    name = case_file_name("jumps", "png", case.pressure_bar)
    ends = "S1 (ramp up) and T2 (ramp down)" if paper else "the window's ends"
    plot_jump_histories(experiments, os.path.join(ctx.out, name),
                        title=f"Jumps between the modes in both models, {case.pressure_bar:g} bar; dashed: the speed "
                              f"passes {ends}; dotted: detected switches")
    return name


def _kick_rows(ctx: Context, setup: JumpSetup) -> list[Row]:
    """The reduced model's kick threshold in the middle of each bistable window of its diagram."""
    from comparisons.verify.kick_rows import kick_verdict
    from comparisons.studies.kick import kicks
    ctx.progress("Bistable jumps: kick threshold of the reduced model (tens of runs)")
    family = family_of(ShimmyModel(params=setup.case.axle.params), TyrePressures.uniform(setup.diagram.q))
    rows = []
    for kick in kicks(family, setup.diagram):
        cells, status, text = kick_verdict(kick, "reduced model")
        rows.append(Row({"run": f"kick at {kmh(kick.speed):.2f} km/h: {kick.lower.label} -> {kick.upper.label}",
                         **cells}, status, text))
    return rows or [Row({"run": "kick threshold"}, CheckStatus.COULD_NOT_CHECK,
                        "no two stable states coexist in the reduced model's diagram: nothing to kick from")]


def settled_apart(first, second) -> bool:
    """Two starts ended on different cycles (neither on straight running)."""
    from reduced_model.modes import Mode
    return first is not second and Mode.NONE not in (first, second)


def ramp_row(ramp, both, setup: JumpSetup, rate: float) -> Row:
    """A ramp through the window: information.  The speed of a jump under a slow ramp is a delayed loss of
    stability, set by how far the state is from the cycle (numerical noise at the integrator's error level), so
    two equal models may jump at different speeds by chance: the row states the ramp rate and each model's delay
    past the window's end, and says when a jump came only in the hold at the ramp's end speed."""
    from comparisons.verify.jump_experiments import ramp_jump
    jumps = {traj.model: ramp_jump(ramp, history, setup) for traj, history in both}
    parts = []
    for model, name in (("reduced", "reduced model"), ("mbs", "MBS")):
        j = jumps[model]
        if j.speed_kmh is None:
            parts.append(f"{name}: no jump before the run ended ({j.ramp_s:.0f} s ramp, then "
                         f"{j.end_kmh:.1f} km/h held)")
        elif j.in_hold:
            parts.append(f"{name}: jumped only in the hold at the ramp's end speed {j.end_kmh:.1f} km/h, "
                         f"{j.time_s - j.ramp_s:.1f} s after the ramp ended (not a jump speed)")
        else:
            delay = j.speed_kmh - ramp.edge
            parts.append(f"{name}: jumped at {j.speed_kmh:.2f} km/h during the ramp, {delay:+.2f} km/h "
                         f"({delay / rate * (1 if ramp.up else -1):+.1f} s) past the window's end")
    v_from, v_to = (setup.v_lo, setup.v_hi) if ramp.up else (setup.v_hi, setup.v_lo)
    speed = {m: (None if j.speed_kmh is None or j.in_hold else j.speed_kmh) for m, j in jumps.items()}
    return Row({"run": f"{ramp.name} {v_from:.0f}->{v_to:.0f} km/h at {rate:g} km/h/s", "continuation_kmh": ramp.edge,
                "reduced_kmh": speed["reduced"], "mbs_reduced_kmh": speed["mbs"]}, CheckStatus.INFO,
               f"{ramp.before.value} -> {ramp.after.value} (window's end {ramp.edge:.2f} km/h): " + "; ".join(parts)
               + ". Information: a jump speed under a ramp is not well posed (the delay is set by numerical noise)")


def end_row(end) -> Row:
    """Both models at constant speed just past one end of the window, started on the cycle that ends there: the
    check is that they agree on whether the motion leaves that cycle and where it goes."""
    finals = {traj.model: history.final_mode for traj, history in end.both}
    left = {m: f is not end.start_mode for m, f in finals.items()}
    ok = finals["reduced"] is finals["mbs"]
    name = f"{end.point} " if end.point else ""
    what = ("a cycle fold: the cycle no longer exists past it, both runs are expected to leave it"
            if end.point.startswith("S") else
            "a torus point: the cycle is unstable past it, the motion may stay near it (quasi-periodic) or leave"
            if end.point.startswith("T") else "the window's end")
    moves = {m: (f"left {end.start_mode.value} for {f.value}" if left[m] else f"stayed in {f.value}")
             for m, f in finals.items()}
    return Row({"run": f"{end.end} end {name}{end.end_kmh:.2f} km/h: constant {end.speed_kmh:.2f} km/h from the "
                       f"{end.start_mode.value} cycle at {end.cycle_kmh:.2f} km/h",
                "continuation_kmh": end.end_kmh, "final_1": finals["reduced"].value, "final_2": finals["mbs"].value},
               CheckStatus.PASS if ok else CheckStatus.FAIL,
               f"{what}; reduced model {moves['reduced']}, MBS {moves['mbs']}"
               + ("" if ok else ": the models end in different modes"))


def two_start_rows(speed: float, starts, finals: dict) -> list[Row]:
    """Two starts inside the window: each start must end in the same mode in both models (the check); that the two
    starts end on different cycles is what the models are expected to do (information)."""
    if len(starts) != 2:
        return [Row({"run": "two starts"}, CheckStatus.COULD_NOT_CHECK,
                    "fewer than two stable cycles found inside the window to start from")]
    rows = []
    for label, _ in starts:
        a, b = finals[(label, "reduced")], finals[(label, "mbs")]
        rows.append(Row({"run": f"{speed:.1f} km/h, start {label}: reduced model and MBS", "final_1": a.value,
                         "final_2": b.value}, CheckStatus.PASS if a is b else CheckStatus.FAIL,
                        "both models end in the same mode" if a is b else "the models end in different modes"))
    for m in ("reduced", "mbs"):
        a, b = finals[(starts[0][0], m)], finals[(starts[1][0], m)]
        rows.append(Row({"run": f"{speed:.1f} km/h, two starts ({m})", "final_1": a.value, "final_2": b.value},
                        CheckStatus.INFO, "two different stable cycles, as expected in a bistable window"
                        if settled_apart(a, b) else "the two starts did not settle on different cycles (expected "
                                                    "of a bistable window; information, not a check)"))
    return rows


def jumps_section(ctx: Context) -> Section:
    rows, recordings, figures = [], [], []
    from comparisons.verify.jump_experiments import RAMP_KMH_S, jump_runs_of, paper_window
    for i, case in enumerate(ctx.plan.bistable):
        paper = paper_window(ctx.axle, case)
        runs = jump_runs_of(ctx, i, case)
        setup = runs.setup
        named = setup.named
        if paper:
            for key in ("S1", "T1", "T2", "S2"):
                ref, got = FIG9A[key], named.get(key)
                ok = got is not None and agrees_to_printed_digits(ref, got)
                known = KNOWN_DIFFERENCES.get(f"cycles:fig9a:{key}")
                status = CheckStatus.PASS if ok else CheckStatus.KNOWN_DIFFERENCE if known and got else \
                    CheckStatus.FAIL
                rows.append(Row({"run": f"continuation {key}", "paper_kmh": ref, "reduced_kmh": got}, status,
                                "paper: agrees to the printed digits" if ok else known or "differs from the paper"))
        else:
            for key, v in sorted(named.items(), key=lambda kv: -kv[1]):
                rows.append(Row({"run": f"continuation {key}", "reduced_kmh": v}, CheckStatus.INFO,
                                "cycle fold" if key.startswith("S") else "torus point"))
        experiments = []
        for ramp, _, both in runs.ramps:
            name, edge, up = ramp.name, ramp.edge, ramp.up
            for traj, history in both:
                rec = _record(ctx, f"{name.replace(' ', '_')}_{traj.model}.rrd", traj, history,
                              f"{name}, {traj.model} model, {case.pressure_bar:g} bar", case)
                if rec:
                    recordings.append(rec)
            mark = ("S1" if up else "T2") if paper else "window end"
            experiments.append(_experiment(f"{name}, {case.pressure_bar:g} bar", both, {mark: edge}))
            recordings += _record_both(ctx, f"{name.replace(' ', '_')}_both.rrd", both,
                                       f"{name}: reduced model and MBS side by side, {case.pressure_bar:g} bar", case)
            rows.append(ramp_row(ramp, both, setup, rate=RAMP_KMH_S[ctx.quick]))
        rows += [end_row(e) for e in runs.ends]
        if not runs.ends:
            rows.append(Row({"run": "window ends"}, CheckStatus.COULD_NOT_CHECK,
                            "fewer than two stable cycles found inside the window to start the end runs from"))
        figures.append(_jump_figure(ctx, experiments, case, paper))
        # Two starts inside the window settle on different cycles.
        speed, starts = runs.start_kmh, runs.starts
        prefix = "fig11_" if paper else "two_starts_"
        finals = {}
        for label, both in starts:
            for traj, history in both:
                finals[(label, traj.model)] = history.final_mode
                rec = _record(ctx, f"{prefix}{label.replace(' ', '_')}_{traj.model}.rrd", traj, history,
                              f"start {label} at {speed:.1f} km/h, {traj.model} model", case)
                if rec:
                    recordings.append(rec)
            recordings += _record_both(ctx, f"{prefix}{label.replace(' ', '_')}_both.rrd", both,
                                       f"start {label} at {speed:.1f} km/h: reduced model and MBS side by side", case)
        rows += two_start_rows(speed, starts, finals)
        if ctx.quick:
            rows.append(Row({"run": "kick threshold"}, CheckStatus.INFO, "skipped in quick mode (tens of runs)"))
        else:
            rows += _kick_rows(ctx, setup)
    title = "Bistable jumps" + (" at t0 = 0.25 m, 1.5 bar" if ctx.plan.bistable and
                                paper_window(ctx.axle, ctx.plan.bistable[0]) else "")
    return Section(
        key="jumps", title=title,
        columns=("run", "paper_kmh", "continuation_kmh", "reduced_kmh", "mbs_reduced_kmh", "final_1", "final_2",
                 "kick_deg"),
        labels={"final_1": Column("final mode: first start, or the reduced model in an end run"),
                "final_2": Column("final mode: second start, or the MBS in an end run")},
        rows=tuple(rows), recordings=tuple(recordings), figures=tuple(figures),
        text=("Cycle folds (S) and torus points (T) from continuation. Checks (the MBS with every assumption of the "
              "reduced model on against the reduced model): at each end of the window where two stable cycles "
              f"coexist, both models run at constant speed {PAST_END_KMH:g} km/h past it, started on the cycle that "
              "ends there, must end in the same mode (at a fold both are expected to leave it; past a torus point "
              "both may stay near it, quasi-periodic, or leave); two starts inside the window, one near each cycle, "
              "must each end in the same mode in both models. Information: speed ramps up and down through the "
              "window, with the ramp rate, each model's jump speed and its delay past the window's end (a delayed "
              "loss of stability: its speed is set by how near the state is to the cycle, numerical noise, so it is "
              "not compared), a jump that came only while the ramp's end speed was held is named so; whether the "
              "two starts end on different cycles; the kick that leaves the lower state (the smallest initial "
              "theta1 from straight running, bracketed by two runs of the reduced model)."))
