"""The multibody axle as one value: Table 1, the pressure effects, the fidelity switches and the chosen dimensions.

Its forces (:mod:`mbs_shimmy.forces`) and its assembled Exudyn system (:mod:`mbs_shimmy.system`) are made from it;
:class:`mbs_shimmy.linearisation.MbsFamily` continues it, :func:`mbs_shimmy.simulation.simulate` runs it.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from axles.dimensions import DEFAULT_DIMENSIONS, AxleDimensions
from axles.parameters import YANG2024, ShimmyParameters
from axles.braking import FREE_ROLLING, Braking
from axles.pressures import TyrePressures
from mbs_shimmy.fidelity import Fidelity
from mbs_shimmy.forces import AxleForces, layout_of
from mbs_shimmy.layout import Layout
from mbs_shimmy.system import MbsSystem, build_system
from reduced_model.model import Effects


@dataclass
class MbsModel:
    """The multibody axle with its parameters, pressure effects, fidelity switches and chosen dimensions."""

    params: ShimmyParameters = YANG2024
    effects: Effects = field(default_factory=Effects)
    fidelity: Fidelity = field(default_factory=Fidelity.reduced)
    dims: AxleDimensions = DEFAULT_DIMENSIONS

    def forces(self, pressures: TyrePressures, speed, acceleration=None,
               braking: Braking = FREE_ROLLING) -> AxleForces:
        return AxleForces(self.params, self.effects, self.fidelity, self.dims, pressures, speed, acceleration,
                          braking)

    def system(self, pressures: TyrePressures, speed, acceleration=None, y0=None, output_interval=None,
               drawing: bool = False, braking: Braking = FREE_ROLLING) -> MbsSystem:
        return build_system(self.params, self.effects, self.fidelity, self.dims,
                            self.forces(pressures, speed, acceleration, braking), y0, output_interval, drawing)

    @property
    def layout(self) -> Layout:
        return layout_of(self.fidelity, self.dims)
