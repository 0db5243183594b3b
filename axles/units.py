"""Units at the user interface: km/h, bar and degrees; everything inside the code is SI.

One table says how an SI unit is shown (:data:`INTERFACE`); every option, axle file, report and JSON field goes
through :func:`to_interface` / :func:`to_si` so that no command converts by hand.
"""

from __future__ import annotations

import math

KMH_PER_M_S = 3.6
KMH = 1.0 / KMH_PER_M_S   # m/s per km/h
BAR = 1e5                 # Pa per bar
DEG = math.pi / 180.0

# SI unit -> (interface unit, SI per interface unit)
INTERFACE = {"rad": ("deg", DEG), "Pa": ("bar", BAR), "m/s": ("km/h", KMH), "rad/s": ("deg/s", DEG)}


def interface_of(si_unit: str) -> tuple[str, float]:
    """(interface unit, SI per interface unit) of an SI unit; units without a rule are shown as they are."""
    return INTERFACE.get(si_unit, (si_unit, 1.0))


def to_interface(value: float, si_unit: str) -> float:
    """The interface value of an SI value, chosen so that :func:`to_si` gives the SI value back bit for bit.

    A plain ``value / factor`` can come back one ulp off after ``* factor``; files written by ``shimmy params
    --write`` must reproduce the same numbers exactly, so the nearest float that round-trips is searched.
    """
    factor = interface_of(si_unit)[1]
    if factor == 1.0:
        return float(value)
    guess = value / factor
    candidates = [guess]
    up = down = guess
    for _ in range(8):
        up, down = math.nextafter(up, math.inf), math.nextafter(down, -math.inf)
        candidates += [up, down]
    for c in candidates:
        if c * factor == value:
            return c
    return guess


def to_si(value: float, si_unit: str) -> float:
    return float(value) * interface_of(si_unit)[1]


# Speeds are converted by multiplying or dividing by 3.6, not by KMH: ``v / 3.6`` and ``v * (1 / 3.6)`` can differ
# in the last bit, and the reports' and the tests' numbers were computed the first way.  Pressures and angles need no
# helper: ``p / BAR`` is exact enough and ``math.degrees`` exists.
def kmh(speed):
    """km/h of a speed in m/s (a float or an array)."""
    return speed * KMH_PER_M_S


def from_kmh(speed_kmh):
    """m/s of a speed in km/h (a float or an array)."""
    return speed_kmh / KMH_PER_M_S


# Units a tyre property file (.tir, TYDEX format) may declare in its [UNITS] section: SI per file unit, by the
# quantity the [UNITS] key names.  Names are matched case-insensitively; a name not listed cannot be converted and
# the file is refused.  ANGLE has only radians: the Magic Formula's coefficients are defined per radian, and a file
# in degrees would need every camber coefficient rescaled, which the models' sources never do.
TIR_UNITS = {
    "LENGTH": {"meter": 1.0, "metre": 1.0, "m": 1.0, "millimeter": 1e-3, "mm": 1e-3, "centimeter": 1e-2, "cm": 1e-2,
               "kilometer": 1e3, "km": 1e3, "inch": 0.0254, "in": 0.0254, "foot": 0.3048, "ft": 0.3048},
    "FORCE": {"newton": 1.0, "n": 1.0, "kilonewton": 1e3, "kn": 1e3, "pound_force": 4.4482216152605,
              "lbf": 4.4482216152605},
    "ANGLE": {"radians": 1.0, "radian": 1.0, "rad": 1.0},
    "MASS": {"kg": 1.0, "kilogram": 1.0, "gram": 1e-3, "g": 1e-3, "pound_mass": 0.45359237, "lbm": 0.45359237},
    "TIME": {"second": 1.0, "s": 1.0, "sec": 1.0, "millisecond": 1e-3, "ms": 1e-3},
    "PRESSURE": {"pascal": 1.0, "pa": 1.0, "kpa": 1e3, "kilopascal": 1e3, "bar": BAR, "mpa": 1e6, "psi": 6894.757293168361},
}


def tir_unit_factor(quantity: str, name: str) -> float | None:
    """SI per unit of a .tir file's ``[UNITS] QUANTITY = 'name'``; None for a unit it cannot convert."""
    return TIR_UNITS.get(quantity, {}).get(name.strip().lower())
