"""The 3-DOF truck front-axle shimmy model, eqs. (2.1)-(2.11) of Yang, Knowles & Mavros.

State (SI): ``x = (theta1, theta1_dot, theta2, theta2_dot, psi, psi_dot, alpha1, alpha2)``: yaw angles of the right
(1) and left (2) wheel about their kingpins, axle tramp angle, tyre slip angles.  The left wheel carries the drag
link (k2, c2).  The section 3 model uses constant a0, t0, sigma0, k5_0; the extended model of section 5 switches
on, each on its own, the pressure dependence of the half contact length (``hcl``, eq. 4.1), pneumatic trail
(``pt``, 4.2-4.8), relaxation length (``rl``, 4.9) and vertical stiffness (``vs``, 4.10).  The lateral force always
depends on pressure (2.4-2.9).  Left and right tyre may have different pressures.

Straight running x = 0 is an equilibrium for every speed and pressure because F_y(0) = 0; the Jacobian there is
affine in the speed (V enters only through V/R and V/sigma), which :mod:`bifurcation.equilibria.hopf` exploits.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Iterable

import numpy as np

from bifurcation.messages import Message, Quantity
from axles.parameters import YANG2024, ParameterError, ShimmyParameters
from axles.braking import FREE_ROLLING, Braking
from axles.pressures import TyrePressures
from reduced_model import tyre

STATE_NAMES = ("theta1", "theta1_dot", "theta2", "theta2_dot", "psi", "psi_dot", "alpha1", "alpha2")
STATE_UNITS = ("rad", "rad/s", "rad", "rad/s", "rad", "rad/s", "rad", "rad")
N_STATES = len(STATE_NAMES)
EFFECT_NAMES = ("hcl", "pt", "rl", "vs")
_COMPLEX_STEP = 1e-30
_STEP_MATRIX = 1j * _COMPLEX_STEP * np.eye(8)


@dataclass(frozen=True)
class Effects:
    """Which tyre properties follow the inflation pressure (section 5); all off is the section 3 model."""

    hcl: bool = False
    pt: bool = False
    rl: bool = False
    vs: bool = False

    @classmethod
    def parse(cls, text: str | Iterable[str] | None) -> "Effects":
        """``"hcl,pt"``, ``"all"``, ``"none"`` or ``""`` (or an iterable of names)."""
        if text is None:
            return cls()
        names = [s.strip() for s in (text.split(",") if isinstance(text, str) else text) if s.strip()]
        if names in (["all"],):
            return cls(True, True, True, True)
        if names in ([], ["none"]):
            return cls()
        unknown = [n for n in names if n not in EFFECT_NAMES]
        if unknown:
            raise ParameterError(f"unknown effect '{unknown[0]}' (known: {', '.join(EFFECT_NAMES)}, all, none)")
        return cls(**{n: True for n in names})

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(n for n in EFFECT_NAMES if getattr(self, n))

    @classmethod
    def cumulative(cls) -> tuple["Effects", ...]:
        """The paper's figure-17 sequence: LF, +HCL, +PT, +RL, +VS."""
        return tuple(cls.parse(EFFECT_NAMES[:k]) for k in range(len(EFFECT_NAMES) + 1))


@dataclass(frozen=True)
class WheelTyre:
    """Tyre properties of one wheel at its inflation pressure (SI)."""

    pressure: float
    force: tyre.MagicFormula
    trail: tyre.TrailFormula | None  # None: constant trail t0
    t0: float
    a: float
    sigma: float
    k5: float
    combined: tyre.CombinedSlip | None = None   # under braking: F_x and the combined-slip F_y (None: pure slip)

    def trail_at(self, alpha):
        return self.t0 if self.trail is None else self.trail.trail(alpha)


def contact_lengths(params: ShimmyParameters, effects: Effects, pressure: float) -> tuple[float, float]:
    """(half contact length a, relaxation length sigma) of a tyre: following the pressure (and the load
    ``params.Fz``) with HCL and RL, the constants a0 and sigma0 without."""
    a = tyre.half_contact_length(params, pressure) if effects.hcl else params.a0
    sigma = tyre.relaxation_length(params, pressure) if effects.rl else params.sigma0
    return a, sigma


def wheel_slip(params: ShimmyParameters, pressure: float, braking: Braking, side: float) -> float:
    """ISO longitudinal slip kappa (braking negative) of the wheel on ``side`` (-1 right, +1 left) under ``braking``:
    the brake slip given, or the one at which the tyre gives the brake force given at straight running."""
    value = braking.right if side < 0.0 else braking.left
    return -(tyre.brake_slip_for_force(params, pressure, value) if braking.by_force else value)


def braked(wheel: "WheelTyre", params: ShimmyParameters, braking: Braking, side: float,
           rl: bool = False) -> "WheelTyre":
    """The wheel under ``braking`` (unchanged without): its combined-slip forces at its slip, the right wheel's
    (``side`` -1) tyre mirrored (:class:`~reduced_model.tyre.CombinedSlip`); with ``rl`` (the relaxation length
    following the tyre, (4.9)) its relaxation length follows the braking too
    (:func:`~reduced_model.tyre.braked_relaxation_length`)."""
    if not braking.active:
        return wheel
    kappa = wheel_slip(params, wheel.pressure, braking, side)
    combined = tyre.combined_slip(params, wheel.pressure, kappa, mirrored=side < 0.0)
    return dataclasses.replace(wheel, combined=combined.following_braking() if rl else combined)


def _wheel_tyre(params: ShimmyParameters, effects: Effects, pressure: float) -> WheelTyre:
    if not pressure > 0.0:
        raise ParameterError(Message.of("inflation pressure must be positive, got ", Quantity("pressure", pressure, 10)))
    mf = tyre.magic_formula(params, pressure)
    trail = tyre.trail_formula(params, pressure) if effects.pt else None
    a, sigma = contact_lengths(params, effects, pressure)
    k5 = tyre.vertical_stiffness(params, pressure) if effects.vs else params.k5_0
    t_nominal = trail.Dt if trail is not None else params.t0
    checks = (("magic-formula peak force D_y", mf.D, "N"), ("cornering stiffness K_ya", mf.K, "N/rad"),
              ("half contact length", a, "m"), ("relaxation length", sigma, "m"),
              ("pneumatic trail", t_nominal, "m"), ("vertical stiffness k5", k5, "N/m"))
    for what, value, unit in checks:
        if not value > 0.0:
            raise ParameterError(Message.of(f"{what} is {value:.4g} {unit} at ", Quantity("pressure", pressure, 10),
                                            ": the model is meaningless there"))
    return WheelTyre(pressure=pressure, force=mf, trail=trail, t0=params.t0, a=a, sigma=sigma, k5=k5)


@dataclass(frozen=True)
class ShimmyModel:
    """Vector field f(x; V, p_i) of eqs. (2.1)-(2.11) at the tyre pressures ``pressures`` (Pa)."""

    params: ShimmyParameters = YANG2024
    effects: Effects = Effects()
    # Tyre properties per pressure pair; per instance because hashing 56 parameters per call costs more than rhs.
    _tyre_cache: dict = dataclasses.field(default_factory=dict, init=False, compare=False, repr=False)

    def with_params(self, **overrides: float) -> "ShimmyModel":
        return dataclasses.replace(self, params=self.params.replace(**overrides))

    def tyres(self, pressures: TyrePressures, braking: Braking = FREE_ROLLING) -> tuple[WheelTyre, WheelTyre]:
        """(right, left) tyre properties at the tyres' pressures, under ``braking``."""
        key = (pressures, braking)
        found = self._tyre_cache.get(key)
        if found is None:
            rl = self.effects.rl
            found = (braked(_wheel_tyre(self.params, self.effects, pressures.right), self.params, braking, -1.0, rl),
                     braked(_wheel_tyre(self.params, self.effects, pressures.left), self.params, braking, 1.0, rl))
            if len(self._tyre_cache) > 4096:
                self._tyre_cache.clear()
            self._tyre_cache[key] = found
        return found

    def rhs(self, x: np.ndarray, speed: float, pressures: TyrePressures,
            braking: Braking = FREE_ROLLING) -> np.ndarray:
        """dx/dt for x of shape (8,) or (8, m) (real or complex); speed in m/s.

        Under ``braking`` each wheel's tyre gives F_x, the combined-slip F_y and the combined aligning moment M_z
        (:class:`~reduced_model.tyre.CombinedSlip`), which replaces the trail's -t F_y, and F_x steers the wheel
        about its kingpin at the wheel offset l, as the rolling resistance does in (2.1)-(2.2): -side l F_x, side -1
        right, +1 left (docs/numerics.md, "Braking")."""
        P = self.params
        w1, w2 = self.tyres(pressures, braking)
        th1, th1d, th2, th2d, psi, psid, al1, al2 = x
        Fy1 = w1.force.force(al1)
        Fy2 = w2.force.force(al2)
        if w1.combined is None:
            # free rolling: the paper's moments -F_y (R gamma + t(alpha)) of (2.1)-(2.2)
            moment1 = -Fy1 * (P.R * P.gamma + w1.trail_at(al1))
            moment2 = -Fy2 * (P.R * P.gamma + w2.trail_at(al2))
            sigma1, sigma2 = w1.sigma, w2.sigma
        else:
            # under braking: the combined F_y, the combined aligning moment M_z and F_x at the wheel offset l
            Fx1, Fy1, Mz1 = w1.combined.moment_and_forces(Fy1, al1, w1.trail_at)
            Fx2, Fy2, Mz2 = w2.combined.moment_and_forces(Fy2, al2, w2.trail_at)
            moment1 = -Fy1 * P.R * P.gamma + Mz1 + P.l * Fx1
            moment2 = -Fy2 * P.R * P.gamma + Mz2 - P.l * Fx2
            sigma1 = tyre.braked_relaxation_length(w1.combined.constants, w1.sigma)
            sigma2 = tyre.braked_relaxation_length(w2.combined.constants, w2.sigma)
        gyro = P.I2 * speed / P.R
        coupling1 = 0.5 * P.L * w1.k5 * P.l * (P.gamma - P.f) + P.k4 * P.R ** 2 * P.gamma
        coupling2 = 0.5 * P.L * w2.k5 * P.l * (P.gamma - P.f) + P.k4 * P.R ** 2 * P.gamma
        # L^2/2 k5 of eq. (2.3) is the two tyres' vertical springs at +-L/2; split per wheel.
        tramp_stiffness = P.k3 + 0.25 * P.L ** 2 * (w1.k5 + w2.k5) + 2.0 * P.k4 * P.R ** 2
        th1dd = (P.k1 * (th2 - th1) + P.c1 * (th2d - th1d) - P.c4 * th1d - gyro * psid + coupling1 * psi
                 + moment1) / P.I1
        th2dd = (P.k1 * (th1 - th2) + P.c1 * (th1d - th2d) - (P.c4 + P.c2) * th2d - P.k2 * th2 - gyro * psid
                 + coupling2 * psi + moment2) / P.I1
        psidd = (-P.c3 * psid - tramp_stiffness * psi + gyro * (th1d + th2d) + (Fy1 + Fy2) * P.R) / P.I3
        al1d = (-speed * (al1 + th1) + w1.a * th1d) / sigma1
        al2d = (-speed * (al2 + th2) + w2.a * th2d) / sigma2
        return np.array([th1d, th1dd, th2d, th2dd, psid, psidd, al1d, al2d])

    def jacobian(self, x: np.ndarray, speed: float, pressures: TyrePressures,
                 braking: Braking = FREE_ROLLING) -> np.ndarray:
        """Exact Jacobian df/dx by complex-step differentiation (Squire & Trapp, SIAM Rev. 40, 1998)."""
        X = np.asarray(x, dtype=float)[:, None] + _STEP_MATRIX
        return self.rhs(X, speed, pressures, braking).imag / _COMPLEX_STEP

    def linear_matrix(self, speed: float, pressures: TyrePressures) -> np.ndarray:
        """Jacobian at straight running (x = 0) of the free-rolling axle."""
        return self.jacobian(np.zeros(N_STATES), speed, pressures)


STRAIGHT_RUNNING = np.zeros(N_STATES)
