"""The JSON of ``shimmy cycles``: its branches, cycles, Hopf ends, special points, two-parameter curves and kicks
(schema in docs/json.md); the command itself is :mod:`comparisons.cli.commands.cycles`."""

from __future__ import annotations

import math

import numpy as np

from axles.axle import interface_text
from axles.units import KMH, interface_of, kmh
from bifurcation.cycles.branches import branch_peak
from bifurcation.cycles.end_segments import hopf_multipliers
from bifurcation.cycles.multipliers import classify_multipliers
from bifurcation.cycles.problem import CycleBranch, CycleDiagram, CyclePoint
from bifurcation.equilibria.hopf import HopfPoint
from bifurcation.special_points import ConvergenceError
from comparisons.studies.onset import read_onset
from reduced_model.family import SpeedFamily
from reduced_model.model import STATE_NAMES


def degrees(x: float) -> float:
    return math.degrees(float(x))


def largest(mu: np.ndarray) -> complex:
    """The non-trivial multiplier of largest modulus."""
    rest, _ = classify_multipliers(mu)
    return complex(rest[np.argmax(np.abs(rest))])


def extra_coordinates(family) -> list[tuple[str, str, float]]:
    """(state name, JSON key, SI per interface unit) of the coordinates beyond the reduced model's (the multibody
    axle's lateral travel, bounce and steering gear): keys ``max_y_axle_m``, ``max_phi_gear_deg``, ..."""
    out = []
    for name, unit in zip(family.state_names, family.state_units):
        if name not in STATE_NAMES and not unit.endswith("/s"):
            label, factor = interface_of(unit)
            out.append((name, f"max_{name}_{label}", factor))
    return out


def extra_amplitudes(p: CyclePoint, family) -> dict:
    """max |x| of those coordinates over the orbit, each in its interface unit."""
    return {key: p.max_abs(name) / factor for name, key, factor in extra_coordinates(family)}


def point_row(p: CyclePoint, family) -> dict:
    mu = largest(p.multipliers)
    return {"kind": "cycle", "speed_kmh": kmh(p.p), "period_s": p.period, "frequency_hz": p.frequency_hz,
            "max_theta1_deg": degrees(p.max_abs("theta1")), "max_theta2_deg": degrees(p.max_abs("theta2")),
            "max_psi_deg": degrees(p.max_abs("psi")), **extra_amplitudes(p, family),
            "largest_multiplier": [mu.real, mu.imag],
            "largest_multiplier_abs": abs(mu), "stable": p.stable, "error_estimate": p.error,
            "meets_tolerance": p.meets_tolerance, "intervals": p.orbit.intervals}


def hopf_row(h: HopfPoint, family: SpeedFamily) -> dict:
    """A Hopf end of a branch as a point of zero amplitude: multipliers exp(lambda T) of straight running, one
    of the critical pair's two unit multipliers being the trivial one."""
    period = 2.0 * np.pi / h.omega
    big = largest(hopf_multipliers(family, h))
    extras = {key: 0.0 for _, key, _ in extra_coordinates(family)}
    return {"kind": "hopf", "speed_kmh": kmh(h.p), "period_s": period, "frequency_hz": h.frequency_hz,
            "max_theta1_deg": 0.0, "max_theta2_deg": 0.0, "max_psi_deg": 0.0, **extras,
            "largest_multiplier": [big.real, big.imag], "largest_multiplier_abs": abs(big), "stable": False,
            "error_estimate": 0.0, "meets_tolerance": True, "intervals": 0}


def orbit_row(p: CyclePoint, branch: int, family) -> dict:
    """An orbit at a requested speed: everything of :func:`point_row` and all Floquet multipliers."""
    row = point_row(p, family)
    row.pop("kind")
    return {"branch": branch, **row, "multipliers": [[m.real, m.imag] for m in p.multipliers]}


def at_json(diagram: CycleDiagram, speeds_kmh, family) -> list[dict]:
    out = []
    for v in speeds_kmh:
        orbits = [orbit_row(p, i, family) for i, b in enumerate(diagram.branches) for p in b.user_points
                  if abs(kmh(p.p) - v) <= 1e-9 * max(1.0, v)]
        out.append({"speed_kmh": v, "orbits": orbits})
    return out


def peaks(family: SpeedFamily, b: CycleBranch) -> dict:
    """Refined peaks of max|theta1| and max|psi| along a branch (the computed point if refinement fails)."""
    out = {}
    for name in ("theta1", "psi"):
        try:
            p = branch_peak(family, b, name)
        except ConvergenceError:
            p = b.peak(name)
        out[name] = {"speed_kmh": kmh(p.p), "max_deg": degrees(p.max_abs(name)), "frequency_hz": p.frequency_hz}
    return out


def branch_row(b: CycleBranch, family: SpeedFamily) -> dict:
    return {"from_hopf_kmh": kmh(b.start.p) if b.start else None,
            "to_hopf_kmh": kmh(b.end.p) if b.end else None,
            "complete": b.complete, "status": b.status.value, "message": interface_text(b.message),
            "peak": peaks(family, b) if b.points else None,
            "frequency_range_hz": list(b.frequency_range) if b.points else None,
            "points": ([hopf_row(b.start, family)] if b.start else []) + [point_row(p, family) for p in b.points]
            + ([hopf_row(b.end, family)] if b.end else [])}


def add_exudyn_residuals(out: dict, diagram: CycleDiagram, family) -> None:
    """Each MBS orbit's collocation residual with Exudyn's own right-hand side (one Exudyn call per collocation
    point; relative, :func:`~comparisons.studies.exudyn_check.exudyn_residual`) as ``exudyn_residual``, after a
    Newton polish on that residual where it was above the tolerance (``polished``), and which derivatives the
    continuation used (``derivatives``: the compiled twin's or differences of Exudyn's)."""
    from comparisons.studies.exudyn_check import checked_on_exudyn
    for b, row in zip(diagram.branches, out["branches"]):
        cycles = [r for r in row["points"] if r["kind"] == "cycle"]
        for p, r in zip(b.points, cycles):
            check = checked_on_exudyn(family, p)
            r["exudyn_residual"], r["polished"] = check.residual, check.polished
    out["derivatives"] = family.derivatives


def diagram_json(diagram: CycleDiagram, family: SpeedFamily, pressure_bar: float, effects) -> dict:
    from comparisons.figures.cycle_plots import special_point_labels

    labels = {id(p): text for text, p in special_point_labels(diagram)}
    specials = []
    for i, b in enumerate(diagram.branches):
        for s in sorted(b.special_points, key=lambda s: s.bracket[0]):
            amp = s.data["amplitude"]
            specials.append({"kind": s.kind.value, "label": labels[id(s)], "speed_kmh": kmh(s.p),
                             "max_theta1_deg": degrees(amp[0]), "max_psi_deg": degrees(amp[4]),
                             "frequency_hz": 1.0 / s.data["period"], "status": s.status.value, "branch": i})
    # how the shimmy sets in at each Hopf point, and what says so (l1, or where the right-hand side has a kink at
    # straight running its branch: the full geometry's camber force)
    hopf = [{"speed_kmh": kmh(h.p), "frequency_hz": h.frequency_hz, **read_onset(family, h, diagram).to_json(h)}
            for h in diagram.hopf]
    return {"pressure_bar": pressure_bar, "effects": list(effects), "complete": diagram.complete, "hopf": hopf,
            "branches": [branch_row(b, family) for b in diagram.branches], "special_points": specials}


def codim2_row(p, factor: float) -> dict:
    """A codimension-two point of a two-parameter curve: kind, place (km/h, interface unit), status."""
    return {"kind": p.kind.value, "speed_kmh": kmh(p.p), "value": p.q / factor, "status": p.status.value}


def curves_json(curves, labels, factor: float, checks=None) -> list[dict]:
    """The two-parameter curves; with ``checks`` (an MBS's :class:`~comparisons.studies.exudyn_check.CurveCheck`
    per curve, None where it failed) each point's residual on Exudyn's right-hand side."""
    out = []
    for i, ((curve, error), label) in enumerate(zip(curves, labels)):
        if curve is None:
            out.append({"label": label, "kind": None, "complete": False, "status": ["newton_failed"] * 2,
                        "messages": [error, error], "points": [], "ends_at_zero_amplitude": [None, None]})
            continue
        out.append({"label": label, "kind": curve.kind.value, "complete": curve.complete,
                    "status": [s.value for s in curve.status], "messages": [interface_text(m) for m in curve.messages],
                    "points": [[kmh(v), q / factor] for v, q in zip(curve.ps, curve.qs)],
                    "max_abs_theta1_deg": [float(np.degrees(a[0])) for a in curve.amplitudes],
                    # Per point, parallel to "points": past a 1:1 or 1:2 resonance a torus curve goes on as
                    # neutral saddles; a curve keeps its start mesh, so its error estimate is marked, not enforced.
                    "neutral_saddle": [bool(f) for f in curve.neutral_saddle],
                    "meets_tolerance": [bool(f) for f in curve.meets_tolerance],
                    "ends_at_zero_amplitude": [None if e is None else [kmh(e[0]), e[1] / factor]
                                               for e in curve.ends],
                    "end_points": [None if e is None else codim2_row(e, factor) for e in curve.end_points],
                    "special_points": [codim2_row(e, factor) for e in curve.special_points],
                    # gaps stepped over where a collocation node crosses a kink of the right-hand side
                    "corners": [{"before": [kmh(c.before[0]), c.before[1] / factor],
                                 "after": [kmh(c.after[0]), c.after[1] / factor]} for c in curve.corners]})
        if checks is not None and checks[i] is not None:
            out[-1].update({"exudyn_residual": list(checks[i].residuals), "exudyn_failing": checks[i].failing})
    return out


def kick_row(k) -> dict:
    """A kick threshold (:mod:`comparisons.studies.kick`) in interface units, with the two runs that bracket it."""
    def run(r):
        return None if r is None else {"settled": r.settled, "max_theta1_deg": degrees(r.theta1),
                                       "max_psi_deg": degrees(r.psi)}
    return {"speed_kmh": k.speed / KMH, "status": k.status.value, "lower": k.lower.label, "upper": k.upper.label,
            "kick_theta1_deg": degrees(k.kick), "stays_theta1_deg": degrees(k.stays),
            "leaves_theta1_deg": degrees(k.leaves), "unstable_cycle_max_theta1_deg": degrees(k.unstable_theta1),
            "runs": k.runs, "stays_run": run(k.stays_run), "leaves_run": run(k.leaves_run)}


