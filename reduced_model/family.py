"""The shimmy model as a two-parameter family: speed V and one more named parameter q.

This is the "problem" in BifurcationKit's sense: it only evaluates the vector field and its Jacobian; the
continuation algorithms in :mod:`bifurcation.equilibria.hopf` and :mod:`bifurcation.equilibria.hopf_curves` never see the physics.
q is ``"pressure"`` (both tyres, Pa), ``"pressure_right"`` / ``"pressure_left"`` (one tyre, the other held at its
operating pressure) or any entry of :class:`~axles.parameters.ShimmyParameters`.  With different left and
right operating pressures, ``"pressure"`` moves both by the same amount and q is their mean.
"""

from __future__ import annotations

from dataclasses import dataclass, field
import numpy as np

from bifurcation.derivatives import ComplexStepDerivatives
from axles.pressures import PRESSURE_PARAMS, TyrePressures
from reduced_model.model import N_STATES, STATE_NAMES, STATE_UNITS, ShimmyModel
from axles.parameters import ParameterError, ShimmyParameters

# Scales for continuation norms and mesh monitors (what "small" and "large" mean for this problem): speed per
# unit of arclength, and the size of an oscillation per unit of arclength for each coordinate (rates scale with
# the frequency).  The lateral travel of the multibody axle moves millimetres where the angles move degrees.
SPEED_SCALE = 10.0     # m/s
COORDINATE_SCALES = {"theta1": 0.1, "theta2": 0.1, "psi": 0.1, "alpha1": 0.1, "alpha2": 0.1,   # rad
                     "phi_gear": 0.1, "y_axle": 0.005, "z_axle": 0.005}                         # rad, m, m
# Lower end of every speed window (m/s).  At V = 0 the relaxation equations lose their speed terms, two
# eigenvalues are zero and the Hopf defining system is singular: a Hopf curve that runs down to V -> 0 turns back
# on itself there instead of ending, and Newton near V = 0 is ill-conditioned.  Shimmy below walking pace is moot.
MIN_SPEED = 0.1388888888888889   # 0.5 km/h



def oscillation_scales(state_names: tuple[str, ...], omega: float) -> np.ndarray:
    """Typical size of each state in an oscillation at omega rad/s: a coordinate its :data:`COORDINATE_SCALES`
    entry, a rate (``name_dot``) omega times its coordinate's."""
    scales = []
    for name in state_names:
        coordinate = name[:-len("_dot")] if name.endswith("_dot") else name
        scale = COORDINATE_SCALES[coordinate]
        scales.append(scale * omega if coordinate != name else scale)
    return np.array(scales)


class ShimmyFamily:
    """What both shimmy models' families share (:class:`bifurcation.problem.Family`): the first
    parameter is the speed V (m/s, from :data:`MIN_SPEED`), the second ``param`` a pressure or a Table 1 entry.
    A subclass provides ``model`` (with ``params``), ``param``, ``pressures`` (the operating
    :class:`~axles.pressures.TyrePressures`) and ``state_names``."""

    primary = "speed"
    primary_scale = SPEED_SCALE
    primary_min = MIN_SPEED

    def check_param(self) -> None:
        if self.param not in PRESSURE_PARAMS:
            ShimmyParameters.unit(self.param)  # raises ParameterError for unknown names

    @property
    def n(self) -> int:
        return len(self.state_names)

    def state_scales(self, omega: float) -> np.ndarray:
        return oscillation_scales(self.state_names, omega)

    @property
    def nominal(self) -> float:
        """Current value of q, used as its scale in continuation."""
        if self.param in PRESSURE_PARAMS:
            return self.pressures.value(self.param)
        return float(getattr(self.model.params, self.param))


@dataclass(frozen=True)
class SpeedFamily(ComplexStepDerivatives, ShimmyFamily):
    """f(x; V, q): the model with speed V (m/s) and parameter ``param`` = q (SI) free."""

    model: ShimmyModel
    param: str = "pressure"
    pressures: TyrePressures = TyrePressures.uniform(2.5e5)   # operating pressures; "pressure" params move them
    _cache: dict = field(default_factory=dict, init=False, compare=False, repr=False)

    def __post_init__(self) -> None:
        self.check_param()

    state_names: tuple[str, ...] = field(default=STATE_NAMES, init=False, repr=False)
    state_units: tuple[str, ...] = field(default=STATE_UNITS, init=False, repr=False)

    def at(self, q: float) -> tuple[ShimmyModel, TyrePressures]:
        q = float(q)
        found = self._cache.get(q)
        if found is None:
            if self.param in PRESSURE_PARAMS:
                found = (self.model, self.pressures.moved(self.param, q))
            else:
                found = (self.model.with_params(**{self.param: q}), self.pressures)
            if len(self._cache) > 4096:
                self._cache.clear()
            self._cache[q] = found
        return found

    def rhs(self, x: np.ndarray, speed: float, q: float) -> np.ndarray:
        model, pressures = self.at(q)
        return model.rhs(x, speed, pressures)

    def jacobian(self, x: np.ndarray, speed: float, q: float) -> np.ndarray:
        model, pressures = self.at(q)
        return model.jacobian(x, speed, pressures)

    def equilibrium(self, speed: float, q: float) -> np.ndarray:
        """Straight running; checked, because everything downstream assumes f(0) = 0."""
        x0 = np.zeros(N_STATES)
        residual = np.max(np.abs(self.rhs(x0, speed, q)))
        if residual > 1e-12:
            raise ParameterError(f"straight running is not an equilibrium here (|f(0)| = {residual:.3g})")
        return x0

    def linear_matrix(self, speed: float, q: float) -> np.ndarray:
        """Jacobian at straight running x = 0 (an equilibrium everywhere; :meth:`validate` checks it)."""
        model, pressures = self.at(q)
        return model.linear_matrix(speed, pressures)

    def validate(self, q: float) -> None:
        """Raise :class:`ParameterError` if the model is meaningless at q or straight running is no equilibrium."""
        model, pressures = self.at(q)
        model.tyres(pressures)
        self.equilibrium(1.0, q)
