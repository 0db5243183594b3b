"""A steady braking condition: one frozen type from the command line to the tyre formula, as the pressures.

:class:`Braking` holds each front wheel's brake slip (-, positive braking: ISO's longitudinal slip kappa = -slip) or
brake force (N, rearward), wheel 1 (theta1) being the right wheel.  A negative value drives the wheel (kappa > 0,
F_x forward): "braking" below means either.  It is made once at the interface by
:meth:`Braking.of_slip` or :meth:`Braking.of_force` (the one place its range is checked) and walks unchanged through
the API (:func:`comparisons.api.family_of`), the families and the models to :mod:`reduced_model.tyre`'s combined-slip
forces.  A brake force is turned into the brake slip that gives it at straight running by the tyre itself
(:func:`reduced_model.tyre.brake_slip_for_force`), where the tyre's pressure is known.

The wheel's spin is not a state: the slip is held while the wheel steers and tramps (the brake slip's own dynamics,
through the wheel's spin inertia and the brake, are fast against shimmy's 5-15 Hz only for a slip-controlled brake;
docs/numerics.md, "Braking").  No braking (:data:`FREE_ROLLING`) leaves both models' equations as they were.

A family continued in a brake slip moves it by name (:data:`BRAKE_PARAMS`): ``"brake_slip"`` both wheels together
(its value is their mean), ``"brake_slip_right"`` and ``"brake_slip_left"`` one wheel.
"""

from __future__ import annotations

from dataclasses import dataclass

from axles.input_file import check_range, finite_number
from axles.limits import BRAKE_FORCE_RANGE_N, BRAKE_SLIP_RANGE
from axles.parameters import ParameterError

BRAKE_PARAMS = ("brake_slip", "brake_slip_right", "brake_slip_left")


@dataclass(frozen=True)
class Braking:
    """Steady braking of the two front wheels: brake slips (-) or, with ``by_force``, brake forces (N).

    >>> str(Braking.of_slip(0.05, 0.05))
    'brake slip 0.05'
    >>> str(Braking.of_force(2000.0, 0.0))
    'brake force right 2000 / left 0 N'
    """

    right: float = 0.0
    left: float = 0.0
    by_force: bool = False

    def __post_init__(self) -> None:
        unit = "N" if self.by_force else "-"
        object.__setattr__(self, "right", finite_number("right wheel's braking", self.right, unit))
        object.__setattr__(self, "left", finite_number("left wheel's braking", self.left, unit))

    # --- made at the interface --------------------------------------------------------------------------------
    @classmethod
    def of_slip(cls, right: float, left: float) -> "Braking":
        """Brake slips (0: free rolling, 1: locked, negative: driving), each checked against :data:`~axles.limits.BRAKE_SLIP_RANGE`."""
        return cls(check_range("right brake slip", right, *BRAKE_SLIP_RANGE, "(-)"),
                   check_range("left brake slip", left, *BRAKE_SLIP_RANGE, "(-)"))

    @classmethod
    def of_force(cls, right: float, left: float) -> "Braking":
        """Brake forces, N rearward (negative: a drive force, forward), each checked against :data:`~axles.limits.BRAKE_FORCE_RANGE_N` (the tyre's
        grip is checked where the tyre is known)."""
        return cls(check_range("right brake force", right, *BRAKE_FORCE_RANGE_N, "N"),
                   check_range("left brake force", left, *BRAKE_FORCE_RANGE_N, "N"), by_force=True)

    # --- read ------------------------------------------------------------------------------------------------
    @property
    def active(self) -> bool:
        """False for free rolling: the models then run the paper's pure-slip equations unchanged."""
        return self != FREE_ROLLING

    @property
    def quantity(self) -> str:
        return "brake_force" if self.by_force else "brake_slip"

    @property
    def unit(self) -> str:
        return "N" if self.by_force else "-"

    def __str__(self) -> str:
        what, unit = ("brake force", " N") if self.by_force else ("brake slip", "")
        if not self.active:
            return "free rolling"
        if self.right == self.left:
            return f"{what} {self.right:g}{unit}"
        return f"{what} right {self.right:g} / left {self.left:g}{unit}"

    def describe(self) -> dict:
        """The ``"braking"`` object of a JSON output (interface units: slip -, force N)."""
        return {"quantity": self.quantity, "unit": self.unit, "right": self.right, "left": self.left}

    # --- a brake slip as a continuation parameter ----------------------------------------------------------------
    def value(self, param: str) -> float:
        """q of the brake-slip parameter ``param`` (``"brake_slip"`` is the mean of the two wheels')."""
        self._slips(param)
        if param == "brake_slip":
            return self.right if self.right == self.left else 0.5 * (self.right + self.left)
        return self.right if param == "brake_slip_right" else self.left

    def moved(self, param: str, q: float) -> "Braking":
        """This braking with ``param`` at q: ``"brake_slip"`` shifts both wheels' slips by the same amount."""
        self._slips(param)
        if param == "brake_slip":
            if self.right == self.left:
                return Braking(q, q)
            shift = q - self.value(param)
            return Braking(self.right + shift, self.left + shift)
        return Braking(q, self.left) if param == "brake_slip_right" else Braking(self.right, q)

    def _slips(self, param: str) -> None:
        if param not in BRAKE_PARAMS:
            raise ValueError(f"not a brake-slip parameter: {param}")
        if self.by_force:
            raise ParameterError(f"{param} cannot be continued under a given brake force: give --brake-slip")


FREE_ROLLING = Braking()
"""No braking: both wheels roll freely (the paper's assumption of no longitudinal slip)."""

PLANNED_BRAKINGS = (Braking.of_slip(0.05, 0.05), Braking.of_slip(0.05, 0.0))
"""The planned braking levels where a study needs some (``shimmy assumptions``' "no longitudinal slip" rows, verify's
"Under braking" section): a brake slip of 0.05 on both wheels (about 80 % of the paper's tyre's peak brake force at
2.5 bar), then on the right wheel alone."""
