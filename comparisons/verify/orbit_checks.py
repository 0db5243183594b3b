"""Continued orbits and special points of a model checked against that model's own simulations (issue 16, item 4).

Only orbits whose Floquet multipliers let a run of :data:`comparisons.studies.limit_cycle.SETTLE` seconds decide are
sampled (:func:`decides_within`: not those next to a Hopf point or a fold, where |mu| is near 1).

* A stable orbit is what a long simulation settles on: started 2 % inside it (every state scaled by 0.98, so that
  it must attract to pass), the run's max |theta1| and frequency of theta1 over its last settled window must lie
  within :data:`ORBIT_TOL` of the orbit's (:func:`comparisons.studies.limit_cycle.mbs_steady_amplitude`).
* A simulation leaves an unstable orbit: from the same start, it ends more than :data:`LEFT_TOL` away from the
  orbit's max |theta1| (on another state: straight running or another cycle).
* A cycle fold, torus or period-doubling point is bracketed by the branch's computed cycles nearest to it on either
  side of its change of stability (among the few next to it, one a run can decide), each checked as above; beyond
  a fold (where no cycle of the branch exists) a run started on the fold's orbit must leave it.  A side with no
  cycle a run can decide gets no run: :func:`undecided_sides` names it.

``settle(speed)`` gives a function x0 -> :class:`~comparisons.studies.limit_cycle.SteadyAmplitude` that runs the model at
that speed until it settles (:func:`comparisons.studies.kick.settle_function`): the checks are the same for the reduced
model and the MBS.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

import numpy as np

from axles.units import from_kmh
from comparisons.studies.limit_cycle import SETTLE
from bifurcation.special_points import PointKind

ORBIT_TOL = 0.005        # relative: max |theta1| and frequency of a stable orbit against the simulation
LEFT_TOL = 0.05          # relative: a run that ends farther than this from an unstable orbit has left it
START_SCALE = 0.98       # the run starts on the orbit's first node scaled by this
BEYOND_FOLD_KMH = 1.0    # how far past a fold the run on the fold's orbit is made (km/h)


@dataclass(frozen=True)
class OrbitCheck:
    """One continued orbit against a simulation of the same model at its speed, started next to it."""

    cycle: object             # the CyclePoint checked
    run: object               # SteadyAmplitude of the simulation
    speed: float              # m/s of the run (the orbit's own, or past a fold)

    @property
    def theta1_diff(self) -> float:
        ref = self.cycle.max_abs("theta1")
        return abs(self.run.theta1 - ref) / ref if math.isfinite(self.run.theta1) else math.inf

    @property
    def frequency_diff(self) -> float:
        f = self.run.frequency_hz
        return abs(f - self.cycle.frequency_hz) / self.cycle.frequency_hz if math.isfinite(f) else math.inf

    @property
    def expect_stays(self) -> bool:
        return self.cycle.stable and self.speed == self.cycle.p

    @property
    def ok(self) -> bool:
        if self.expect_stays:
            return self.run.settled and self.theta1_diff <= ORBIT_TOL and self.frequency_diff <= ORBIT_TOL
        return self.theta1_diff > LEFT_TOL

    @property
    def verdict(self) -> str:
        if self.expect_stays:
            return ("the simulation settles on the orbit" if self.ok else
                    f"the simulation does not settle within {ORBIT_TOL:.1%} of the orbit"
                    + ("" if self.run.settled else " (it did not settle)"))
        return ("the simulation leaves the orbit" if self.ok else
                f"the simulation stays within {LEFT_TOL:.0%} of an orbit that should not hold it")


def check_orbit(settle: Callable[[float], Callable], cycle, speed: float | None = None) -> OrbitCheck:
    """The simulation at ``speed`` (default the orbit's) from the orbit's first node scaled by :data:`START_SCALE`."""
    speed = cycle.p if speed is None else speed
    return OrbitCheck(cycle, settle(speed)(START_SCALE * cycle.orbit.nodes[0]), speed)


def decides_within(cycle, seconds: float) -> bool:
    """Whether a run started :data:`START_SCALE` inside the orbit can meet its test within ``seconds``: the
    largest nontrivial Floquet multiplier mu shrinks the start's offset below a tenth of :data:`ORBIT_TOL` (stable
    orbit) or grows it past ten times :data:`LEFT_TOL` (unstable), |mu|^(seconds / period).  Next to a Hopf point
    or a fold |mu| is near 1 and no run of that length decides."""
    mu = float(np.max(np.abs(cycle.nontrivial)))
    offset = 1.0 - START_SCALE
    factor = mu ** (seconds / cycle.period)
    return factor <= 0.1 * ORBIT_TOL / offset if cycle.stable else factor >= 10.0 * LEFT_TOL / offset


def sample_orbits(branch, count: int, stable: bool, seconds: float = SETTLE) -> list:
    """Up to ``count`` computed orbits of one stability spread along the branch, among those a run of
    ``seconds`` can decide (:func:`decides_within`)."""
    inner = [p for p in branch.points if p.stable == stable and decides_within(p, seconds)]
    if len(inner) <= count:
        return inner
    step = (len(inner) - 1) / max(1, count - 1)
    return [inner[round(i * step)] for i in range(count)]


def bracketing_cycles(branch, point, seconds: float = SETTLE) -> tuple[object | None, object | None]:
    """The computed cycles of ``branch`` nearest to the special ``point`` on its stable and on its unstable side
    (by speed, among the cycles next to it along the branch), those a run of ``seconds`` can decide
    (:func:`decides_within`) first."""
    pts = list(branch.points)
    if not pts:
        return None, None
    located = point.data.get("cycle")
    k = min(range(len(pts)), key=lambda i: abs(pts[i].p - point.p)
            + (0.0 if located is None else abs(pts[i].max_abs("theta1") - located.max_abs("theta1"))))
    near = pts[max(0, k - 2):k + 3]

    def nearest(stable: bool):
        return min((p for p in near if p.stable == stable), default=None,
                   key=lambda p: (not decides_within(p, seconds), abs(p.p - point.p)))
    return nearest(True), nearest(False)


def beyond_fold(branch, point) -> float:
    """A speed (m/s) past the fold ``point``, on the side where the branch has no cycles near it."""
    near = [p.p for p in branch.points if abs(p.p - point.p) < from_kmh(10.0)] or [point.p]
    side = 1.0 if point.p >= sum(near) / len(near) else -1.0
    return point.p + side * from_kmh(BEYOND_FOLD_KMH)


def bracket_special_point(settle, branch, point) -> list[tuple[str, OrbitCheck]]:
    """(what, check) pairs that bracket a special point by simulations on either side."""
    stable, unstable = bracketing_cycles(branch, point)
    out = []
    if stable is not None and decides_within(stable, SETTLE):
        out.append(("stable side", check_orbit(settle, stable)))
    if point.kind is PointKind.CYCLE_FOLD and "cycle" in point.data:
        out.append(("past the fold", check_orbit(settle, point.data["cycle"], beyond_fold(branch, point))))
    elif unstable is not None and decides_within(unstable, SETTLE):
        out.append(("unstable side", check_orbit(settle, unstable)))
    return out


def undecided_sides(branch, point) -> list[str]:
    """The sides of a special point that :func:`bracket_special_point` leaves unchecked: those whose nearest
    computed cycles are all too close to |mu| = 1 for a run to decide."""
    stable, unstable = bracketing_cycles(branch, point)
    out = []
    if stable is not None and not decides_within(stable, SETTLE):
        out.append("stable side")
    if point.kind is not PointKind.CYCLE_FOLD and unstable is not None and not decides_within(unstable, SETTLE):
        out.append("unstable side")
    return out
