"""Comparisons of computed results with the paper's printed values (used by ``shimmy verify``)."""

from __future__ import annotations

from reduced_model.family import SpeedFamily
from reduced_model.hopf import hopf_points
from reduced_model.model import ShimmyModel

from .paper_reference import HOPF_SPEEDS_KMH


def printed_decimals(value: float) -> int:
    text = repr(value)
    return len(text.split(".")[1]) if "." in text else 0


def agreement(printed: float | None, computed: float | None) -> str:
    if printed is None and computed is None:
        return "agrees (none)"
    if printed is None:
        return "not in paper"
    if computed is None:
        return "not found"
    digits = printed_decimals(printed)
    if abs(round(computed, digits) - printed) < 0.5 * 10 ** -digits:
        return "agrees to printed digits"
    return "differs (see README)"


def hopf_table(model: ShimmyModel | None = None, pressures=(1.5, 2.5, 2.7)) -> list[dict]:
    family = SpeedFamily(model or ShimmyModel())
    rows = []
    for p in pressures:
        computed = hopf_points(family, p * 1e5, 0.0, 400 / 3.6)
        printed = HOPF_SPEEDS_KMH.get(p, ())
        for i in range(max(len(computed), len(printed), 1)):
            h = computed[i] if i < len(computed) else None
            ref = printed[i] if i < len(printed) else None
            rows.append({"pressure_bar": p, "point": f"HB{i + 1}" if (h or ref) else "-",
                         "paper_kmh": ref, "computed_kmh": h.speed_kmh if h else None,
                         "difference_kmh": (h.speed_kmh - ref) if (h and ref is not None) else None,
                         "frequency_hz": h.frequency_hz if h else None,
                         "criticality": h.criticality.value if h else None,
                         "agreement": agreement(ref, h.speed_kmh if h else None)})
    return rows
