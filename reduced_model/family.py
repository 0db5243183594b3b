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
from bifurcation.messages import Message
from bifurcation.problem import describe
from axles.braking import BRAKE_PARAMS, FREE_ROLLING, Braking
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
    steady_tolerance = 1e-12    # |f| (rad/s, rad/s^2) at which Newton's steady state under braking is accepted
    piecewise_smooth = False    # the reduced model's f is smooth (the MBS's is not: mbs_shimmy.linearisation)

    def check_param(self) -> None:
        if self.param in BRAKE_PARAMS:
            self.braking.value(self.param)     # raises ParameterError under a brake force
        elif self.param not in PRESSURE_PARAMS:
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
        if self.param in BRAKE_PARAMS:
            return self.braking.value(self.param)
        return float(getattr(self.model.params, self.param))

    def operating(self, q: float) -> tuple[TyrePressures, Braking]:
        """(pressures, braking) at q: a pressure or brake-slip parameter moves them, any other leaves them."""
        if self.param in PRESSURE_PARAMS:
            return self.pressures.moved(self.param, q), self.braking
        if self.param in BRAKE_PARAMS:
            return self.pressures, self.braking.moved(self.param, q)
        return self.pressures, self.braking

    @property
    def origin_equilibrium(self) -> bool:
        """Straight running is x = 0 only free rolling (the toolkit then measures cycles about x = 0)."""
        return not self.braked

    @property
    def braked(self) -> bool:
        """Whether straight running may lie off x = 0 (some braking, or a brake slip being continued)."""
        return self.braking.active or self.param in BRAKE_PARAMS

    def steady(self, speed: float, q: float) -> np.ndarray:
        """Straight running under braking (:func:`steady_state`), Newton started from the steady state found
        nearest so far; kept per (speed, q) in the subclass's ``_equilibria``.

        The steady state does not depend on the speed: its rates are zero, so no gyroscopic moment acts, and the slip
        equations give alpha = -theta (the MBS: alpha = v_y / |v_x| of the steered wheel) at every V > 0.  At V = 0
        the slip equations vanish and leave it undetermined: below :data:`MIN_SPEED` it is the one at MIN_SPEED.
        So the Jacobian there is again affine in V, A0 + V A1, and the Hopf seeding by the bialternate pencil
        applies as free rolling (:func:`bifurcation.equilibria.hopf.hopf_seeds` checks the affine form)."""
        speed = max(float(speed), MIN_SPEED)
        key = (speed, float(q))
        found = self._equilibria.get(key)
        if found is None:
            start = None
            if self._equilibria:
                scale = max(abs(self.nominal), 1e-3)
                near = min(self._equilibria, key=lambda k: abs(k[0] - speed) / SPEED_SCALE + abs(k[1] - q) / scale)
                start = self._equilibria[near]
            if len(self._equilibria) > 4096:
                self._equilibria.clear()
            found = self._equilibria[key] = steady_state(self, speed, q, start)
        return found.copy()


@dataclass(frozen=True)
class SpeedFamily(ComplexStepDerivatives, ShimmyFamily):
    """f(x; V, q): the model with speed V (m/s) and parameter ``param`` = q (SI) free."""

    model: ShimmyModel
    param: str = "pressure"
    pressures: TyrePressures = TyrePressures.uniform(2.5e5)   # operating pressures; "pressure" params move them
    braking: Braking = FREE_ROLLING                           # operating braking; "brake_slip" params move it
    _cache: dict = field(default_factory=dict, init=False, compare=False, repr=False)
    _equilibria: dict = field(default_factory=dict, init=False, compare=False, repr=False)

    def __post_init__(self) -> None:
        self.check_param()

    state_names: tuple[str, ...] = field(default=STATE_NAMES, init=False, repr=False)
    state_units: tuple[str, ...] = field(default=STATE_UNITS, init=False, repr=False)

    def at(self, q: float) -> tuple[ShimmyModel, TyrePressures, Braking]:
        q = float(q)
        found = self._cache.get(q)
        if found is None:
            pressures, braking = self.operating(q)
            model = (self.model if self.param in PRESSURE_PARAMS + BRAKE_PARAMS
                     else self.model.with_params(**{self.param: q}))
            found = (model, pressures, braking)
            if len(self._cache) > 4096:
                self._cache.clear()
            self._cache[q] = found
        return found

    def rhs(self, x: np.ndarray, speed: float, q: float) -> np.ndarray:
        model, pressures, braking = self.at(q)
        return model.rhs(x, speed, pressures, braking)

    def jacobian(self, x: np.ndarray, speed: float, q: float) -> np.ndarray:
        model, pressures, braking = self.at(q)
        return model.jacobian(x, speed, pressures, braking)

    def equilibrium(self, speed: float, q: float) -> np.ndarray:
        """Straight running: x = 0 when free rolling (checked, because everything downstream assumes f(0) = 0);
        under braking the steady state Newton finds from x = 0 (:func:`steady_state`)."""
        if self.braked:
            return self.steady(speed, q)
        x0 = np.zeros(N_STATES)
        residual = np.max(np.abs(self.rhs(x0, speed, q)))
        if residual > 1e-12:
            raise ParameterError(f"straight running is not an equilibrium here (|f(0)| = {residual:.3g})")
        return x0

    def linear_matrix(self, speed: float, q: float) -> np.ndarray:
        """Jacobian at straight running: x = 0 free rolling (an equilibrium everywhere; :meth:`validate` checks
        it), the steady state under braking (the same at every speed: affine in V as free rolling)."""
        model, pressures, braking = self.at(q)
        if self.braked:
            return model.jacobian(self.equilibrium(speed, q), speed, pressures, braking)
        return model.linear_matrix(speed, pressures)

    def validate(self, q: float) -> None:
        """Raise :class:`ParameterError` if the model is meaningless at q or straight running is no equilibrium."""
        model, pressures, braking = self.at(q)
        model.tyres(pressures, braking)
        self.equilibrium(1.0, q)


def steady_state(family, speed: float, q: float, x0: np.ndarray | None = None, max_iter: int = 50) -> np.ndarray:
    """The equilibrium of ``family`` at (speed, q) by Newton's method from ``x0`` (default x = 0, straight running
    free rolling): under braking the steady brake moments deflect the steering, so straight running is not x = 0.
    Raises :class:`ParameterError` when Newton does not converge (a braking level the axle cannot hold straight)."""
    x = np.zeros(family.n) if x0 is None else np.array(x0, dtype=float)
    scale = family.state_scales(1.0)          # 0.1 rad a coordinate (and 0.1 rad/s a rate)
    for _ in range(max_iter):
        f = family.rhs(x, speed, q)
        if np.max(np.abs(f)) <= family.steady_tolerance * max(1.0, np.max(np.abs(x) / scale)):
            return x
        J = family.jacobian(x, speed, q)
        try:
            dx = np.linalg.solve(J, -f)
        except np.linalg.LinAlgError:
            break
        # damped where a step would take an angle beyond a radian: the steady state is small or it is none
        worst = np.max(np.abs(dx) / scale) * 0.1
        x = x + (dx / worst if worst > 1.0 else dx)
    residual = float(np.max(np.abs(family.rhs(x, speed, q))))
    raise ParameterError(Message.of("no steady straight running under braking found at ", describe(family, speed, q),
                                    f" (Newton from x = 0 left |f| = {residual:.3g})"))
