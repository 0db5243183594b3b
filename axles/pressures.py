"""Tyre inflation pressures: the names of the pressure parameters a family can be continued in.

``"pressure"`` moves both tyres together, ``"pressure_right"`` and ``"pressure_left"`` one tyre (wheel 1, theta1,
is the right wheel).
"""

from __future__ import annotations

PRESSURE_PARAMS = ("pressure", "pressure_right", "pressure_left")
