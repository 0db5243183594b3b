"""``shimmy hopf``: Hopf points of straight running at one pressure in 0..vmax, reduced model or MBS."""

from __future__ import annotations

import argparse
import math

from axles.units import KMH
from comparisons.api import hopf_points
from comparisons.cli.options import (
    add_braking_options,
    add_model_choice,
    add_model_options,
    add_output_options,
    add_speed_window,
    braking_label,
    build_axle,
    build_model_family,
    emit_json,
    inputs_json,
    pressure_label,
)
from comparisons.results import HopfSummary


def add_parser(sub) -> None:
    p = sub.add_parser("hopf", help="Hopf points (shimmy onset speeds) at one pressure")
    add_model_options(p)
    add_braking_options(p)
    add_model_choice(p)
    add_speed_window(p)
    add_output_options(p)
    p.set_defaults(run=run)


def hopf_row(h: HopfSummary) -> dict:
    return {"speed_kmh": h.speed_kmh, "frequency_hz": h.frequency_hz,
            "first_lyapunov": None if h.criticality is None else h.first_lyapunov,
            "criticality": h.criticality.value if h.criticality else None,
            # where the right-hand side has a kink at straight running: the quadratic amplitude coefficient and
            # the criticality it gives at vanishing amplitude (null where it is smooth there)
            "kink_coefficient": h.kink if h.kink_criticality else None,
            "kink_criticality": h.kink_criticality.value if h.kink_criticality else None}


STEADY_KMH = 60.0     # where hopf reports the braked steady state


def steady_state(family) -> dict:
    """The braked steady state at :data:`STEADY_KMH`: the steer and tramp angles, deg."""
    x = family.equilibrium(STEADY_KMH * KMH, family.nominal)
    names = family.state_names
    angles = {f"{n}_deg": math.degrees(x[names.index(n)]) for n in ("theta1", "theta2", "psi")}
    return {"speed_kmh": STEADY_KMH, **angles}


def run(args: argparse.Namespace) -> int:
    family = build_model_family(args)
    mbs = args.model == "mbs"
    # Both models carry the first Lyapunov coefficient: the MBS's from the twin's exact forms or by differences.
    points = hopf_points(family, vmax_kmh=args.vmax).points
    effects = list(family.problem.model.effects.names)
    steady = steady_state(family.problem) if args.braking.active else {}
    if args.json:
        out = {**inputs_json(args), "hopf": [hopf_row(h) for h in points]}
        if steady:
            out["steady_state"] = steady
        if mbs:
            # the Jacobians (and so the Hopf conditions) from the compiled twin or from differences of Exudyn's rhs
            out["model"], out["fidelity"] = "mbs", family.problem.model.fidelity.label
            out["derivatives"] = {"jacobian": family.problem.derivatives,
                                  "lyapunov_forms": family.problem.lyapunov_forms}
        emit_json(out)
        return 0
    what = f"MBS, fidelity {family.problem.model.fidelity.label}" if mbs else "reduced model"
    print(f"Hopf points at {pressure_label(args)}{braking_label(args)}, 0-{args.vmax:g} km/h ({what}), "
          f"pressure effects: "
          f"{','.join(effects) or 'none (section 3 model)'}")
    print(f"  {build_axle(args).label()}")
    if args.braking.active:
        shown = ", ".join(f"{k.replace('_deg', '')} {v:+.4f}" for k, v in steady.items() if k != "speed_kmh")
        print(f"  straight running under braking is a steady state off x = 0 (found by Newton; the same at every "
              f"speed), deg: {shown}")
    if not points:
        print("  none: straight running is stable at every speed in the window")
    for i, h in enumerate(points, 1):
        l1 = "" if h.criticality is None else f"  l1 = {h.first_lyapunov:+.4e}  ({h.criticality.value})"
        kink = (f"  at the kink a = {h.kink:+.4e} ({h.kink_criticality.value} at vanishing amplitude)"
                if h.kink_criticality else "")
        print(f"  HB{i}: {h.speed_kmh:10.4f} km/h  {h.frequency_hz:7.3f} Hz{l1}{kink}")
    if mbs and points:
        from mbs_shimmy.linearisation import KINKED_FORMS, L1_NOT_WELL_POSED
        if KINKED_FORMS in family.problem.lyapunov_forms:
            print(f"  {L1_NOT_WELL_POSED}")
    return 0
