"""The assumption study of :mod:`mbs_shimmy.assumption_study` (SI) in interface units: what ``shimmy
assumptions``, the verify report and the sweeps show of it."""

from __future__ import annotations

import math

from comparisons.axles.units import BAR, kmh
from mbs_shimmy.assumption_study import AssumptionRow, AssumptionStudy, HopfShift


def _kmh(speed: float | None) -> float | None:
    return None if speed is None else kmh(speed)


def _deg(angle: float | None) -> float | None:
    return None if angle is None else math.degrees(angle)


def reduced_kmh(h: HopfShift) -> float | None:
    return _kmh(h.reduced_speed)


def mbs_kmh(h: HopfShift) -> float | None:
    return _kmh(h.mbs_speed)


def shift_kmh(h: HopfShift) -> float | None:
    """MBS minus reference, km/h; None where the mode has no partner."""
    if h.reduced_speed is None or h.mbs_speed is None:
        return None
    return kmh(h.mbs_speed) - kmh(h.reduced_speed)


def peak_theta1_deg(row: AssumptionRow) -> tuple[float | None, float | None]:
    """(reference, MBS) peak max |theta1|, deg."""
    return _deg(row.peak_theta1_reduced), _deg(row.peak_theta1_mbs)


def peak_theta1_shift_deg(row: AssumptionRow) -> float | None:
    reduced, mbs = peak_theta1_deg(row)
    return None if reduced is None or mbs is None else mbs - reduced


def hopf_shift_json(h: HopfShift) -> dict:
    return {"reduced_kmh": reduced_kmh(h), "mbs_kmh": mbs_kmh(h), "shift_kmh": shift_kmh(h)}


def study_json(study: AssumptionStudy) -> dict:
    return {"pressure_bar": study.pressure / BAR, "effects": list(study.effects),
            "peak_speed_kmh": _kmh(study.peak_speed), "reduced_peak_theta1_deg": _deg(study.peak_theta1),
            "rows": [{"assumption": r.assumption, "hopf": [hopf_shift_json(h) for h in r.hopf],
                      "peak_theta1_shift_deg": peak_theta1_shift_deg(r)} for r in study.rows]}
