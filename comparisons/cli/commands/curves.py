"""``shimmy curves``: two-parameter Hopf curves in the (V, q) plane."""

from __future__ import annotations

import argparse
import sys

from axles.axle import interface_text, interface_unit
from axles.limits import UsageError
from axles.units import KMH, kmh
from comparisons.cli.options import (
    SECOND_PARAMETERS,
    add_model_choice,
    add_braking_options,
    add_model_options,
    braking_label,
    add_output_options,
    add_speed_window,
    build_axle,
    build_family,
    check_window,
    emit_json,
    inputs_json,
    pressure_label,
)
from comparisons.cli.progress import progress, ticker
from bifurcation.equilibria.hopf_curves import HopfDiagram, hopf_diagram
from axles.pressures import PRESSURE_PARAMS
from axles.parameters import ParameterError

PARAMS = SECOND_PARAMETERS
MARGIN_GRID = (161, 41)      # speeds, pressures of the margin panel of --plot over a pressure


def add_parser(sub) -> None:
    p = sub.add_parser("curves", help="Hopf curves in the (speed, parameter) plane")
    p.add_argument("--param", required=True, choices=PARAMS, help="second parameter")
    p.add_argument("--range", required=True, nargs=2, type=float, metavar=("LO", "HI"),
                   help="parameter window (bar for pressures, otherwise the units of 'shimmy params')")
    add_model_options(p, pressure_required=False)
    add_braking_options(p)
    add_model_choice(p)
    add_speed_window(p)
    p.add_argument("--cycle-curves", action="store_true",
                   help="also the cycle-fold (S) and torus (T) curves born at the Hopf curves' generalized Hopf and "
                        "Hopf-Hopf points, by branch switching there (figure 18); the MBS's curve points are "
                        "checked on Exudyn's own right-hand side")
    add_output_options(p, plot=True)
    p.set_defaults(run=run)


def switched(family, diagram: HopfDiagram, vmax: float, quiet: bool, model: str):
    """The cycle curves born at the diagram's located Hopf-Hopf and generalized Hopf points: (the switching per
    point, [(curve or None, error)], labels, Exudyn checks or None) in the form ``shimmy cycles`` prints."""
    from bifurcation.cycle_curves.switching import named_curves, switched_curves
    from bifurcation.special_points import PointKind, PointStatus

    origins = [p for p in diagram.special_points if p.status is PointStatus.LOCATED
               and p.kind in (PointKind.HOPF_HOPF, PointKind.GENERALIZED_HOPF)]
    with progress(len(origins), "cycle curves", quiet) as bar:
        found = switched_curves(family, origins, diagram.lo, diagram.hi, diagram.p_min, vmax,
                                progress=lambda _: bar.update(1))
    named = named_curves(found)
    curves = [(c, "" if c is not None else f"newton_failed: {interface_text(s.error)}") for _, s, c in named]
    labels = [label for label, _, _ in named]
    checks = None
    if model == "mbs":
        from comparisons.studies.exudyn_check import curve_on_exudyn
        checks = [None if c is None else curve_on_exudyn(family, c) for c, _ in curves]
    return found, curves, labels, checks


def diagram_json(diagram: HopfDiagram, factor: float) -> dict:
    return {
        "param": diagram.param,
        "unit": interface_unit(diagram.param)[0],
        "complete": diagram.complete,
        "curves": [{"points": [[kmh(v), q / factor] for v, q in zip(c.ps, c.qs)],
                    "status": [s.value for s in c.status],
                    "messages": [interface_text(m) for m in c.messages]}
                   for c in diagram.curves],
        "special_points": [{"kind": s.kind.value, "speed_kmh": kmh(s.p), "value": s.q / factor,
                            "status": s.status.value,
                            **{f"{k}_hz" if k.startswith("omega") else k:
                               (v / (2 * 3.141592653589793) if k.startswith("omega") else v)
                               for k, v in s.data.items()}}
                           for s in diagram.special_points],
    }


def run(args: argparse.Namespace) -> int:
    lo, hi = args.range
    unit, factor = interface_unit(args.param)
    check_window(lo, hi, args.param, unit)
    family = build_family(args, args.param)
    try:
        for q in (lo * factor, hi * factor):
            family.validate(q)
    except ParameterError as exc:
        raise UsageError(f"--range: {exc}") from None
    quiet = args.json or not sys.stderr.isatty()
    with progress(10, "Hopf curves", quiet) as bar:
        diagram = hopf_diagram(family, lo * factor, hi * factor, 0.0, args.vmax * KMH, progress=ticker(bar))
    cycle_curves = switched(family, diagram, args.vmax * KMH, quiet, args.model) if args.cycle_curves else None
    if args.plot and args.param in PRESSURE_PARAMS:
        import numpy as np

        from comparisons.figures.margin_figures import plot_hopf_diagram_with_margins
        from comparisons.studies.margin_study import margin_study
        study = margin_study(family, np.linspace(diagram.p_min, diagram.p_max, MARGIN_GRID[0]),
                             np.linspace(diagram.lo, diagram.hi, MARGIN_GRID[1]))
        plot_hopf_diagram_with_margins(diagram, family, study, args.plot)
    elif args.plot:
        from comparisons.figures.plots import plot_hopf_diagram
        plot_hopf_diagram(diagram, family, args.plot)
    if args.json:
        model = {"model": "mbs", "fidelity": family.model.fidelity.label} if args.model == "mbs" else {}
        out = {**inputs_json(args), **model, **diagram_json(diagram, factor)}
        if cycle_curves is not None:
            out["cycle_curves"] = cycle_curves_json(cycle_curves, factor)
        emit_json(out)
    else:
        print(f"Hopf curves in (V, {args.param}) for {args.param} in [{lo:g}, {hi:g}] {unit}, V in "
              f"[{kmh(diagram.p_min):g}, {args.vmax:g}] km/h"
              + ("" if args.param == "pressure" else f", at {pressure_label(args)}") + braking_label(args)
              + (f" (MBS, fidelity {family.model.fidelity.label})" if args.model == "mbs" else ""))
        print(f"  {build_axle(args).label()}")
        for i, c in enumerate(diagram.curves, 1):
            ends = " | ".join(interface_text(m) for m in c.messages)
            print(f"  curve {i}: {len(c.ps)} points; ends: {ends}")
        for s in diagram.special_points:
            print(f"  {s.kind.value:17s} {kmh(s.p):9.3f} km/h  {args.param} = {s.q / factor:.6g} {unit}"
                  f"  ({s.status.value})")
        if cycle_curves is not None:
            print_switched(cycle_curves, args.param)
        if args.plot:
            print(f"  plot written to {args.plot}")
    problems = [] if diagram.complete else ["a Hopf curve stopped before leaving the window (see the curve end "
                                            "messages)"]
    if cycle_curves is not None:
        _, curves, labels, checks = cycle_curves
        problems += [f"cycle curve {label}: " + (error or "; ".join(interface_text(m) for m, s in
                                                                    zip(c.messages, c.status) if not s.is_complete))
                     for (c, error), label in zip(curves, labels) if c is None or not c.complete]
        problems += [f"cycle curve {label}: {check.text()}" for check, label in zip(checks or (), labels)
                     if check is not None and check.failing]
    if problems:
        sys.stderr.write("shimmy: incomplete: " + "; ".join(problems) + "\n")
        return 3
    return 0


def cycle_curves_json(cycle_curves, factor: float) -> dict:
    from comparisons.cli.commands.cycle_json import curves_json
    found, curves, labels, checks = cycle_curves
    return {"origins": [{"kind": s.origin.kind.value, "speed_kmh": kmh(s.origin.p), "value": s.origin.q / factor,
                         "curves": len(s.curves), "error": None if s.error is None else interface_text(s.error)}
                        for s in found],
            "curves": curves_json(curves, labels, factor, checks),
            "complete": all(c is not None and c.complete for c, _ in curves)
            and not any(c is not None and c.failing for c in checks or ())}


def print_switched(cycle_curves, name: str) -> None:
    from comparisons.cli.commands.cycles import print_curves
    found, curves, labels, checks = cycle_curves
    unit, factor = interface_unit(name)
    if not found:
        print("  no generalized Hopf or Hopf-Hopf point located: no cycle curve to switch onto")
        return
    for s in found:
        what = "error" if s.error is not None else f"{len(s.curves)} curve(s) end there"
        print(f"  switching at the {s.origin.kind.value} point {kmh(s.origin.p):.3f} km/h, {name} = "
              f"{s.origin.q / factor:.6g} {unit}: {what}")
    if curves:
        print_curves(curves, labels, name, checks)
