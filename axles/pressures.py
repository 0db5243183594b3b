"""Tyre inflation pressures: one frozen type from the command line to the tyre formula.

:class:`TyrePressures` holds the two front tyres' pressures in Pa (wheel 1, theta1, is the right wheel).  It is
made once at the interface, from bar, by :meth:`TyrePressures.of_bar` or :meth:`TyrePressures.both` (the one place a
pressure's range is checked and bar becomes Pa), and walks unchanged through the API, the families and the models to
:func:`reduced_model.model.wheel_tyres`, which reads ``right`` and ``left``.

A family continued in a pressure moves them by name (:data:`PRESSURE_PARAMS`): ``"pressure"`` moves both tyres
together (its value is their mean), ``"pressure_right"`` and ``"pressure_left"`` one tyre.
"""

from __future__ import annotations

from dataclasses import dataclass

from axles.limits import PRESSURE_RANGE_BAR
from axles.input_file import check_range, finite_number
from axles.units import to_interface, to_si

PRESSURE_PARAMS = ("pressure", "pressure_right", "pressure_left")


@dataclass(frozen=True)
class TyrePressures:
    """Inflation pressures of the two front tyres, Pa.

    >>> TyrePressures.both(1.5)
    TyrePressures(right=150000.0, left=150000.0)
    >>> str(TyrePressures.of_bar(1.5, 1.2))
    'right 1.5 / left 1.2 bar'
    """

    right: float
    left: float

    def __post_init__(self) -> None:
        # plain floats, so that 2 and 2.0 (or a numpy scalar) are the same pressures and the same cache key; a
        # value that is no real number, or an integer beyond any float, is refused by name
        object.__setattr__(self, "right", finite_number("right tyre pressure", self.right, "Pa"))
        object.__setattr__(self, "left", finite_number("left tyre pressure", self.left, "Pa"))

    # --- made at the interface, from bar ---------------------------------------------------------------------
    @classmethod
    def of_bar(cls, right_bar: float, left_bar: float, *, right_name: str = "right tyre pressure",
               left_name: str = "left tyre pressure") -> "TyrePressures":
        """The pressures of two tyres given in bar, each checked against :data:`~axles.limits.PRESSURE_RANGE_BAR`
        (the names say which input was out of range)."""
        right = check_range(right_name, right_bar, *PRESSURE_RANGE_BAR, "bar")
        left = check_range(left_name, left_bar, *PRESSURE_RANGE_BAR, "bar")
        return cls(to_si(right, "Pa"), to_si(left, "Pa"))

    @classmethod
    def both(cls, bar: float, name: str = "tyre pressure") -> "TyrePressures":
        """Both tyres at ``bar``."""
        return cls.of_bar(bar, bar, right_name=name, left_name=name)

    @classmethod
    def uniform(cls, pa: float) -> "TyrePressures":
        """Both tyres at ``pa`` (SI, inside the code: no interface check)."""
        return cls(pa, pa)

    # --- read in interface units ------------------------------------------------------------------------------
    @property
    def right_bar(self) -> float:
        return to_interface(self.right, "Pa")

    @property
    def left_bar(self) -> float:
        return to_interface(self.left, "Pa")

    @property
    def alike(self) -> bool:
        return self.right == self.left

    def __str__(self) -> str:
        if self.alike:
            return f"{self.right_bar:g} bar"
        return f"right {self.right_bar:g} / left {self.left_bar:g} bar"

    # --- a pressure as a continuation parameter ----------------------------------------------------------------
    def value(self, param: str) -> float:
        """q of the pressure parameter ``param`` at these pressures (Pa); ``"pressure"`` is the mean."""
        if param == "pressure":
            return self.right if self.alike else 0.5 * (self.right + self.left)
        if param == "pressure_right":
            return self.right
        if param == "pressure_left":
            return self.left
        raise ValueError(f"not a pressure parameter: {param}")

    def moved(self, param: str, q: float) -> "TyrePressures":
        """These pressures with the parameter ``param`` at q: ``"pressure"`` shifts both by the same amount."""
        right, left = self.right, self.left
        if param == "pressure":
            if self.alike:
                return TyrePressures(q, q)
            mean = 0.5 * (right + left)
            return TyrePressures(q + (right - mean), q + (left - mean))
        if param == "pressure_right":
            return TyrePressures(q, left)
        if param == "pressure_left":
            return TyrePressures(right, q)
        raise ValueError(f"not a pressure parameter: {param}")
