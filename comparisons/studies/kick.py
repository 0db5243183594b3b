"""The kick that sets shimmy off: where two stable states coexist at one speed, the smallest initial yaw angle
of the right wheel that leaves the lower one.

Two stable states at one speed are separated by the stable manifold of an unstable periodic orbit between them
(a saddle cycle; Kuznetsov 2004, section 1.5).  Its max |theta1| says roughly how large a kick must be, but the
kick that crosses the separatrix along one line of initial states is a property of the flow, not of the orbit
alone; so the threshold is found by simulation.  Each run starts from straight running with theta1 = a (every
other state zero; under braking: the braked steady state plus that kick, the amplitudes then about it), settles
(:mod:`comparisons.studies.limit_cycle`), and is classified by the attractor whose amplitudes (max |theta1|,
max |psi|) are nearest to where it settled.  Bisection in log a brackets the threshold between the
largest kick that stays and the smallest that leaves, to ``rel_tol``; those two runs are kept as the evidence.
The bracket starts from the unstable cycle's amplitude.  Runs near the threshold linger by the saddle cycle, which
is why a run is continued until it settles rather than cut at a fixed time.
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass
from typing import Callable

import numpy as np

from axles.units import kmh
from comparisons.studies.limit_cycle import DECAYED, SteadyAmplitude
from reduced_model.model import N_STATES, STATE_NAMES

TH1 = STATE_NAMES.index("theta1")
MAX_KICK = 0.5          # rad: beyond any small-angle meaning; a state that no kick up to here leaves is kept
SMALLEST_KICK = 1e-3    # rad: the kick that finds the lower state


class KickStatus(enum.Enum):
    FOUND = "found"                  # bracketed to the tolerance
    NOT_LEFT = "not_left"            # no kick up to MAX_KICK leaves the lower state
    UNSETTLED = "unsettled"          # a run did not settle: the bracket is not trustworthy

    @property
    def is_complete(self) -> bool:
        return self is KickStatus.FOUND


@dataclass(frozen=True)
class Attractor:
    """A stable state by its amplitudes (rad): straight running is (0, 0)."""

    label: str
    theta1: float
    psi: float


@dataclass(frozen=True)
class KickThreshold:
    speed: float                     # m/s
    lower: Attractor
    upper: Attractor
    unstable_theta1: float           # max |theta1| of the separating unstable cycle (rad)
    status: KickStatus
    stays: float                     # largest kick (rad) found to stay in the lower state
    leaves: float                    # smallest kick (rad) found to leave it
    stays_run: SteadyAmplitude | None
    leaves_run: SteadyAmplitude | None
    runs: int

    @property
    def kick(self) -> float:
        """The threshold (rad): the geometric middle of the final bracket."""
        return math.sqrt(self.stays * self.leaves)


def kick_start(angle: float) -> np.ndarray:
    x0 = np.zeros(N_STATES)
    x0[TH1] = angle
    return x0


def settled_on(run: SteadyAmplitude, attractors: tuple[Attractor, Attractor]) -> int:
    """Index of the attractor nearest (in log amplitude) to where the run settled."""
    def distance(a: Attractor) -> float:
        return sum(abs(math.log(max(x, DECAYED)) - math.log(max(y, DECAYED)))
                   for x, y in ((run.theta1, a.theta1), (run.psi, a.psi)))
    return int(np.argmin([distance(a) for a in attractors]))


def kick_threshold(settle: Callable[[np.ndarray], SteadyAmplitude], speed: float,
                   states: tuple[Attractor, Attractor], unstable_theta1: float, rel_tol: float = 0.02,
                   progress: Callable[[str], None] | None = None) -> KickThreshold:
    """The smallest kick in theta1 from straight running that leaves the lower of two coexisting stable
    ``states`` for the other.  The lower state is the one a tiny kick (:data:`SMALLEST_KICK`) settles on:
    straight running itself where it is stable, otherwise the cycle its unstable manifold reaches.

    ``settle(x0)`` runs one model at ``speed`` from x0 until it settles (e.g.
    :func:`comparisons.studies.limit_cycle.reduced_steady_amplitude` or :func:`comparisons.studies.limit_cycle.mbs_steady_amplitude`
    bound to a model, pressure and speed).  ``progress(text)`` is called after each run, saying which."""
    results: dict[float, SteadyAmplitude] = {}

    def ends_on(a: float) -> int | None:
        if a not in results:
            results[a] = settle(kick_start(a))
            if progress is not None:
                progress(f"{kmh(speed):.2f} km/h, run {len(results)}: kick {math.degrees(a):.3g} deg")
        result = results[a]
        return settled_on(result, states) if result.settled else None

    first = ends_on(SMALLEST_KICK)
    if first is None:
        return KickThreshold(speed, states[0], states[1], unstable_theta1, KickStatus.UNSETTLED, SMALLEST_KICK,
                             SMALLEST_KICK, results[SMALLEST_KICK], None, 1)
    lower, upper = states[first], states[1 - first]

    def outcome(status: KickStatus, lo: float, hi: float) -> KickThreshold:
        return KickThreshold(speed, lower, upper, unstable_theta1, status, lo, hi, results.get(lo), results.get(hi),
                             len(results))

    lo, hi = SMALLEST_KICK, max(2.0 * unstable_theta1, 2.0 * SMALLEST_KICK)
    went = ends_on(hi)
    while went == first:
        lo, hi = hi, 2.0 * hi
        if hi > MAX_KICK:
            return outcome(KickStatus.NOT_LEFT, lo, hi)
        went = ends_on(hi)
    if went is None:
        return outcome(KickStatus.UNSETTLED, lo, hi)
    while hi / lo > 1.0 + rel_tol:
        mid = math.sqrt(lo * hi)
        went = ends_on(mid)
        if went is None:
            return outcome(KickStatus.UNSETTLED, lo, hi)
        lo, hi = (mid, hi) if went == first else (lo, mid)
    return outcome(KickStatus.FOUND, lo, hi)


def states_at(family, diagram, speed: float) -> tuple[list[Attractor], list[float]]:
    """The stable states at ``speed`` (straight running where it is stable, and the stable cycles of the diagram's
    branches there, each computed at exactly that speed) and the max |theta1| of its unstable cycles there."""
    from bifurcation.equilibria.hopf import eigenvalues

    stable: list[Attractor] = []
    if eigenvalues(family, speed, diagram.q)[0].real < 0.0:
        stable.append(Attractor("straight running", 0.0, 0.0))
    unstable: list[float] = []
    for i, b in enumerate(diagram.branches, 1):   # numbered as the reports number branches
        pts = list(b.points)
        for a, c in zip(pts[:-1], pts[1:]):
            if not min(a.p, c.p) <= speed <= max(a.p, c.p) or a.stable != c.stable:
                continue
            cycle = _cycle_from_either(family, a, c, speed)
            if cycle.stable:
                stable.append(Attractor(f"cycle of branch {i}", cycle.max_abs("theta1"), cycle.max_abs("psi")))
            else:
                unstable.append(cycle.max_abs("theta1"))
    return stable, unstable


def _cycle_from_either(family, a, c, speed: float):
    """The cycle at ``speed`` by Newton's method from the nearer of its two neighbours on the branch, else from
    the other: a neighbour whose mesh was refined at its step can be a start Newton does not converge from (seen at
    t0 = 0.25 m, 1.5 bar: from 199.07 km/h on 251 intervals no cycle at 199.38 km/h, from 201.43 km/h on 190 it
    converges)."""
    from bifurcation.cycles.branches import cycle_at
    from bifurcation.special_points import ConvergenceError

    first, second = sorted((a, c), key=lambda p: abs(p.p - speed))
    try:
        return cycle_at(family, first, speed)
    except ConvergenceError:
        return cycle_at(family, second, speed)


def coexisting_states(family, diagram, speed: float) -> tuple[tuple[Attractor, Attractor], float] | None:
    """The two stable states of least max |theta1| at ``speed`` (:func:`states_at`) and the max |theta1| of the
    unstable cycle between them; None where fewer than two stable states coexist."""
    stable, unstable = states_at(family, diagram, speed)
    if len(stable) < 2:
        return None
    a, b = sorted(stable, key=lambda s: s.theta1)[:2]
    between = [u for u in unstable if a.theta1 < u < b.theta1]
    return (a, b), (min(between) if between else math.sqrt(max(a.theta1, DECAYED) * b.theta1))


def stable_stretches(diagram) -> list[tuple[float, float]]:
    """(low, high) speed intervals (m/s) of consecutive stable cycles on each branch of the diagram."""
    out = []
    for b in diagram.branches:
        run: list[float] = []
        for p in list(b.points) + [None]:
            if p is not None and p.stable:
                run.append(p.p)
                continue
            if len(run) >= 2:
                out.append((min(run), max(run)))
            run = []
    return out


def stable_straight_running(family, diagram) -> list[tuple[float, float]]:
    """(low, high) speed intervals (m/s) of the diagram's window where straight running is stable: between its
    Hopf points, by the eigenvalues in the middle of each interval."""
    from bifurcation.equilibria.hopf import eigenvalues

    edges = [diagram.p_min] + sorted(h.p for h in diagram.hopf) + [diagram.p_max]
    return [(a, b) for a, b in zip(edges[:-1], edges[1:])
            if b > a and eigenvalues(family, 0.5 * (a + b), diagram.q)[0].real < 0.0]


def bistable_windows(diagram, family=None, min_width: float = 0.0) -> list[tuple[float, float]]:
    """Speed intervals (m/s) wider than ``min_width`` where two stable states coexist: stable cycles on
    overlapping stable stretches of the diagram's branches and, when ``family`` is given, a stable cycle where
    straight running is stable too (the window of a subcritical Hopf point).  Exact: the intervals' ends are
    the computed cycles' speeds and the Hopf points."""
    intervals = stable_stretches(diagram)
    if family is not None:
        intervals += stable_straight_running(family, diagram)
    edges = sorted({e for interval in intervals for e in interval})
    windows: list[tuple[float, float]] = []
    for a, b in zip(edges[:-1], edges[1:]):
        mid = 0.5 * (a + b)
        if sum(lo <= mid <= hi for lo, hi in intervals) < 2:
            continue
        if windows and windows[-1][1] == a:
            windows[-1] = (windows[-1][0], b)
        else:
            windows.append((a, b))
    return [(a, b) for a, b in windows if b - a > min_width]


def bistable_speeds(family, diagram, min_width: float = 0.0) -> list[float]:
    """The middle speed (m/s) of every window of the diagram wider than ``min_width`` where two stable states
    coexist (:func:`bistable_windows`, straight running included)."""
    return [0.5 * (a + b) for a, b in bistable_windows(diagram, family, min_width)]


def start_state(steady: np.ndarray, origin: np.ndarray | None, x0: np.ndarray) -> np.ndarray:
    """A run's start: the kick ``x0`` itself in free rolling (``origin`` None), in whichever order it comes (the
    reduced model's 8 states, or an MBS orbit's every state); under braking the steady state plus the kick, the
    shorter padded with zeros (both orders begin with the reduced model's states)."""
    x0 = np.asarray(x0, dtype=float)
    if origin is None:
        return x0
    n = max(len(steady), len(x0))
    return np.pad(np.asarray(steady, dtype=float), (0, n - len(steady))) + np.pad(x0, (0, n - len(x0)))


def settle_function(family, speed: float) -> Callable[[np.ndarray], SteadyAmplitude]:
    """Runs of the family's model at ``speed`` until they settle: the reduced model or the MBS, under the family's
    braking from its steady state plus the kick x0 (reduced-model order), measured about that steady state."""
    from comparisons.studies.limit_cycle import mbs_steady_amplitude, reduced_steady_amplitude
    from mbs_shimmy.linearisation import MbsFamily

    braking, origin = family.braking, None
    steady = np.zeros(N_STATES)
    if not family.origin_equilibrium:
        steady = family.equilibrium(speed, family.nominal)
        origin = steady[:N_STATES]

    def start(x0: np.ndarray) -> np.ndarray:
        return start_state(steady, origin, x0)

    if isinstance(family, MbsFamily):
        m = family.model
        return lambda x0: mbs_steady_amplitude(m.params, m.effects, m.fidelity, family.pressures, speed, start(x0),
                                               dims=m.dims, braking=braking, origin=origin)
    return lambda x0: reduced_steady_amplitude(family.model, family.pressures, speed, start(x0), braking=braking,
                                               origin=origin)


def kicks(family, diagram, min_width: float = 0.0, progress: Callable[[str], None] | None = None
          ) -> list[KickThreshold]:
    """The kick threshold in the middle of every bistable window of the diagram wider than ``min_width`` (m/s);
    ``progress(text)`` after each run (:func:`kick_threshold`)."""
    out = []
    for speed in bistable_speeds(family, diagram, min_width):
        found = coexisting_states(family, diagram, speed)
        if found is not None:
            out.append(kick_threshold(settle_function(family, speed), speed, *found, progress=progress))
    return out
