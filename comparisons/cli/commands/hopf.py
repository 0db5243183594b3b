"""``shimmy hopf``: Hopf points of straight running at one pressure in 0..vmax, reduced model or MBS."""

from __future__ import annotations

import argparse

from axles.units import KMH, kmh
from comparisons.cli.options import (
    add_model_choice,
    add_model_options,
    add_output_options,
    add_speed_window,
    build_axle,
    build_family,
    emit_json,
    inputs_json,
    pressure_label,
)
from bifurcation.equilibria.hopf import HopfPoint, hopf_points


def add_parser(sub) -> None:
    p = sub.add_parser("hopf", help="Hopf points (shimmy onset speeds) at one pressure")
    add_model_options(p)
    add_model_choice(p)
    add_speed_window(p)
    add_output_options(p)
    p.set_defaults(run=run)


def hopf_row(h: HopfPoint) -> dict:
    return {"speed_kmh": kmh(h.p), "frequency_hz": h.frequency_hz,
            "first_lyapunov": None if h.criticality is None else h.first_lyapunov,
            "criticality": h.criticality.value if h.criticality else None}


def run(args: argparse.Namespace) -> int:
    family = build_family(args)
    mbs = args.model == "mbs"
    # Both models carry the first Lyapunov coefficient: the MBS's from multilinear forms by finite differences.
    points = hopf_points(family, family.nominal, 0.0, args.vmax * KMH)
    effects = list(family.model.effects.names)
    if args.json:
        out = {**inputs_json(args), "hopf": [hopf_row(h) for h in points]}
        if mbs:
            # the Jacobians (and so the Hopf conditions) from the compiled twin or from differences of Exudyn's rhs
            out["model"], out["fidelity"] = "mbs", family.model.fidelity.label
            out["derivatives"] = {"jacobian": family.derivatives, "lyapunov_forms": "differences"}
        emit_json(out)
        return 0
    what = f"MBS, fidelity {family.model.fidelity.label}" if mbs else "reduced model"
    print(f"Hopf points at {pressure_label(args)}, 0-{args.vmax:g} km/h ({what}), pressure effects: "
          f"{','.join(effects) or 'none (section 3 model)'}")
    print(f"  {build_axle(args).label()}")
    if not points:
        print("  none: straight running is stable at every speed in the window")
    for i, h in enumerate(points, 1):
        l1 = "" if h.criticality is None else f"  l1 = {h.first_lyapunov:+.4e}  ({h.criticality.value})"
        print(f"  HB{i}: {kmh(h.p):10.4f} km/h  {h.frequency_hz:7.3f} Hz{l1}")
    return 0
