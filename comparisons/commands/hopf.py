"""``shimmy hopf``: Hopf points of straight running at one pressure in 0..vmax."""

from __future__ import annotations

import argparse

from reduced_model.family import SpeedFamily
from reduced_model.hopf import HopfPoint, hopf_points

from ..options import BAR, KMH, add_model_options, add_output_options, build_model, emit_json, positive_float


def add_parser(sub) -> None:
    p = sub.add_parser("hopf", help="Hopf points (shimmy onset speeds) at one pressure")
    add_model_options(p)
    p.add_argument("--vmax", type=positive_float("--vmax"), default=400.0, metavar="KMH",
                   help="upper end of the speed window, km/h (default 400)")
    add_output_options(p)
    p.set_defaults(run=run)


def hopf_row(h: HopfPoint) -> dict:
    return {"speed_kmh": h.speed_kmh, "frequency_hz": h.frequency_hz, "first_lyapunov": h.first_lyapunov,
            "criticality": h.criticality.value if h.criticality else None}


def run(args: argparse.Namespace) -> int:
    model = build_model(args)
    family = SpeedFamily(model, "pressure")
    points = hopf_points(family, args.pressure * BAR, 0.0, args.vmax * KMH)
    if args.json:
        emit_json({"pressure_bar": args.pressure, "effects": list(model.effects.names),
                   "hopf": [hopf_row(h) for h in points]})
        return 0
    effects = ",".join(model.effects.names) or "none (section 3 model)"
    print(f"Hopf points at {args.pressure:g} bar, 0-{args.vmax:g} km/h, pressure effects: {effects}")
    if not points:
        print("  none: straight running is stable at every speed in the window")
    for i, h in enumerate(points, 1):
        print(f"  HB{i}: {h.speed_kmh:10.4f} km/h  {h.frequency_hz:7.3f} Hz  l1 = {h.first_lyapunov:+.4e}"
              f"  ({h.criticality.value})")
    return 0
