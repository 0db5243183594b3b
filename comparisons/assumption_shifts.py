"""The assumption study of :mod:`comparisons.studies.assumption_study` (SI) in interface units: what ``shimmy
assumptions``, the verify report and the sweeps show of it."""

from __future__ import annotations

import math

from axles.axle import interface_text
from axles.units import BAR, kmh
from comparisons.studies.assumption_study import AssumptionRow, AssumptionStudy, HopfShift
from comparisons.studies.cycle_peak import BranchPeak, CyclePeak, Refinement


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


def branch_json(b: BranchPeak) -> dict:
    """One continued branch: its Hopf ends, how it ended, its largest cycle (null if it did not complete)."""
    c = b.cycle
    return {"from_hopf_kmh": _kmh(b.start), "to_hopf_kmh": _kmh(b.end), "status": b.status.value,
            "complete": b.complete, "message": interface_text(b.message), "cycles": b.cycles,
            "peak_theta1_deg": None if c is None else math.degrees(c.max_abs("theta1")),
            "peak_speed_kmh": None if c is None else kmh(c.p),
            "refinement": None if b.refinement is None else b.refinement.value}


def peak_json(peak: CyclePeak | None) -> dict | None:
    """A side's largest cycle over its branches (null when cycles were not computed)."""
    if peak is None:
        return None
    return {"status": peak.status.value, "theta1_deg": _deg(peak.theta1), "psi_deg": _deg(peak.psi),
            "speed_kmh": _kmh(peak.speed), "frequency_hz": peak.frequency_hz, "mode": peak.mode,
            "stable": peak.stable, "refinement": None if peak.refinement is None else peak.refinement.value,
            "branches": [branch_json(b) for b in peak.branches]}


def peak_text(peak: CyclePeak | None) -> str:
    """'9.854 deg at 48.14 km/h (yaw, stable)', 'no cycle', 'incomplete (...)' or '-' (not computed)."""
    if peak is None:
        return "-"
    if peak.cycle is None:
        if peak.branches:
            failed = [b for b in peak.branches if not b.complete]
            return f"incomplete: {interface_text(failed[0].message)}"
        return "no cycle (no Hopf point)"
    # an unrefined peak is the continuation's own cycle: a branch end (often the window's boundary) or a fold
    how = "" if peak.refinement is Refinement.PARABOLA else ", a computed cycle at a branch end or fold"
    return (f"{math.degrees(peak.theta1):.3f} deg at {kmh(peak.speed):.2f} km/h "
            f"({peak.mode}, {'stable' if peak.stable else 'unstable'}, {peak.frequency_hz:.2f} Hz{how})")


def study_json(study: AssumptionStudy) -> dict:
    return {"pressure_bar": study.pressure / BAR, "effects": list(study.effects),
            "peak_speed_kmh": _kmh(study.peak_speed), "reduced_peak_theta1_deg": _deg(study.peak_theta1),
            "reduced_peak": peak_json(study.reduced_peak),
            "rows": [{"assumption": r.assumption, "hopf": [hopf_shift_json(h) for h in r.hopf],
                      "peak_theta1_shift_deg": peak_theta1_shift_deg(r), "mbs_peak": peak_json(r.peak_mbs),
                      "reference_peak": peak_json(r.peak_reference)} for r in study.rows]}
