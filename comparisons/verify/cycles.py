"""``shimmy verify``: limit cycles and bistable jumps in both models, at the planned cases.

Limit cycles: the reduced model's branches by continuation (with their cycle folds and torus points) against the
steady amplitudes of long MBS runs started on the cycle.  Bistable jumps: in a window where two stable cycles
coexist, speed ramps up and down through it and two starts inside it, in both models; the jump must come at or past
the end of the window the ramp leaves through (the lag is the delayed loss of stability of a slow passage).
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass

import numpy as np

from comparisons.axles.axle import interface_text
from comparisons.axles.paper_reference import FIG9A, KNOWN_DIFFERENCES
from comparisons.axles.units import BAR, from_kmh, kmh
from comparisons.verify.context import Context, agrees_to_printed_digits, shimmy_cases
from comparisons.verify.plan import VMAX, BistableCase
from comparisons.verify.report import CheckStatus, Row, Section
from reduced_model.bifurcation.special_points import PointKind
from reduced_model.family import SpeedFamily
from reduced_model.model import ShimmyModel

AMPLITUDE_TOL = 0.005        # relative, MBS steady amplitude against the continuation branch
WINDOW_SLACK_KMH = 0.5       # a jump may come this much before the window's end (classifier windows)


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
    mbs: object               # mbs_shimmy.limit_cycle.SteadyAmplitude
    relative_diff: float      # inf when the MBS run stopped

    @property
    def ok(self) -> bool:
        return self.relative_diff <= AMPLITUDE_TOL


def cycle_amplitude_check(model: ShimmyModel, point, pressure, dims, settle: float, x0=None) -> CycleCheck:
    """The MBS steady amplitude at the speed of ``point`` (a continuation cycle of ``model``) against the cycle's
    max|theta1|; the run starts on the cycle unless ``x0`` is given."""
    from mbs_shimmy.fidelity import Fidelity
    from mbs_shimmy.limit_cycle import mbs_steady_amplitude
    start = point.orbit.nodes[0] if x0 is None else x0
    got = mbs_steady_amplitude(model.params, model.effects, Fidelity.reduced(), pressure, point.p, start,
                               settle=settle, dims=dims)
    ref = point.max_abs("theta1")
    rel = abs(got.theta1 - ref) / ref if math.isfinite(got.theta1) else math.inf
    return CycleCheck(ref, got, rel)


def cycles_section(ctx: Context) -> Section:
    from comparisons.figures.cycle_plots import plot_cycle_overlay
    from mbs_shimmy.fidelity import Fidelity
    from mbs_shimmy.limit_cycle import mbs_steady_amplitude
    from reduced_model.bifurcation.cycles.branches import cycle_diagram
    settle = 6.0 if ctx.quick else 12.0
    rows, figures = [], []
    model = ShimmyModel(params=ctx.axle.params)
    diagrams = []
    for case in shimmy_cases(ctx):
        ctx.progress(f"Limit cycles: continuation at {case.label}")
        family = SpeedFamily(model, pressure=case.pressure)
        diagrams.append((case, family, cycle_diagram(family, family.nominal, 0.0, VMAX)))
    # MBS runs are the cost: a budget over all stable branches keeps verify's time bounded for any plan.
    stable_branches = sum(any(p.stable for p in b.points) for _, _, d in diagrams for b in d.branches)
    budget, most = (6, 2) if ctx.quick else (28, 8)
    per_branch = max(1, min(most, budget // max(1, stable_branches)))
    if not diagrams:
        rows.append(Row({}, CheckStatus.NOTHING, "no planned case where the reduced model shimmies: no limit cycle "
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
                check = cycle_amplitude_check(model, point, case.pressure, ctx.axle.dims, settle)
                full_run = mbs_steady_amplitude(model.params, model.effects, Fidelity.parse("full"),
                                                case.pressure, point.p, point.orbit.nodes[0], settle=settle,
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
        tag = case.label.replace(" ", "").replace("/", "_").replace(".", "p")
        name = f"cycles_{tag}.png"
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

def _bistable_diagram(case: BistableCase):
    from reduced_model.bifurcation.cycles.branches import cycle_diagram
    if case.value_diagram is not None:
        return case.value_diagram
    family = SpeedFamily(ShimmyModel(params=case.axle.params))
    return cycle_diagram(family, case.pressure_bar * BAR, 0.0, VMAX)


def window_points(diagram) -> dict:
    """The cycle folds and torus points that bound and cross the window, by name: S1.. (folds, by decreasing
    speed) and T1.. (torus points), as the paper names them in figure 9a."""
    folds = sorted(diagram.points_of(PointKind.CYCLE_FOLD), key=lambda s: -s.p)
    tori = sorted(diagram.points_of(PointKind.TORUS), key=lambda s: -s.p)
    named = {f"S{i}": kmh(s.p) for i, s in enumerate(folds, 1)}
    named.update({f"T{i}": kmh(s.p) for i, s in enumerate(tori, 1)})
    return named


def _snap(speed_kmh: float, points, within_kmh: float = 3.0) -> float:
    """The special point nearest a window end found from computed cycles (the end itself lies between them)."""
    nearest = min(points, key=lambda s: abs(s - speed_kmh), default=None)
    return nearest if nearest is not None and abs(nearest - speed_kmh) < within_kmh else speed_kmh


def _stable_cycles_at(diagram, speed: float) -> list:
    """The computed stable cycles nearest to ``speed`` on each stable stretch covering it."""
    out = []
    for b in diagram.branches:
        pts = list(b.points)
        for a, c in zip(pts[:-1], pts[1:]):
            if a.stable and c.stable and min(a.p, c.p) <= speed <= max(a.p, c.p):
                out.append(min((a, c), key=lambda p: abs(p.p - speed)))
    return out


def _stable_reach(diagram, cycle) -> float:
    """Lowest speed (m/s) of the stable stretch of the branch that carries ``cycle``."""
    for b in diagram.branches:
        pts = list(b.points)
        if not any(p is cycle for p in pts):
            continue
        k = next(i for i, p in enumerate(pts) if p is cycle)
        lo = cycle.p
        for step in (-1, 1):
            j = k
            while 0 <= j + step < len(pts) and pts[j + step].stable:
                j += step
                lo = min(lo, pts[j].p)
        return lo
    return cycle.p


def _classifier_for(cycles):
    """A mode classifier whose splits lie between the two coexisting cycles (the default one for the paper)."""
    from reduced_model.modes import ModeClassifier
    if len(cycles) < 2:
        return ModeClassifier()
    (a, b) = sorted(cycles[:2], key=lambda p: p.frequency_hz)
    ra, rb = (p.max_abs("psi") / p.max_abs("theta1") for p in (a, b))
    if not (rb > ra and b.frequency_hz > a.frequency_hz):
        return ModeClassifier()
    return ModeClassifier(ratio_split=math.sqrt(ra * rb), frequency_split_hz=0.5 * (a.frequency_hz + b.frequency_hz))


def _run_both(case: BistableCase, schedule, x0, duration: float, fidelity=None):
    """(reduced trajectory, MBS trajectory at ``fidelity``, default every assumption on)."""
    from mbs_shimmy.fidelity import Fidelity
    from mbs_shimmy.simulation import simulate as simulate_mbs
    from reduced_model.simulation import simulate
    model = ShimmyModel(params=case.axle.params)
    reduced = simulate(model, case.pressure_bar * BAR, schedule, duration, x0)
    multibody = simulate_mbs(model.params, model.effects, fidelity or Fidelity.reduced(), case.pressure_bar * BAR,
                             schedule, x0, duration, dims=case.axle.dims, poses=True)
    return reduced, multibody


def _record(ctx: Context, name: str, trajectory, history, title: str, case: BistableCase) -> str | None:
    if not ctx.recordings:
        return None
    from comparisons.recordings.writer import write_recording
    path = os.path.join(ctx.out, name)
    write_recording(path, trajectory, history.segments(), history.switches, title=title,
                    model=ShimmyModel(params=case.axle.params), pressure=case.pressure_bar * BAR)
    return name


def _record_both(ctx: Context, name: str, both, title: str, case: BistableCase) -> list[str]:
    """The side-by-side recording of one experiment in both models (besides one file per model)."""
    if not ctx.recordings:
        return []
    from comparisons.recordings.writer import ComparedRun, write_comparison
    write_comparison(os.path.join(ctx.out, name), [ComparedRun(t, h.segments(), h.switches) for t, h in both],
                     title, model=ShimmyModel(params=case.axle.params), pressure=case.pressure_bar * BAR)
    return [name]


def _experiment(title: str, both, marks: dict):
    from comparisons.verify.report_figures import Experiment, RunHistory
    runs = [RunHistory(t.model, t.t, kmh(t.speed), np.degrees(t.state("theta1")), np.degrees(t.state("psi")),
                       [(s.time, kmh(s.speed), f"{s.before.value} -> {s.after.value}") for s in h.switches])
            for t, h in both]
    return Experiment(title, runs, marks)


def _jump_figure(ctx: Context, experiments, case: BistableCase, paper: bool) -> str:
    from comparisons.verify.report_figures import plot_jump_histories
    name = "jumps_" + f"{case.pressure_bar:g}".replace(".", "p") + "bar.png"
    ends = "S1 (ramp up) and T2 (ramp down)" if paper else "the window's ends"
    plot_jump_histories(experiments, os.path.join(ctx.out, name),
                        title=f"Jumps between the modes in both models, {case.pressure_bar:g} bar; dashed: the speed "
                              f"passes {ends}; dotted: detected switches")
    return name


@dataclass(frozen=True)
class JumpSetup:
    """What the jump experiments of one bistable case need: the window (km/h), the two stable cycles inside it,
    the mode classifier split between them, which mode lives below and which above the window, the ramp range."""

    case: BistableCase
    diagram: object
    paper: bool               # the paper's figure 9a window: its ends are the printed T2 and S1
    named: dict               # the window's special points by name (window_points)
    low: float
    high: float
    cycles: list              # stable cycles at the window's middle
    classify: object          # trajectory -> ModeHistory
    below_mode: object
    above_mode: object
    v_lo: float
    v_hi: float

    @property
    def mid(self) -> float:
        return 0.5 * (self.low + self.high)


def jump_setup(case: BistableCase, paper: bool) -> JumpSetup:
    """The window and cycles of ``case`` from its cycle diagram (continued here if the plan did not keep it)."""
    from reduced_model.modes import Mode
    diagram = _bistable_diagram(case)
    named = window_points(diagram)
    if paper:
        low, high = named["T2"], named["S1"]
    else:   # the ends of the window are special points of the branches
        low, high = _snap(case.low_kmh, named.values()), _snap(case.high_kmh, named.values())
    mid = 0.5 * (low + high)
    cycles = _stable_cycles_at(diagram, from_kmh(mid))
    margin = max(20.0, 1.5 * (high - low))
    v_lo, v_hi = (120.0, 200.0) if paper else (max(1.0, low - margin), high + margin)
    # Which cycle lives below the window (its stable stretch reaches lower) and which above it; the classifier
    # built from the two names the lower-frequency one "yaw".  The paper: yaw below, tramp above.
    below_mode, above_mode = Mode.YAW, Mode.TRAMP
    if not paper and len(cycles) >= 2:
        reach = {id(c): _stable_reach(diagram, c) for c in cycles[:2]}
        lower = min(cycles[:2], key=lambda c: reach[id(c)])
        upper = next(c for c in cycles[:2] if c is not lower)
        if lower.frequency_hz > upper.frequency_hz:
            below_mode, above_mode = Mode.TRAMP, Mode.YAW
    return JumpSetup(case, diagram, paper, named, low, high, cycles, _classifier_for(cycles).classify, below_mode,
                     above_mode, v_lo, v_hi)


@dataclass(frozen=True)
class Ramp:
    name: str                 # "ramp up" or "ramp down"
    schedule: object          # SpeedSchedule
    duration: float           # s
    before: object            # the mode it starts in
    after: object             # the mode it must jump to
    edge: float               # km/h: the end of the window the ramp leaves through

    @property
    def up(self) -> bool:
        return self.name == "ramp up"

    def beyond(self, jump_kmh: float | None) -> bool:
        """The jump comes at or past the window's end it leaves through (a slow passage only delays it)."""
        if jump_kmh is None:
            return False
        return jump_kmh >= self.edge - WINDOW_SLACK_KMH if self.up else jump_kmh <= self.edge + WINDOW_SLACK_KMH


def ramps(setup: JumpSetup, rate_kmh_s: float) -> tuple[Ramp, Ramp]:
    """Speed ramps up and down through the whole window, starting from a small disturbance of straight running."""
    from reduced_model.trajectory import SpeedSchedule
    ramp_time = (setup.v_hi - setup.v_lo) / rate_kmh_s
    lo, hi = from_kmh(setup.v_lo), from_kmh(setup.v_hi)
    return (Ramp("ramp up", SpeedSchedule.ramp(lo, hi, ramp_time), ramp_time + 10.0, setup.below_mode,
                 setup.above_mode, setup.high),
            Ramp("ramp down", SpeedSchedule.ramp(hi, lo, ramp_time), ramp_time + 10.0, setup.above_mode,
                 setup.below_mode, setup.low))


def run_ramp(setup: JumpSetup, ramp: Ramp, fidelity=None) -> tuple[dict, list]:
    """Both models through one ramp: ({model: speed of the first before->after switch, km/h, or None},
    [(trajectory, mode history)] for the reduced model and the MBS at ``fidelity`` (default every assumption
    on))."""
    from reduced_model.simulation import initial_state
    found, both = {}, []
    for traj in _run_both(setup.case, ramp.schedule, initial_state(), ramp.duration, fidelity):
        history = setup.classify(traj)
        jumps = [s for s in history.switches if s.before is ramp.before and s.after is ramp.after]
        found[traj.model] = kmh(jumps[0].speed) if jumps else None
        both.append((traj, history))
    return found, both


def two_start_states(setup: JumpSetup) -> tuple[float, tuple]:
    """(speed km/h, ((label, state), ...)): two starts inside the window, one near each stable cycle (figure 11's
    L1 and L2 for the paper)."""
    from reduced_model.simulation import initial_state
    if setup.paper:
        return 180.0, (("L1", initial_state()), ("L2", initial_state({"theta1": 0.2, "psi": 0.01})))
    return setup.mid, tuple((f"on cycle {i}", 0.9 * c.orbit.nodes[0]) for i, c in enumerate(setup.cycles[:2], 1))


def run_start(setup: JumpSetup, speed_kmh: float, x0, duration: float) -> list:
    """Both models at constant speed from ``x0``: [(trajectory, mode history)]."""
    from reduced_model.trajectory import SpeedSchedule
    return [(traj, setup.classify(traj))
            for traj in _run_both(setup.case, SpeedSchedule.constant(from_kmh(speed_kmh)), x0, duration)]


def _kick_rows(ctx: Context, setup: JumpSetup) -> list[Row]:
    """The reduced model's kick threshold in the middle of each bistable window of its diagram."""
    from comparisons.verify.kick_rows import kick_verdict
    from mbs_shimmy.kick import kicks
    ctx.progress("Bistable jumps: kick threshold of the reduced model (tens of runs)")
    family = SpeedFamily(ShimmyModel(params=setup.case.axle.params), pressure=setup.diagram.q)
    rows = []
    for kick in kicks(family, setup.diagram):
        cells, status, text = kick_verdict(kick, "reduced model")
        rows.append(Row({"run": f"kick at {kmh(kick.speed):.2f} km/h: {kick.lower.label} -> {kick.upper.label}",
                         **cells}, status, text))
    return rows or [Row({"run": "kick threshold"}, CheckStatus.FAIL, "no two stable states coexist in the "
                                                                      "reduced model's diagram")]


def settled_apart(first, second) -> bool:
    """Two starts ended on different cycles (neither on straight running)."""
    from reduced_model.modes import Mode
    return first is not second and Mode.NONE not in (first, second)


def jumps_section(ctx: Context) -> Section:
    rows, recordings, figures = [], [], []
    for case in ctx.plan.bistable:
        ctx.progress(f"Bistable jumps: cycles at {case.pressure_bar:g} bar")
        paper = ctx.axle.is_paper and not math.isfinite(case.low_kmh)
        setup = jump_setup(case, paper)
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
        v_lo, v_hi = setup.v_lo, setup.v_hi
        experiments = []
        for ramp in ramps(setup, 2.0 if ctx.quick else 1.0):       # km/h per s
            name, edge, up = ramp.name, ramp.edge, ramp.up
            ctx.progress(f"Bistable jumps: {name} {v_lo:.0f}-{v_hi:.0f} km/h in both models")
            found, both = run_ramp(setup, ramp)
            for traj, history in both:
                rec = _record(ctx, f"{name.replace(' ', '_')}_{traj.model}.rrd", traj, history,
                              f"{name}, {traj.model} model, {case.pressure_bar:g} bar", case)
                if rec:
                    recordings.append(rec)
            mark = ("S1" if up else "T2") if paper else "window end"
            experiments.append(_experiment(f"{name}, {case.pressure_bar:g} bar", both, {mark: edge}))
            recordings += _record_both(ctx, f"{name.replace(' ', '_')}_both.rrd", both,
                                       f"{name}: reduced model and MBS side by side, {case.pressure_bar:g} bar", case)
            before, after = ramp.before, ramp.after
            ok = all(ramp.beyond(v) for v in found.values())
            rows.append(Row({"run": f"{name} {v_lo:.0f}->{v_hi:.0f} km/h" if up else
                             f"{name} {v_hi:.0f}->{v_lo:.0f} km/h", "continuation_kmh": edge,
                             "reduced_kmh": found["reduced"], "mbs_reduced_kmh": found["mbs"],
                             "model_diff_kmh": (found["mbs"] - found["reduced"]) if None not in found.values()
                             else None},
                            CheckStatus.PASS if ok else CheckStatus.FAIL,
                            f"{before.value} -> {after.value}: both models jump "
                            f"{'at or above' if up else 'at or below'} the window's end {edge:.2f} km/h (delayed by the slow passage)" if ok else
                            f"a model did not jump {before.value}->{after.value} past {edge:.2f} km/h"))
        figures.append(_jump_figure(ctx, experiments, case, paper))
        # Two starts inside the window settle on different cycles.
        duration = 20.0 if ctx.quick else 40.0
        speed, starts = two_start_states(setup)
        prefix = "fig11_" if paper else "two_starts_"
        finals = {}
        for label, x0 in starts:
            ctx.progress(f"Bistable jumps: start {label} at {speed:.1f} km/h in both models")
            both = run_start(setup, speed, x0, duration)
            for traj, history in both:
                finals[(label, traj.model)] = history.final_mode
                rec = _record(ctx, f"{prefix}{label.replace(' ', '_')}_{traj.model}.rrd", traj, history,
                              f"start {label} at {speed:.1f} km/h, {traj.model} model", case)
                if rec:
                    recordings.append(rec)
            recordings += _record_both(ctx, f"{prefix}{label.replace(' ', '_')}_both.rrd", both,
                                       f"start {label} at {speed:.1f} km/h: reduced model and MBS side by side", case)
        if len(starts) == 2:
            for m in ("reduced", "mbs"):
                a, b = finals[(starts[0][0], m)], finals[(starts[1][0], m)]
                ok = settled_apart(a, b)
                rows.append(Row({"run": f"{speed:.1f} km/h, two starts ({m})", "final_1": a.value,
                                 "final_2": b.value}, CheckStatus.PASS if ok else CheckStatus.FAIL,
                                "two different stable cycles" if ok else
                                "the two starts did not settle on different cycles"))
        else:
            rows.append(Row({"run": "two starts"}, CheckStatus.FAIL, "fewer than two stable cycles found inside the "
                                                                     "window to start from"))
        if ctx.quick:
            rows.append(Row({"run": "kick threshold"}, CheckStatus.INFO, "skipped in quick mode (tens of runs)"))
        else:
            rows += _kick_rows(ctx, setup)
    title = "Bistable jumps" + (" at t0 = 0.25 m, 1.5 bar" if ctx.axle.is_paper and ctx.plan.bistable and
                                not math.isfinite(ctx.plan.bistable[0].low_kmh) else "")
    return Section(
        key="jumps", title=title,
        columns=("run", "paper_kmh", "continuation_kmh", "reduced_kmh", "mbs_reduced_kmh", "model_diff_kmh",
                 "final_1", "final_2", "kick_deg"),
        rows=tuple(rows), recordings=tuple(recordings), figures=tuple(figures),
        text=("Cycle folds (S) and torus points (T) from continuation; speed ramps up and down through the window "
              "where two stable cycles coexist, in both models, with the detected mode switches (the jump lags the "
              "window's end because the state passes a slowly changing instability: the lag depends on the ramp "
              "rate); two starts inside the window, one near each cycle; the kick that leaves the lower state (the "
              "smallest initial theta1 from straight running, bracketed by two runs of the reduced model)."))
