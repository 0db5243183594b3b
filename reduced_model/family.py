"""The shimmy model as a two-parameter family: speed V and one more named parameter q.

This is the "problem" in BifurcationKit's sense: it only evaluates the vector field and its Jacobian; the
continuation algorithms in :mod:`reduced_model.hopf` and :mod:`reduced_model.hopf_curves` never see the physics.
q is ``"pressure"`` (both tyres, Pa), ``"pressure_right"`` / ``"pressure_left"`` (one tyre, the other held at its
operating pressure) or any entry of :class:`~reduced_model.parameters.ShimmyParameters`.  With different left and
right operating pressures, ``"pressure"`` moves both by the same amount and q is their mean.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Sequence

import numpy as np

from .model import N_STATES, STATE_NAMES, ShimmyModel
from .parameters import ParameterError, ShimmyParameters

# Scales for continuation norms and mesh monitors (what "small" and "large" mean for this problem): speed per
# unit of arclength, and the angle of an oscillation per unit of arclength (rates scale with the frequency).
SPEED_SCALE = 10.0     # m/s
ANGLE_SCALE = 0.1      # rad
ANGLE_STATES = np.array([name in ("theta1", "theta2", "psi", "alpha1", "alpha2") for name in STATE_NAMES])

# How parameters are shown at the interface (label, factor from SI); everything else is shown in SI.
DISPLAY = {"pressure": ("bar", 1e-5), "pressure_left": ("bar", 1e-5), "pressure_right": ("bar", 1e-5),
           "speed": ("km/h", 3.6)}
PRESSURE_PARAMS = ("pressure", "pressure_right", "pressure_left")


def pressure_pair(pressure: float | Sequence[float]) -> tuple[float, float]:
    """(right, left) tyre pressures of one value or a pair (Pa)."""
    if isinstance(pressure, (int, float, np.floating)):
        return float(pressure), float(pressure)
    right, left = pressure
    return float(right), float(left)


def pressure_at(param: str, q: float, operating: float | Sequence[float]) -> float | tuple[float, float]:
    """The tyre pressures when pressure parameter ``param`` is q (one float where both tyres are alike)."""
    right, left = pressure_pair(operating)
    if param == "pressure":
        if right == left:
            return q
        mean = 0.5 * (right + left)
        right, left = q + (right - mean), q + (left - mean)
    elif param == "pressure_right":
        right = q
    elif param == "pressure_left":
        left = q
    else:
        raise ValueError(f"not a pressure parameter: {param}")
    return right if right == left else (right, left)


def pressure_value(param: str, operating: float | Sequence[float]) -> float:
    """q of a pressure parameter at the operating pressures."""
    right, left = pressure_pair(operating)
    return {"pressure": 0.5 * (right + left) if right != left else right, "pressure_right": right,
            "pressure_left": left}[param]


def display_unit(name: str) -> tuple[str, float]:
    if name in DISPLAY:
        return DISPLAY[name]
    return ShimmyParameters.unit(name), 1.0


@dataclass(frozen=True)
class SpeedFamily:
    """f(x; V, q): the model with speed V (m/s) and parameter ``param`` = q (SI) free."""

    model: ShimmyModel
    param: str = "pressure"
    pressure: float | tuple[float, float] = 2.5e5  # used when param is not "pressure"
    _cache: dict = field(default_factory=dict, init=False, compare=False, repr=False)

    def __post_init__(self) -> None:
        if self.param not in PRESSURE_PARAMS:
            ShimmyParameters.unit(self.param)  # raises ParameterError for unknown names

    @property
    def n(self) -> int:
        return N_STATES

    speed_scale: float = field(default=SPEED_SCALE, init=False, repr=False)
    state_names: tuple[str, ...] = field(default=STATE_NAMES, init=False, repr=False)

    def state_scales(self, omega: float) -> np.ndarray:
        """Typical size of each state in an oscillation at omega rad/s: angles ANGLE_SCALE, rates omega times
        that (used by the generic cycle code for its norms)."""
        return np.where(ANGLE_STATES, ANGLE_SCALE, ANGLE_SCALE * omega)

    @property
    def nominal(self) -> float:
        """Current value of q, used as its scale in continuation."""
        if self.param in PRESSURE_PARAMS:
            return pressure_value(self.param, self.pressure)
        return float(getattr(self.model.params, self.param))

    def at(self, q: float) -> tuple[ShimmyModel, float | Sequence[float]]:
        q = float(q)
        found = self._cache.get(q)
        if found is None:
            if self.param in PRESSURE_PARAMS:
                found = (self.model, pressure_at(self.param, q, self.pressure))
            else:
                found = (self.model.with_params(**{self.param: q}), self.pressure)
            if len(self._cache) > 4096:
                self._cache.clear()
            self._cache[q] = found
        return found

    def rhs(self, x: np.ndarray, speed: float, q: float) -> np.ndarray:
        model, pressure = self.at(q)
        return model.rhs(x, speed, pressure)

    def jacobian(self, x: np.ndarray, speed: float, q: float) -> np.ndarray:
        model, pressure = self.at(q)
        return model.jacobian(x, speed, pressure)

    def equilibrium(self, speed: float, q: float) -> np.ndarray:
        """Straight running; checked, because everything downstream assumes f(0) = 0."""
        x0 = np.zeros(N_STATES)
        residual = np.max(np.abs(self.rhs(x0, speed, q)))
        if residual > 1e-12:
            raise ParameterError(f"straight running is not an equilibrium here (|f(0)| = {residual:.3g})")
        return x0

    def linear_matrix(self, speed: float, q: float) -> np.ndarray:
        """Jacobian at straight running x = 0 (an equilibrium everywhere; :meth:`validate` checks it)."""
        model, pressure = self.at(q)
        return model.linear_matrix(speed, pressure)

    def validate(self, q: float) -> None:
        """Raise :class:`ParameterError` if the model is meaningless at q or straight running is no equilibrium."""
        model, pressure = self.at(q)
        model.tyres(pressure)
        self.equilibrium(1.0, q)
