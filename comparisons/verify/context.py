"""What every verify section shares: the run's context (axle, plan, output folder, progress), the tolerances of
the equivalence checks, and the cases where the reduced model shimmies.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable

from axles.axle import AxleData
from axles.braking import Braking
from comparisons.verify.background import Background
from comparisons.verify.plan import VMAX, Plan
from comparisons.verify.report import CheckStatus
from bifurcation.equilibria.hopf import find_hopf_points
from reduced_model.model import Effects, ShimmyModel
from comparisons.api import family_of

MODEL_SETS = (("section 3", Effects()), ("extended (all effects)", Effects.parse("all")))
HOPF_TOL_KMH = 0.01          # MBS (reduced fidelity) against the reduced model
EIGEN_TOL = 1e-9             # relative, MBS (reduced fidelity) eigenvalues against the reduced model's
EIGEN_SPEEDS_KMH = (20.0, 60.0, 150.0, 300.0)


@dataclass(frozen=True)
class Context:
    out: str
    quick: bool
    axle: AxleData = field(default_factory=AxleData)
    plan: Plan | None = None
    recordings: bool = True
    progress: Callable[[str], None] = field(default=lambda message: None, compare=False)
    background: Background | None = field(default=None, compare=False)   # jobs started early, collected later
    braking: Braking | None = None    # verify --brake-slip/--brake-force: the "Under braking" section's level


def printed_decimals(value: float) -> int:
    text = repr(value)
    return len(text.split(".")[1]) if "." in text else 0


def agrees_to_printed_digits(printed: float, computed: float) -> bool:
    digits = printed_decimals(printed)
    return abs(round(computed, digits) - printed) < 0.5 * 10 ** -digits


def worst(*statuses: CheckStatus) -> CheckStatus:
    for s in (CheckStatus.FAIL, CheckStatus.KNOWN_DIFFERENCE, CheckStatus.PASS):
        if s in statuses:
            return s
    return CheckStatus.INFO


def shimmy_cases(ctx: Context):
    """The planned cases where straight running of the reduced model loses stability somewhere in 0-400 km/h."""
    model = ShimmyModel(params=ctx.axle.params)
    out = []
    for c in ctx.plan.cases:
        family = family_of(model, c.pressures)
        if find_hopf_points(family, family.nominal, 0.0, VMAX, lyapunov=False):
            out.append(c)
    return out
