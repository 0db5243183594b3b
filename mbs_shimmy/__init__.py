"""Geometrically full multibody model of the truck front axle in Exudyn (issues 4 and 9).

This package face is light: it names the switches, which reading an axle needs, and loads no Exudyn.  The
dimensions it needs beyond Table 1 are axle entries (:mod:`axles.dimensions`).  The models live in their modules (SI inside; pressures in Pa, speeds in m/s), imported from there:

* :class:`Fidelity` (``Fidelity.parse("reduced" | "full" | "name,name")``), :class:`Assumption`,
  :func:`assumptions_table` - the reduced model's assumptions as switches (here);
* :class:`mbs_shimmy.model.MbsModel`, :class:`mbs_shimmy.linearisation.MbsFamily` - the model and its
  speed family for :func:`bifurcation.equilibria.hopf.find_hopf_points` (``lyapunov=False``);
* :func:`mbs_shimmy.simulation.simulate` - an Exudyn simulation returning :class:`reduced_model.trajectory.Trajectory`;

Every module that imports Exudyn imports :mod:`mbs_shimmy.engine` first, which chooses Exudyn's compiled module.
"""

from dataclasses import dataclass

from mbs_shimmy.fidelity import ASSUMPTIONS, Assumption, AssumptionInfo, Fidelity


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


__all__ = ["Assumption", "AssumptionInfo", "AssumptionsTable", "Fidelity",
           "assumptions_table"]
