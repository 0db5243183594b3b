"""What ``shimmy verify`` checks: each function returns one report section (see :mod:`comparisons.report`)."""

from __future__ import annotations

from typing import Callable

from reduced_model.family import SpeedFamily
from reduced_model.hopf import hopf_points
from reduced_model.model import Effects, ShimmyModel

from .paper_reference import HOPF_SPEEDS_KMH, KNOWN_DIFFERENCES
from .report import CheckStatus, Report, Row, Section

VMAX = 400 / 3.6
PRESSURES = (1.5, 2.5, 2.7)
MODEL_SETS = (("section 3", Effects()), ("extended (all effects)", Effects.parse("all")))


def printed_decimals(value: float) -> int:
    text = repr(value)
    return len(text.split(".")[1]) if "." in text else 0


def agrees_to_printed_digits(printed: float, computed: float) -> bool:
    digits = printed_decimals(printed)
    return abs(round(computed, digits) - printed) < 0.5 * 10 ** -digits


def hopf_rows(effects: Effects, pressure: float) -> list[dict]:
    """Reduced-model Hopf points at one pressure, paired with the paper's where it prints them."""
    computed = hopf_points(SpeedFamily(ShimmyModel(effects=effects)), pressure * 1e5, 0.0, VMAX)
    printed = HOPF_SPEEDS_KMH.get(pressure, ()) if not effects.names else ()
    rows = []
    for i in range(max(len(computed), len(printed))):
        h = computed[i] if i < len(computed) else None
        rows.append({"pressure_bar": pressure, "point": f"HB{i + 1}",
                     "paper_kmh": printed[i] if i < len(printed) else None,
                     "reduced_kmh": h.speed_kmh if h else None,
                     "frequency_hz": h.frequency_hz if h else None,
                     "criticality": h.criticality.value if h and h.criticality else None})
    if not rows:
        rows.append({"pressure_bar": pressure, "point": "none", "paper_kmh": None, "reduced_kmh": None,
                     "frequency_hz": None, "criticality": None})
    return rows


def paper_status(cells: dict) -> tuple[CheckStatus, str]:
    key = f"hopf:{cells['pressure_bar']}:{cells['point']}"
    printed, computed = cells["paper_kmh"], cells["reduced_kmh"]
    if printed is None and computed is None:
        return CheckStatus.PASS, "no Hopf point, as in the paper" if cells["point"] == "none" else ""
    if printed is None:
        return CheckStatus.INFO, "not printed in the paper"
    if computed is None:
        return CheckStatus.FAIL, "printed in the paper, not found"
    if agrees_to_printed_digits(printed, computed):
        return CheckStatus.PASS, "agrees to the printed digits"
    if key in KNOWN_DIFFERENCES:
        return CheckStatus.KNOWN_DIFFERENCE, KNOWN_DIFFERENCES[key]
    return CheckStatus.FAIL, f"differs from the paper by {computed - printed:+.3f} km/h"


def hopf_section() -> Section:
    rows = []
    for label, effects in MODEL_SETS:
        for p in PRESSURES:
            for cells in hopf_rows(effects, p):
                status, note = paper_status(cells)
                rows.append(Row({"model": label, **cells}, status, note))
    return Section(
        key="hopf", title="Hopf speeds: paper and reduced model",
        columns=("model", "pressure_bar", "point", "paper_kmh", "reduced_kmh", "frequency_hz", "criticality"),
        rows=tuple(rows),
        text="Hopf points of straight running in 0-400 km/h. Paper values are checked to their printed digits.")


SECTIONS: list[tuple[str, Callable[[bool], Section]]] = [
    ("Hopf speeds", lambda quick: hopf_section()),
]


def run_verification(quick: bool, progress=None) -> Report:
    sections = []
    for i, (_, make) in enumerate(SECTIONS):
        sections.append(make(quick))
        if progress is not None:
            progress(i + 1, len(SECTIONS))
    return Report(sections=tuple(sections), quick=quick)
