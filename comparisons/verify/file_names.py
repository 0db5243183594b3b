"""Readable names of the files a verification writes for one case: ``full_geometry_1.5bar_t0_0.25m.png``,
``jumps_1.5bar.png``, ``cycles_R1.5bar_L2.5bar.png``.  Each part carries its unit, as the report does; only
characters that are safe in a file name on every system are used (letters, digits, ``.``, ``_``, ``-``)."""

from __future__ import annotations

import re

from axles.axle import interface_unit


def _number(value: float) -> str:
    return f"{value:g}"


def pressure_part(right_bar: float, left_bar: float | None = None) -> str:
    """``1.5bar`` for both tyres alike, else ``R1.5bar_L2.5bar``."""
    if left_bar is None or left_bar == right_bar:
        return f"{_number(right_bar)}bar"
    return f"R{_number(right_bar)}bar_L{_number(left_bar)}bar"


def overrides_part(overrides) -> str:
    """``t0_0.25m`` from the axle's ``--set`` entries ((name, value in interface units)); "" when none."""
    parts = []
    for name, value in overrides:
        unit = interface_unit(name)[0].replace("/", "_per_")
        parts.append(f"{name}_{_number(value)}{unit}")
    return "_".join(parts)


def case_file_name(stem: str, extension: str, right_bar: float, left_bar: float | None = None,
                   overrides=(), suffix: str = "") -> str:
    """``<stem>_<pressures>[_<overrides>][_<suffix>].<extension>``."""
    name = "_".join(p for p in (stem, pressure_part(right_bar, left_bar), overrides_part(overrides), suffix) if p)
    return re.sub(r"[^A-Za-z0-9._-]", "_", name) + f".{extension}"
