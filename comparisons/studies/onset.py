"""How a shimmy sets in at a Hopf point: softly (supercritical: the cycles born there are stable, the amplitude grows
from zero) or by a jump (subcritical: they are unstable, and the motion leaves for a distant state).

The first Lyapunov coefficient l1 says which where the right-hand side is twice differentiable at the equilibrium.
The full geometry's is not (MF 6.1's cornering stiffness has |camber|: ``mbs_shimmy.linearisation``), and there
l1 by differences is an average across the kink whose sign is no criticality.  The cycle branch born at the Hopf
point says it in every case: its first computed cycle is stable or unstable, or a cycle fold lies between them
(Kuznetsov, Elements of Applied Bifurcation Theory, 3rd ed., 2004, chapter 3: the sign of l1 decides the
stability of the cycles born at a Hopf point; the branch reads that stability directly).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from axles.units import kmh
from bifurcation.special_points import Criticality, PointKind


@dataclass(frozen=True)
class BranchOnset:
    """What a Hopf point's cycle branch says of the cycles born there (:func:`branch_onset`)."""

    criticality: Criticality
    detail: str               # "the cycles born there are stable", ...

    @property
    def text(self) -> str:
        return f"its branch: {self.detail} ({self.criticality.value} by its branch)"


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
        folds = [s for s in branch.special_points if s.kind is PointKind.CYCLE_FOLD
                 and abs(s.p - hopf.p) < abs(first.p - hopf.p)]
        if folds:
            fold = min(folds, key=lambda s: abs(s.p - hopf.p))
            return BranchOnset(Criticality.SUBCRITICAL, f"the cycles born there are unstable up to a cycle fold at "
                                                        f"{kmh(fold.p):.4f} km/h")
        if first.stable:
            return BranchOnset(Criticality.SUPERCRITICAL, "the cycles born there are stable")
        return BranchOnset(Criticality.SUBCRITICAL, "the cycles born there are unstable")
    return None


def has_kink(family, hopf) -> bool:
    """Whether ``family``'s right-hand side has a kink at straight running at ``hopf`` (False where the family
    cannot tell, or has no such test: the reduced model is smooth)."""
    smooth = getattr(family, "twice_differentiable", None)
    return smooth is not None and smooth(np.zeros(family.n), hopf.p, hopf.q) is False


def onset_criticality(hopf, onset: BranchOnset | None, kinked: bool) -> tuple[Criticality | None, str]:
    """(criticality, what it rests on: "l1" or "branch"): l1's where the right-hand side is twice differentiable at
    straight running; where it is not (``kinked``), l1's sign is no criticality and the branch's reading replaces
    it, or none when no branch was continued."""
    if not kinked:
        return hopf.criticality, "l1"
    return (onset.criticality, "branch") if onset is not None else (None, "branch")
