"""How a shimmy sets in at a Hopf point: softly (supercritical: the cycles born there are stable, the amplitude grows
from zero) or by a jump (subcritical: they are unstable, and the motion leaves for a distant state).

The first Lyapunov coefficient l1 says which where the right-hand side is twice differentiable at the equilibrium.
The full geometry's is not (MF 6.1's cornering stiffness has |camber|: ``mbs_shimmy.linearisation``), and there
l1 by differences is an average across the kink whose sign is no criticality.  The cycle branch born at the Hopf
point says it in every case: its first computed cycle is stable or unstable, or a cycle fold lies between them
(Kuznetsov, Elements of Applied Bifurcation Theory, 3rd ed., 2004, chapter 3: the sign of l1 decides the
stability of the cycles born at a Hopf point; the branch reads that stability directly).

At vanishing amplitude the kink decides: its quadratic coefficient a (:func:`bifurcation.equilibria.hopf.kink_coefficient`)
adds a rho^2 to the amplitude equation rho' = sigma' dp rho + a rho^2 + c rho^3 and outweighs the cubic term below
rho ~ |a / c|.  On the paper's axle a > 0 at both Hopf points at 1.5 bar: the cycles born there are unstable and
fold back at theta1 0.0097 deg, 1.3e-5 km/h from HB1 (2.2e-6 km/h from HB2), the branch's end segment locates
those folds (:mod:`bifurcation.cycles.end_segments`, its side now a's), and every cycle beyond them is stable.  So
the onset is subcritical by a jump of a hundredth of a degree.  A jump whose fold cycle stays below
:data:`JUMP_TOL_DEG` in steer and tramp is counted a soft onset in practice (:attr:`BranchOnset.soft`), with the
fold's size reported; ``tests/mbs/test_mbs_kink.py`` checks the folds against a branch started forty times
smaller and against the normal form's estimate.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np

from axles.units import kmh
from bifurcation.special_points import Criticality, PointKind


# A subcritical onset whose unstable cycles fold back below this largest angle (steer, tramp; deg) is soft in
# practice: the jump it makes is a twentieth of a degree at most, below the first cycle a branch computes (0.077 deg
# on the paper's axle) and far below the shimmy the paper reports (degrees).  A classification, stated with it.
JUMP_TOL_DEG = 0.05
ANGLES = ("theta1", "theta2", "psi")


@dataclass(frozen=True)
class BranchOnset:
    """What a Hopf point's cycle branch says of the cycles born there (:func:`branch_onset`)."""

    criticality: Criticality
    detail: str               # "the cycles born there are stable", ...
    # subcritical with a located fold: the largest angle of the fold's cycle (deg), the least size of the jump
    jump_deg: float | None = None

    @property
    def soft(self) -> bool:
        """Soft in practice: supercritical, or its unstable cycles fold back below :data:`JUMP_TOL_DEG`."""
        return self.criticality is Criticality.SUPERCRITICAL or (self.jump_deg is not None
                                                                  and self.jump_deg < JUMP_TOL_DEG)

    @property
    def kind(self) -> str:
        """"soft" or "hard" (:attr:`soft`)."""
        return "soft" if self.soft else "hard"

    @property
    def text(self) -> str:
        tail = ", a soft onset in practice" if self.soft and self.criticality is Criticality.SUBCRITICAL else ""
        return f"its branch: {self.detail} ({self.criticality.value} by its branch{tail})"


def largest_angle(names, amplitude) -> tuple[str, float] | None:
    """(name, deg) of the largest of theta1, theta2 and psi in an amplitude vector (SI), None without them."""
    found = [(n, float(np.degrees(amplitude[names.index(n)]))) for n in ANGLES if n in names]
    return max(found, key=lambda t: t[1]) if found else None


def branch_onset(diagram, hopf) -> BranchOnset | None:
    """What the cycle branch at ``hopf`` says of the cycles born there, which l1 says too where the right-hand side
    is twice differentiable and cannot where it is not (the full geometry's camber force): stable (supercritical)
    unless a cycle fold lies nearer the Hopf point than the first computed cycle, or that cycle is unstable.  None
    where no branch of ``diagram`` starts or ends there."""
    if diagram is None:
        return None
    for branch in diagram.branches:
        ends = [(end, near) for end, near in ((branch.start, branch.points[:1]), (branch.end, branch.points[-1:]))
                if end is not None and near and abs(end.p - hopf.p) <= 1e-6 * max(1.0, abs(hopf.p))]
        if not ends:
            continue
        first = ends[0][1][0]
        # a fold between the Hopf point and the first cycle: nearer in speed, or in the end segment there (its
        # cycles grow from zero amplitude to the first's; a fold just short of the first cycle in amplitude can lie
        # farther in speed, the first cycle having turned back towards the Hopf point), not the end segment at the
        # branch's other Hopf end
        first_size = np.linalg.norm(first.amplitude)
        other = branch.end if ends[0][0] is branch.start else branch.start
        folds = [s for s in branch.special_points if s.kind is PointKind.CYCLE_FOLD
                 and (abs(s.p - hopf.p) < abs(first.p - hopf.p)
                      or (s.data.get("end_segment") and np.linalg.norm(s.data["amplitude"]) < first_size
                          and (other is None or abs(s.p - hopf.p) < abs(s.p - other.p))))]
        if folds:
            fold = min(folds, key=lambda s: abs(s.p - hopf.p))
            cycle = fold.data.get("cycle")
            size = largest_angle(cycle.names, cycle.amplitude) if cycle is not None else None
            detail = (f"the cycles born there are unstable up to a cycle fold at {kmh(fold.p):.4f} km/h "
                      f"({kmh(fold.p) - kmh(hopf.p):+.2g} km/h from the Hopf point"
                      + (f", {size[0]} {size[1]:.2g} deg)" if size is not None else ")"))
            if hopf.kink_criticality is Criticality.SUBCRITICAL:
                detail += f", made by the kink (a = {hopf.kink:+.3g})"
            if size is not None and size[1] < JUMP_TOL_DEG:
                detail += f": a jump below {JUMP_TOL_DEG:g} deg"
            return BranchOnset(Criticality.SUBCRITICAL, detail, None if size is None else size[1])
        if first.stable:
            return BranchOnset(Criticality.SUPERCRITICAL, "the cycles born there are stable")
        return BranchOnset(Criticality.SUBCRITICAL, "the cycles born there are unstable")
    return None


def has_kink(family, hopf) -> bool:
    """Whether ``family``'s right-hand side has a kink at its equilibrium at ``hopf`` (straight running, or the
    steady braked state off x = 0; False where the family cannot tell, or has no such test: the reduced model is
    smooth)."""
    smooth = getattr(family, "twice_differentiable", None)
    return smooth is not None and smooth(family.equilibrium(hopf.p, hopf.q), hopf.p, hopf.q) is False


@dataclass(frozen=True)
class OnsetReading:
    """How the shimmy sets in at one Hopf point, and what says so (:func:`read_onset`)."""

    criticality: Criticality | None
    by: str                   # "l1" (smooth there), "branch" (its cycle branch), "kink" (a, no branch)
    kind: str | None          # "soft" or "hard"; None where nothing says it (a kink without a branch)
    jump_deg: float | None    # a subcritical branch's fold cycle, largest angle (deg)
    detail: str               # the branch's words, "" without one

    def to_json(self, hopf) -> dict:
        return {"criticality": self.criticality.value if self.criticality else None, "criticality_by": self.by,
                "onset": self.kind, "jump_deg": self.jump_deg,
                "kink_coefficient": hopf.kink if hopf.kink_criticality else None, "detail": self.detail or None}


def read_onset(family, hopf, diagram=None) -> OnsetReading:
    """l1's reading where the right-hand side is twice differentiable at straight running (soft where
    supercritical); where it has a kink, the branch's from ``hopf`` in ``diagram`` (:func:`branch_onset`), or
    without one the kink coefficient's criticality with the onset unknown."""
    kinked = has_kink(family, hopf)
    onset = branch_onset(diagram, hopf)
    criticality, by = onset_criticality(hopf, onset, kinked)
    if by == "l1":
        kind = None if criticality is None else ("soft" if criticality is Criticality.SUPERCRITICAL else "hard")
        return OnsetReading(criticality, by, kind, None, onset.text if onset else "")
    if onset is None:
        return OnsetReading(hopf.kink_criticality, "kink", None, None, "")
    return OnsetReading(criticality, by, onset.kind, onset.jump_deg, onset.detail)


def onset_criticality(hopf, onset: BranchOnset | None, kinked: bool) -> tuple[Criticality | None, str]:
    """(criticality, what it rests on: "l1" or "branch"): l1's where the right-hand side is twice differentiable at
    straight running; where it is not (``kinked``), l1's sign is no criticality and the branch's reading replaces
    it, or none when no branch was continued."""
    if not kinked:
        return hopf.criticality, "l1"
    return (onset.criticality, "branch") if onset is not None else (None, "branch")


def stable_sides(family, q: float, hopf, points, p_min: float, p_max: float, past: float
                 ) -> list[tuple[float, float]]:
    """The parameter intervals (p_lo, p_hi) beside the Hopf point ``hopf`` (one of ``points``) where the equilibrium
    is stable (by the eigenvalues halfway to the neighbouring Hopf point or window end), stopping ``past`` short of
    that neighbour (whose own branch stays out) and reaching ``past`` beyond the point itself: its side above
    first."""
    from bifurcation.equilibria.hopf import eigenvalues
    ordered = sorted(points, key=lambda h: h.p)
    i = next(k for k, h in enumerate(ordered) if h is hopf)
    edges = [p_min] + [h.p for h in ordered] + [p_max]
    low, high = edges[i], edges[i + 2]
    out = []
    if eigenvalues(family, 0.5 * (hopf.p + high), q)[0].real < 0.0:
        out.append((hopf.p - past, high - past if i < len(ordered) - 1 else high))
    if eigenvalues(family, 0.5 * (low + hopf.p), q)[0].real < 0.0:
        out.append((low + past if i > 0 else low, hopf.p + past))
    return out


def onset_windows(family, q: float, hopf, p_min: float, p_max: float, past: float) -> list[tuple[float, float]]:
    """Parameter intervals (p_lo, p_hi) to continue the cycles of each subcritical Hopf point (l1's sign) in: its
    :func:`stable_sides`."""
    return [w for h in sorted(hopf, key=lambda h: h.p) if h.criticality is Criticality.SUBCRITICAL
            for w in stable_sides(family, q, h, hopf, p_min, p_max, past)]


@dataclass(frozen=True)
class OnsetWindow:
    """Where a kick sets shimmy off next to a hard onset: the speed interval (m/s) beside the Hopf point where
    straight running is stable and the point's own branch has a stable cycle too (:func:`onset_window`).
    ``kind``: "window" (``interval`` set), "none" (the branch's cycles leave the side without a stable one wider
    than the minimum), "no_stable_side" (straight running is unstable on both sides of the point), "incomplete"
    (the branch stopped early: nothing is claimed)."""

    kind: str
    interval: tuple[float, float] | None = None
    message: str = ""


def onset_window(family, hopf, points, p_max: float, min_width: float, past: float,
                 budget_s: float | None = None) -> OnsetWindow:
    """The bistable window next to the Hopf point ``hopf`` (one of the window's ``points``, sorted or not): its
    cycle branch continued over the side where straight running is stable (:func:`stable_sides`, stopping
    ``past`` short of the neighbouring Hopf point), and the intervals there where two stable states coexist
    (:func:`comparisons.studies.kick.bistable_windows`, narrower than ``min_width`` dropped) that reach the point.
    Within ``budget_s`` seconds of wall clock (:mod:`comparisons.studies.budget`): past it, "incomplete"."""
    from comparisons.studies.budget import DeadlineWatch, OutOfTime
    from bifurcation.cycles.branches import CycleDiagram, branch_from_hopf
    from comparisons.studies.kick import bistable_windows
    # the point's sides whatever l1 says: at a kink a hard onset is read from its branch, not from l1's sign
    sides = stable_sides(family, family.nominal, hopf, points, 0.0, p_max, past)
    if not sides:
        return OnsetWindow("no_stable_side")
    lo, hi = sides[0]
    watch = DeadlineWatch(math.inf if budget_s is None else time.monotonic() + budget_s, family.state_names)
    try:
        branch = branch_from_hopf(family, hopf, lo, hi, others=tuple(h for h in points if h is not hopf),
                                  accept_hook=watch)
    except OutOfTime as stop:
        return OnsetWindow("incomplete", message=f"over its {budget_s:g} s budget, stopped on {stop}")
    if not branch.complete:
        return OnsetWindow("incomplete", message=str(branch.message))
    diagram = CycleDiagram(q=family.nominal, p_min=lo, p_max=hi, hopf=tuple(h for h in points if lo <= h.p <= hi),
                           branches=(branch,))
    found = [w for w in bistable_windows(diagram, family, min_width) if w[0] <= hopf.p <= w[1]]
    return OnsetWindow("window", found[0]) if found else OnsetWindow("none")
