"""``shimmy cycles``: limit-cycle branches born at the Hopf points in a speed window, with their bifurcations."""

from __future__ import annotations

import argparse
import math
import sys

import numpy as np

from reduced_model.cycle_curves import CycleCurve, cycle_bifurcation_curve
from reduced_model.cycles import CycleBranch, CycleDiagram, CyclePoint, branch_peak, cycle_diagram
from reduced_model.family import SpeedFamily
from reduced_model.hopf import MIN_SPEED
from reduced_model.special_points import ConvergenceError, PointKind

from ..options import (
    KMH,
    SECOND_PARAMETERS,
    UsageError,
    add_model_options,
    add_output_options,
    add_speed_window,
    build_axle,
    build_model,
    emit_json,
    inputs_json,
    interface_unit,
    operating_pressure,
    pressure_label,
    progress,
    ticker,
)

TWO_PARAMS = SECOND_PARAMETERS


def add_parser(sub) -> None:
    p = sub.add_parser("cycles", help="limit cycles (shimmy amplitudes) born at the Hopf points, with their "
                                      "folds, torus and period-doubling points")
    add_model_options(p)
    add_speed_window(p, vmin=True)
    p.add_argument("--two-param", metavar="NAME", choices=TWO_PARAMS,
                   help="also continue every cycle fold and torus point in the (speed, NAME) plane "
                        f"(figures 8 and 18); NAME one of {', '.join(TWO_PARAMS)}; needs --range")
    p.add_argument("--range", nargs=2, type=float, metavar=("LO", "HI"),
                   help="window of NAME for --two-param (bar for pressure, SI otherwise)")
    add_output_options(p, plot=True)
    p.set_defaults(run=run)


def degrees(x: float) -> float:
    return math.degrees(float(x))


def point_row(p: CyclePoint) -> dict:
    return {"speed_kmh": p.speed_kmh, "frequency_hz": p.frequency_hz, "max_theta1_deg": degrees(p.max_abs("theta1")),
            "max_psi_deg": degrees(p.max_abs("psi")), "stable": p.stable}


def peaks(family: SpeedFamily, b: CycleBranch) -> dict:
    """Refined peaks of max|theta1| and max|psi| along a branch (the computed point if refinement fails)."""
    out = {}
    for name in ("theta1", "psi"):
        try:
            p = branch_peak(family, b, name)
        except ConvergenceError:
            p = b.peak(name)
        out[name] = {"speed_kmh": p.speed_kmh, "max_deg": degrees(p.max_abs(name)), "frequency_hz": p.frequency_hz}
    return out


def branch_row(b: CycleBranch, family: SpeedFamily) -> dict:
    return {"from_hopf_kmh": b.start.speed_kmh if b.start else None,
            "to_hopf_kmh": b.end.speed_kmh if b.end else None,
            "complete": b.complete, "status": b.status.value, "message": b.message,
            "peak": peaks(family, b) if b.points else None,
            "frequency_range_hz": list(b.frequency_range) if b.points else None,
            "points": [point_row(p) for p in b.points]}


def diagram_json(diagram: CycleDiagram, family: SpeedFamily, pressure_bar: float, effects) -> dict:
    from ..cycle_plots import special_point_labels

    labels = {id(p): text for text, p in special_point_labels(diagram)}
    specials = []
    for i, b in enumerate(diagram.branches):
        for s in sorted(b.special_points, key=lambda s: s.bracket[0]):
            amp = s.data["amplitude"]
            specials.append({"kind": s.kind.value, "label": labels[id(s)], "speed_kmh": s.speed * 3.6,
                             "max_theta1_deg": degrees(amp[0]), "max_psi_deg": degrees(amp[4]),
                             "frequency_hz": 1.0 / s.data["period"], "status": s.status.value, "branch": i})
    return {"pressure_bar": pressure_bar, "effects": list(effects), "complete": diagram.complete,
            "branches": [branch_row(b, family) for b in diagram.branches], "special_points": specials}


def _two_param_window(args: argparse.Namespace, model) -> tuple[str, float, float, float]:
    """(name, current value, lo, hi) in SI for --two-param, checked."""
    name = args.two_param
    if args.range is None:
        raise UsageError("--two-param needs --range LO HI")
    lo, hi = args.range
    unit, factor = interface_unit(name)
    if not 0.0 < lo < hi:
        raise UsageError(f"--range needs 0 < LO < HI, got {lo:g} {hi:g} {unit}")
    value = SpeedFamily(model, name, pressure=operating_pressure(args)).nominal
    if not lo * factor <= value <= hi * factor:
        raise UsageError(f"--range {lo:g} {hi:g} {unit} must contain the current {name} = {value / factor:g} {unit}")
    return name, value, lo * factor, hi * factor


def curves_json(curves, labels, factor: float) -> list[dict]:
    out = []
    for (curve, error), label in zip(curves, labels):
        if curve is None:
            out.append({"label": label, "kind": None, "complete": False, "status": ["newton_failed"] * 2,
                        "messages": [error, error], "points": [], "ends_at_zero_amplitude": [None, None]})
            continue
        out.append({"label": label, "kind": curve.kind.value, "complete": curve.complete,
                    "status": [s.value for s in curve.status], "messages": list(curve.messages),
                    "points": [[v * 3.6, q / factor] for v, q in zip(curve.speeds, curve.values)],
                    "ends_at_zero_amplitude": [None if e is None else [e[0] * 3.6, e[1] / factor]
                                               for e in curve.ends]})
    return out


def run(args: argparse.Namespace) -> int:
    if not args.vmin < args.vmax:
        raise UsageError(f"--vmin must be below --vmax, got {args.vmin:g} and {args.vmax:g} km/h")
    if args.range is not None and args.two_param is None:
        raise UsageError("--range is only used with --two-param")
    model = build_model(args)
    if args.two_param:
        name, q, lo, hi = _two_param_window(args, model)
        family = SpeedFamily(model, name, pressure=operating_pressure(args))
        family.validate(lo), family.validate(hi)
    else:
        family = SpeedFamily(model, "pressure", pressure=operating_pressure(args))
        q = family.nominal
    family.validate(q)
    vmin, vmax = args.vmin * KMH, args.vmax * KMH
    quiet = args.json or not sys.stderr.isatty()
    with progress(1, "cycle branches", quiet) as bar:
        diagram = cycle_diagram(family, q, vmin, vmax, progress=ticker(bar))
    unstable = unstable_without_hopf(diagram, family, q)
    curves: list[tuple[CycleCurve | None, str]] = []
    labels: list[str] = []
    if args.two_param:
        from ..cycle_plots import special_point_labels
        chosen = [(text, p) for text, p in special_point_labels(diagram)
                  if p.kind in (PointKind.CYCLE_FOLD, PointKind.TORUS)]
        with progress(len(chosen), "bifurcation curves", quiet) as bar:
            for text, p in chosen:
                try:
                    curves.append((cycle_bifurcation_curve(family, p, lo, hi, vmin, vmax), ""))
                except ConvergenceError as exc:
                    curves.append((None, f"newton_failed: {exc}"))
                labels.append(text)
                bar.update(1)
    if args.plot:
        if args.two_param:
            from reduced_model.hopf_curves import hopf_diagram

            from ..cycle_plots import plot_cycle_curves
            plot_cycle_curves(hopf_diagram(family, lo, hi, vmin, vmax), [c for c, _ in curves], labels, family,
                              args.plot)
        else:
            from ..cycle_plots import plot_cycle_diagram
            plot_cycle_diagram(diagram, family, args.plot)
    factor = interface_unit(args.two_param)[1] if args.two_param else 1.0
    if args.json:
        out = diagram_json(diagram, family, args.pressure, model.effects.names)
        del out["pressure_bar"], out["effects"]
        out = {**inputs_json(args), **out}
        if unstable is not None:
            out["complete"], out["note"] = False, unstable
        if args.two_param:
            out["two_param"] = {"param": args.two_param, "unit": interface_unit(args.two_param)[0],
                                "curves": curves_json(curves, labels, factor)}
            out["complete"] = out["complete"] and all(c is not None and c.complete for c, _ in curves)
        emit_json(out)
    else:
        print_diagram(diagram, family, args)
        if args.two_param:
            print_curves(curves, labels, args.two_param)
    problems = [f"branch from {b.start.speed_kmh:.3f} km/h stopped: {b.message}"
                for b in diagram.branches if not b.complete]
    if unstable is not None:
        problems.append(unstable)
    problems += [f"curve {label}: " + (error or "; ".join(m for m, s in zip(c.messages, c.status)
                                                         if not s.is_complete))
                 for (c, error), label in zip(curves, labels) if c is None or not c.complete]
    if problems:
        sys.stderr.write("shimmy: incomplete: " + "; ".join(problems) + "\n")
        return 3
    return 0


def unstable_without_hopf(diagram: CycleDiagram, family: SpeedFamily, q: float) -> str | None:
    """Why an empty diagram is not 'no shimmy': straight running unstable with its Hopf points outside the window."""
    if diagram.hopf:
        return None
    # From MIN_SPEED: at V = 0 the slip equations have zero eigenvalues that round-off can put on either side.
    speeds = np.linspace(max(diagram.vmin, MIN_SPEED), diagram.vmax, 81)
    bad = [V for V in speeds if np.max(np.linalg.eigvals(family.linear_matrix(V, q)).real) > 1e-9]
    if not bad:
        return None
    return (f"straight running is unstable at {min(bad) * 3.6:.1f}-{max(bad) * 3.6:.1f} km/h but no Hopf point lies "
            f"in the window: the shimmy cycles there are born outside it (widen --vmin/--vmax)")


def print_curves(curves, labels, name: str) -> None:
    unit, factor = interface_unit(name)
    print(f"  two-parameter curves in (V, {name}):")
    for (curve, error), label in zip(curves, labels):
        if curve is None:
            print(f"    {label:4s} [INCOMPLETE] {error}")
            continue
        flag = "" if curve.complete else "  [INCOMPLETE]"
        print(f"    {label:4s} {curve.kind.value:10s} {len(curve.speeds)} points, {name} "
              f"{curve.values.min() / factor:.6g}-{curve.values.max() / factor:.6g} {unit}{flag}")
        for message in curve.messages:
            print(f"         end: {message}")


def print_diagram(diagram: CycleDiagram, family: SpeedFamily, args: argparse.Namespace) -> None:
    from ..cycle_plots import special_point_labels

    effects = ",".join(build_model(args).effects.names) or "none (section 3 model)"
    print(f"Limit cycles at {pressure_label(args)}, {args.vmin:g}-{args.vmax:g} km/h, pressure effects: {effects}")
    print(f"  {build_axle(args).label()}")
    if not diagram.hopf:
        unstable = unstable_without_hopf(diagram, family, diagram.value)
        print(f"  [INCOMPLETE] {unstable}" if unstable else
              "  no Hopf point in the window and straight running stable throughout: no shimmy")
    labels = {id(p): text for text, p in special_point_labels(diagram)}
    for b in diagram.branches:
        head = f"  branch from HB at {b.start.speed_kmh:.3f} km/h ({b.start.frequency_hz:.3f} Hz, " \
               f"{b.start.criticality.value if b.start.criticality else 'criticality unknown'}): " \
               f"{len(b.points)} cycles"
        print(head + ("" if b.complete else "  [INCOMPLETE]"))
        print(f"    end: {b.message}")
        if not b.points:
            continue
        peak = peaks(family, b)
        lo, hi = b.frequency_range
        stable = sum(p.stable for p in b.points)
        print(f"    peak max|theta1| {peak['theta1']['max_deg']:.4f} deg at {peak['theta1']['speed_kmh']:.2f} km/h,"
              f" peak max|psi| {peak['psi']['max_deg']:.4f} deg at {peak['psi']['speed_kmh']:.2f} km/h")
        print(f"    frequency {lo:.3f}-{hi:.3f} Hz; {stable} of {len(b.points)} cycles stable")
        for s in sorted(b.special_points, key=lambda s: s.bracket[0]):
            amp = s.data["amplitude"]
            print(f"    {labels[id(s)]:4s} {s.kind.value:16s} {s.speed * 3.6:10.3f} km/h  "
                  f"max|theta1| {degrees(amp[0]):7.3f} deg  max|psi| {degrees(amp[4]):6.3f} deg  "
                  f"({s.status.value})")
    if args.plot:
        print(f"  plot written to {args.plot}")
