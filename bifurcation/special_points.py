"""Kinds, statuses and records of detected points, shared by every continuation in the project."""

from __future__ import annotations

import enum
from dataclasses import dataclass, field


class PointKind(enum.Enum):
    HOPF = "hopf"
    HOPF_FOLD = "hopf_fold"                # fold of a Hopf curve in the second parameter: two Hopf points meet
    HOPF_HOPF = "hopf_hopf"                # two imaginary pairs at once
    GENERALIZED_HOPF = "generalized_hopf"  # first Lyapunov coefficient zero (Bautin point, the paper's DH)
    ZERO_HOPF = "zero_hopf"                # a real eigenvalue crosses zero on a Hopf curve
    CYCLE_FOLD = "cycle_fold"
    TORUS = "torus"
    PERIOD_DOUBLING = "period_doubling"
    CUSP_OF_CYCLES = "cusp_of_cycles"              # on a cycle-fold curve: its (p, q) projection turns back
    FOLD_FLIP = "fold_flip"                        # on a cycle-fold curve: a multiplier through -1
    FOLD_NEIMARK_SACKER = "fold_neimark_sacker"    # on a cycle-fold curve: a complex pair through the unit circle
    GENERALIZED_PERIOD_DOUBLING = "generalized_period_doubling"  # on a PD curve: the flip coefficient through zero
    CHENCINER = "chenciner"                        # on a torus curve: Re of the NS coefficient through zero
    RESONANCE_1_1 = "resonance_1_1"                # on a torus curve: the critical pair meets at +1 (kappa = 1)
    RESONANCE_1_2 = "resonance_1_2"                # on a torus curve: the critical pair meets at -1 (kappa = -1)
    RESONANCE_1_3 = "resonance_1_3"                # on a torus curve: the critical pair at exp(+-2 pi i / 3)
    RESONANCE_1_4 = "resonance_1_4"                # on a torus curve: the critical pair at +-i


class PointStatus(enum.Enum):
    LOCATED = "located"                # test function zero found to tolerance
    NOT_CONVERGED = "not_converged"    # detected in the bracket, location failed: only the bracket is known


class Criticality(enum.Enum):
    SUPERCRITICAL = "supercritical"
    SUBCRITICAL = "subcritical"


class BranchStatus(enum.Enum):
    COMPLETE = "complete"            # reached the window boundary or closed on itself
    CLOSED = "closed"                # returned to its start: a closed curve
    MAX_STEPS = "max_steps"
    STEP_UNDERFLOW = "step_underflow"
    NEWTON_FAILED = "newton_failed"
    DEGENERATE = "degenerate"        # frequency went to zero (Bogdanov-Takens-like end)
    STOPPED = "stopped"              # ended by its caller's accept hook (a time budget): the rest is not computed

    @property
    def is_complete(self) -> bool:
        return self in (BranchStatus.COMPLETE, BranchStatus.CLOSED)


class ConvergenceError(RuntimeError):
    """Newton's method did not converge; the message says where."""


@dataclass(frozen=True)
class SpecialPoint:
    """A detected point on a branch: kind, location (SI), the bracketing interval and the location status."""

    kind: PointKind
    p: float                              # the primary parameter
    q: float                              # second parameter (SI), or NaN on one-parameter branches
    bracket: tuple[float, float]              # arclength interval of the sign change
    status: PointStatus
    data: dict = field(default_factory=dict, compare=False)  # kind-specific extras (frequencies, l1, ...)
