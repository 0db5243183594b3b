"""Geometrically full multibody model of the truck front axle in Exudyn (issues 4 and 9).

Public API (SI inside; pressures in Pa, speeds in m/s):

* :class:`Fidelity` (``Fidelity.parse("reduced" | "full" | "name,name")``), :class:`Assumption`,
  :func:`assumptions_table` - the reduced model's assumptions as switches;
* :class:`MbsModel` (parameters, pressure effects, fidelity, :class:`AxleDimensions`);
* :class:`MbsFamily` - the model as a speed family for :func:`reduced_model.bifurcation.equilibria.hopf.hopf_points`
  (``lyapunov=False``);
* :func:`simulate` - an Exudyn simulation returning :class:`reduced_model.trajectory.Trajectory`;
* :func:`assumption_study` - Hopf-speed and limit-cycle shifts of each assumption.
"""

from dataclasses import dataclass

from mbs_shimmy import engine  # noqa: F401  (first: chooses Exudyn's compiled module before anything imports exudyn)
from mbs_shimmy.assumption_study import AssumptionRow, AssumptionStudy, HopfShift, assumption_study, match_hopf
from mbs_shimmy.dimensions import DEFAULT_DIMENSIONS, AxleDimensions
from mbs_shimmy.fidelity import ASSUMPTIONS, Assumption, AssumptionInfo, Fidelity
from mbs_shimmy.limit_cycle import SteadyAmplitude, mbs_steady_amplitude, reduced_peak, reduced_steady_amplitude
from mbs_shimmy.linearisation import MbsFamily, MbsModel
from mbs_shimmy.simulation import DEFAULT_METHOD, DEFAULT_STEP, Convergence, convergence, extended_states, simulate


@dataclass(frozen=True)
class AssumptionsTable:
    """The assumptions of the reduced model, one row per switch (see :mod:`mbs_shimmy.fidelity`)."""

    rows: tuple[AssumptionInfo, ...]

    def markdown(self) -> str:
        lines = ["| switch | assumption | where it enters (2.1)-(2.11) | full geometry instead |",
                 "|---|---|---|---|"]
        for r in self.rows:
            lines.append(f"| `{r.name}` | {r.summary} | {r.enters} | {r.full_geometry} |")
        return "\n".join(lines)


def assumptions_table() -> AssumptionsTable:
    return AssumptionsTable(ASSUMPTIONS)


__all__ = ["Assumption", "AssumptionInfo", "AssumptionRow", "AssumptionStudy", "AssumptionsTable", "AxleDimensions",
           "Convergence", "DEFAULT_DIMENSIONS", "DEFAULT_METHOD", "DEFAULT_STEP", "Fidelity", "HopfShift",
           "MbsFamily", "MbsModel", "SteadyAmplitude", "assumption_study", "assumptions_table", "convergence",
           "extended_states", "match_hopf", "mbs_steady_amplitude", "reduced_peak", "reduced_steady_amplitude",
           "simulate"]
