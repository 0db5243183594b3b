"""The experiments of the jumps sections: at a bistable case, the window and its two states (:class:`JumpSetup`),
the speed ramps up and down through it and the two starts inside it, each run in the reduced model and the MBS.

They are the jumps section's main cost (tens of seconds of simulated time in each model), so ``verify`` runs them in
a second process while the sections before it run (:func:`start_jump_runs`, :mod:`comparisons.verify.background`);
what is checked and recorded stays in :func:`comparisons.verify.cycles.jumps_section`.  The full geometry's jumps
(:mod:`comparisons.verify.full_jumps`) use the same pieces.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from axles.units import BAR, from_kmh, kmh
from comparisons.verify.context import Context
from comparisons.verify.plan import VMAX, BistableCase
from bifurcation.special_points import PointKind
from reduced_model.model import ShimmyModel
from axles.pressures import TyrePressures
from comparisons.api import family_of

START_S = {True: 20.0, False: 40.0}       # s of each two-start and window-end run, quick mode or not
RAMP_KMH_S = {True: 2.0, False: 1.0}      # km/h per s of the ramps, quick mode or not
HOLD_S = 10.0                # s a ramp holds its end speed
PAST_END_KMH = 0.5           # how far past a window's end the constant-speed end runs go


def bistable_diagram(case: BistableCase):
    from bifurcation.cycles.branches import cycle_diagram
    if case.value_diagram is not None:
        return case.value_diagram
    family = family_of(ShimmyModel(params=case.axle.params), TyrePressures.uniform(case.pressure_bar * BAR))
    return cycle_diagram(family, case.pressure_bar * BAR, 0.0, VMAX)


def window_points(diagram) -> dict:
    """The cycle folds and torus points that bound and cross the window, by name: S1.. (folds, by decreasing
    speed) and T1.. (torus points), as the paper names them in figure 9a."""
    folds = sorted(diagram.points_of(PointKind.CYCLE_FOLD), key=lambda s: -s.p)
    tori = sorted(diagram.points_of(PointKind.TORUS), key=lambda s: -s.p)
    named = {f"S{i}": kmh(s.p) for i, s in enumerate(folds, 1)}
    named.update({f"T{i}": kmh(s.p) for i, s in enumerate(tori, 1)})
    return named


def snap(speed_kmh: float, points, within_kmh: float = 3.0) -> float:
    """The special point nearest a window end found from computed cycles (the end itself lies between them)."""
    nearest = min(points, key=lambda s: abs(s - speed_kmh), default=None)
    return nearest if nearest is not None and abs(nearest - speed_kmh) < within_kmh else speed_kmh


def stable_cycles_at(diagram, speed: float) -> list:
    """The computed stable cycles nearest to ``speed`` on each stable stretch covering it."""
    out = []
    for b in diagram.branches:
        pts = list(b.points)
        for a, c in zip(pts[:-1], pts[1:]):
            if a.stable and c.stable and min(a.p, c.p) <= speed <= max(a.p, c.p):
                out.append(min((a, c), key=lambda p: abs(p.p - speed)))
    return out


def stable_reach(diagram, cycle) -> float:
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


def classifier_for(cycles):
    """A mode classifier whose splits lie between the two coexisting cycles (the default one for the paper)."""
    from reduced_model.modes import ModeClassifier
    if len(cycles) < 2:
        return ModeClassifier()
    (a, b) = sorted(cycles[:2], key=lambda p: p.frequency_hz)
    ra, rb = (p.max_abs("psi") / p.max_abs("theta1") for p in (a, b))
    if not (rb > ra and b.frequency_hz > a.frequency_hz):
        return ModeClassifier()
    return ModeClassifier(ratio_split=math.sqrt(ra * rb), frequency_split_hz=0.5 * (a.frequency_hz + b.frequency_hz))


def run_both(case: BistableCase, schedule, x0, duration: float, fidelity=None):
    """(reduced trajectory, MBS trajectory at ``fidelity``, default every assumption on).

    The MBS runs at :data:`~mbs_shimmy.simulation.FAST_METHOD` and ``FAST_STEP`` (RK67, 1/240 s; within 1e-4 of
    every state's amplitude, ``tests/mbs/test_mbs_simulation.py``), sampled at that step: a mode switch is then
    timed to 4 ms (0.01 km/h on a 2 km/h/s ramp), and the runs cost a third of RK44 at 1 ms, whose 1e-6 these
    experiments do not use."""
    from mbs_shimmy.fidelity import Fidelity
    from mbs_shimmy.simulation import FAST_METHOD, FAST_STEP, integrate as integrate_mbs
    from reduced_model.simulation import integrate
    model = ShimmyModel(params=case.axle.params)
    pressures = TyrePressures.uniform(case.pressure_bar * BAR)
    reduced = integrate(model, pressures, schedule, duration, x0)
    multibody = integrate_mbs(model.params, model.effects, fidelity or Fidelity.reduced(), pressures,
                              schedule, x0, duration, dims=case.axle.dims, poses=True, step=FAST_STEP,
                              method=FAST_METHOD)
    return reduced, multibody


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
    diagram = bistable_diagram(case)
    named = window_points(diagram)
    if paper:
        low, high = named["T2"], named["S1"]
    else:   # the ends of the window are special points of the branches
        low, high = snap(case.low_kmh, named.values()), snap(case.high_kmh, named.values())
    mid = 0.5 * (low + high)
    cycles = stable_cycles_at(diagram, from_kmh(mid))
    margin = max(20.0, 1.5 * (high - low))
    v_lo, v_hi = (120.0, 200.0) if paper else (max(1.0, low - margin), high + margin)
    # Which cycle lives below the window (its stable stretch reaches lower) and which above it; the classifier
    # built from the two names the lower-frequency one "yaw".  The paper: yaw below, tramp above.
    below_mode, above_mode = Mode.YAW, Mode.TRAMP
    if not paper and len(cycles) >= 2:
        reach = {id(c): stable_reach(diagram, c) for c in cycles[:2]}
        lower = min(cycles[:2], key=lambda c: reach[id(c)])
        upper = next(c for c in cycles[:2] if c is not lower)
        if lower.frequency_hz > upper.frequency_hz:
            below_mode, above_mode = Mode.TRAMP, Mode.YAW
    return JumpSetup(case, diagram, paper, named, low, high, cycles, classifier_for(cycles).classify, below_mode,
                     above_mode, v_lo, v_hi)


@dataclass(frozen=True)
class Ramp:
    name: str                 # "ramp up" or "ramp down"
    schedule: object          # SpeedSchedule
    duration: float           # s
    before: object            # the mode it starts in
    after: object             # the mode a jump leads to
    edge: float               # km/h: the end of the window the ramp leaves through

    @property
    def up(self) -> bool:
        return self.name == "ramp up"


def ramps(setup: JumpSetup, rate_kmh_s: float) -> tuple[Ramp, Ramp]:
    """Speed ramps up and down through the whole window, starting from a small disturbance of straight running."""
    from reduced_model.trajectory import SpeedSchedule
    ramp_time = (setup.v_hi - setup.v_lo) / rate_kmh_s
    lo, hi = from_kmh(setup.v_lo), from_kmh(setup.v_hi)
    return (Ramp("ramp up", SpeedSchedule.ramp(lo, hi, ramp_time), ramp_time + HOLD_S, setup.below_mode,
                 setup.above_mode, setup.high),
            Ramp("ramp down", SpeedSchedule.ramp(hi, lo, ramp_time), ramp_time + HOLD_S, setup.above_mode,
                 setup.below_mode, setup.low))


@dataclass(frozen=True)
class RampJump:
    """Where and when one model left ``ramp.before`` for ``ramp.after`` in a ramp (information, not a check: the
    speed of a jump under a slow ramp is a delayed loss of stability, set by how near the state is to the cycle)."""

    speed_kmh: float | None       # None: no jump before the run ended
    time_s: float | None
    ramp_s: float                 # when the ramp reached its end speed (the hold follows)
    end_kmh: float                # the ramp's end speed, held after ramp_s

    @property
    def in_hold(self) -> bool:
        return self.time_s is not None and self.time_s > self.ramp_s


def ramp_jump(ramp: Ramp, history, setup: JumpSetup) -> RampJump:
    jumps = [s for s in history.switches if s.before is ramp.before and s.after is ramp.after]
    ramp_s = ramp.duration - HOLD_S
    end = setup.v_hi if ramp.up else setup.v_lo
    if not jumps:
        return RampJump(None, None, ramp_s, end)
    return RampJump(kmh(jumps[0].speed), jumps[0].time, ramp_s, end)


def run_ramp(setup: JumpSetup, ramp: Ramp, fidelity=None) -> tuple[dict, list]:
    """Both models through one ramp: ({model: speed of the first before->after switch, km/h, or None},
    [(trajectory, mode history)] for the reduced model and the MBS at ``fidelity`` (default every assumption
    on))."""
    from reduced_model.simulation import initial_state
    found, both = {}, []
    for traj in run_both(setup.case, ramp.schedule, initial_state(), ramp.duration, fidelity):
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
            for traj in run_both(setup.case, SpeedSchedule.constant(from_kmh(speed_kmh)), x0, duration)]


def end_cycle(diagram, cycle, end_kmh: float):
    """The computed cycle nearest ``end_kmh`` on the stable stretch of the branch that carries ``cycle``: the
    cycle that ends at that end of the window."""
    for b in diagram.branches:
        pts = list(b.points)
        k = next((i for i, p in enumerate(pts) if p is cycle), None)
        if k is None:
            continue
        stretch = [cycle]
        for step in (-1, 1):
            j = k
            while 0 <= j + step < len(pts) and pts[j + step].stable:
                j += step
                stretch.append(pts[j])
        return min(stretch, key=lambda p: abs(kmh(p.p) - end_kmh))
    return cycle


@dataclass(frozen=True)
class EndRun:
    """At one end of a bistable window: both models at constant speed just past it, started on the stable cycle
    that ends there (a fold: it no longer exists; a torus point: it lost stability, the motion may stay near it)."""

    end: str                  # "upper" or "lower"
    end_kmh: float            # the window's end (a cycle fold or a torus point)
    point: str                # its name (S1, T2, ...), or "" when the end is not a named special point
    speed_kmh: float          # the constant speed of the runs, PAST_END_KMH beyond the end
    start_mode: object        # the mode of the cycle the runs start on
    cycle_kmh: float          # the speed of that computed cycle
    both: tuple               # ((trajectory, mode history), ...) reduced model and MBS


def end_runs(setup: JumpSetup, duration: float) -> tuple[EndRun, ...]:
    """Both models just past each end of the window, from the cycle that ends there (:class:`EndRun`); none when
    the window's two cycles were not found."""
    if len(setup.cycles) < 2:
        return ()
    reach = {id(c): stable_reach(setup.diagram, c) for c in setup.cycles[:2]}
    lower = min(setup.cycles[:2], key=lambda c: reach[id(c)])
    upper = next(c for c in setup.cycles[:2] if c is not lower)
    names = {round(v, 6): k for k, v in setup.named.items()}
    out = []
    for end, edge, cycle, mode, sign in (("upper", setup.high, lower, setup.below_mode, 1.0),
                                         ("lower", setup.low, upper, setup.above_mode, -1.0)):
        start = end_cycle(setup.diagram, cycle, edge)
        speed = edge + sign * PAST_END_KMH
        both = tuple(run_start(setup, speed, start.orbit.nodes[0], duration))
        out.append(EndRun(end, edge, names.get(round(edge, 6), ""), speed, mode, kmh(start.p), both))
    return tuple(out)


@dataclass(frozen=True)
class JumpRuns:
    """One bistable case's experiments: its setup, each ramp with the jump speeds found in both models and the two
    runs ({model: km/h or None}, [(trajectory, mode history)]), and the two starts at ``start_kmh``."""

    setup: JumpSetup
    ramps: tuple                   # ((Ramp, found, both), ...)
    start_kmh: float
    starts: tuple                  # ((label, both), ...)
    ends: tuple = ()               # (EndRun, ...)


def paper_window(axle, case: BistableCase) -> bool:
    """Whether the case is the paper's figure 9a window (its ends the printed S1 and T2): the paper's truck, whose
    plan leaves the window to the continuation."""
    return axle.is_paper and not math.isfinite(case.low_kmh)


def jump_runs(case: BistableCase, paper: bool, quick: bool) -> JumpRuns:
    setup = jump_setup(case, paper)
    ramp_runs = tuple((ramp, *run_ramp(setup, ramp)) for ramp in ramps(setup, RAMP_KMH_S[quick]))
    speed, starts = two_start_states(setup)
    start_runs = tuple((label, run_start(setup, speed, x0, START_S[quick])) for label, x0 in starts)
    return JumpRuns(setup, ramp_runs, speed, start_runs, end_runs(setup, START_S[quick]))


def _key(i: int) -> str:
    return f"jumps_{i}"


def start_jump_runs(ctx: Context) -> None:
    """Start every bistable case's runs in the background."""
    if ctx.background is None:
        return
    for i, case in enumerate(ctx.plan.bistable):
        ctx.background.submit(_key(i), jump_runs, case, paper_window(ctx.axle, case), ctx.quick)


def jump_runs_of(ctx: Context, i: int, case: BistableCase) -> JumpRuns:
    """The runs of the plan's i-th bistable case: from the background job, or computed here when none was
    started."""
    if ctx.background is not None and ctx.background.started(_key(i)):
        ctx.progress("Bistable jumps: waiting for the ramps and starts (run in a second process)")
        return ctx.background.result(_key(i))
    ctx.progress(f"Bistable jumps: ramps and starts at {case.pressure_bar:g} bar in both models")
    return jump_runs(case, paper_window(ctx.axle, case), ctx.quick)
