"""``shimmy modes``: eigenvalues of straight running at one pressure and speed, with frequency, damping ratio
and what moves (yaw, tramp, lateral travel, steering gear, slip; left/right share), for the reduced model and the
MBS."""

from __future__ import annotations

import argparse
import math

from axles.limits import SPEED_RANGE_KMH, UsageError
from axles.units import KMH
from comparisons.cli.options import (
    add_braking_options,
    add_model_options,
    add_output_options,
    build_axle,
    api_axle,
    braking_label,
    build_fidelity,
    emit_json,
    inputs_json,
    positive_float,
    pressure_label,
)
from reduced_model.mode_shapes import ModeShape, mode_shapes, reduced_inertias
from reduced_model.model import Effects


def add_parser(sub) -> None:
    p = sub.add_parser("modes", help="eigenvalues of straight running at one pressure and speed: frequency, "
                                     "damping ratio and character of each mode, reduced model and MBS")
    add_model_options(p)
    add_braking_options(p)
    p.add_argument("--speed", type=positive_float("--speed"), required=True, metavar="KMH", help="speed, km/h")
    p.add_argument("--fidelity", choices=("reduced", "full"), default=None,
                   help="MBS: all assumptions of the reduced model on (reduced, default) or all off (full)")
    p.add_argument("--assume", metavar="NAME[,NAME]", default=None,
                   help="MBS: keep exactly these assumptions on (see 'shimmy assumptions')")
    add_output_options(p)
    p.set_defaults(run=run)


def _models(args: argparse.Namespace):
    """(key, title, modes) for the reduced model and the MBS."""
    from comparisons.studies.margin_study import mode_inertias
    axle = api_axle(args)
    effects = Effects.parse(args.effects)
    fidelity = build_fidelity(args, "mbs")
    reduced = axle.reduced(effects).problem(args.tyre_pressures, "pressure", args.braking)
    mbs = axle.mbs(fidelity=fidelity, effects=effects).problem(args.tyre_pressures, "pressure", args.braking)
    speed = args.speed * KMH
    return [("reduced", "reduced model", mode_shapes(reduced.linear_matrix(speed, reduced.nominal),
                                                     inertias=reduced_inertias(axle.params.I1, axle.params.I3))),
            ("mbs", f"MBS, fidelity {fidelity.label}",
             mode_shapes(mbs.linear_matrix(speed, mbs.nominal), inertias=mode_inertias(mbs),
                         names=mbs.state_names))], fidelity


def mode_json(m: ModeShape) -> dict:
    return {"real_per_s": m.eigenvalue.real, "imag_rad_per_s": m.eigenvalue.imag,
            "frequency_hz": m.frequency_hz, "damping_ratio": m.damping_ratio, "stable": m.stable,
            "character": m.character, "yaw_share": m.yaw_share, "tramp_share": m.tramp_share,
            "slip_share": m.slip_share, "left_share": m.left_share, "wheel_phase_deg": math.degrees(m.wheel_phase),
            "energy_shares": dict(m.shares)}


def run(args: argparse.Namespace) -> int:
    if args.speed > SPEED_RANGE_KMH[1]:
        raise UsageError(f"--speed must be at most {SPEED_RANGE_KMH[1]:g} km/h, got {args.speed:g}")
    results, fidelity = _models(args)
    if args.json:
        emit_json({**inputs_json(args), "speed_kmh": args.speed, "fidelity": fidelity.label,
                   "models": {key: [mode_json(m) for m in modes] for key, _, modes in results}})
        return 0
    print(f"Modes of straight running at {pressure_label(args)}{braking_label(args)}, {args.speed:g} km/h"
          + (" (about the braked steady state)" if args.braking.active else ""))
    print(f"  {build_axle(args).label()}")
    print("  shares: yaw / tramp (/ lateral / gear on the full geometry) of the kinetic energy, slip of the "
          "squared angles; left: the left wheel's part of the wheel yaw; phase: theta2 against theta1")
    for _, title, modes in results:
        groups = list(modes[0].shares) if modes else []
        print(f"\n{title}")
        print(f"  {'eigenvalue [1/s]':>24s}  {'freq [Hz]':>9s}  {'damping':>8s}  {'character':9s}  "
              + "".join(f"{g:>7s} " for g in groups) + f"{'slip':>5s} {'left':>5s} {'phase':>6s}")
        for m in modes:
            lam = m.eigenvalue
            phase = "-" if math.isnan(m.wheel_phase) else f"{round(math.degrees(m.wheel_phase)) or 0:d}"
            left = "-" if math.isnan(m.left_share) else f"{m.left_share:.2f}"
            flag = "" if m.stable else "  UNSTABLE"
            print(f"  {lam.real:+11.4f} {lam.imag:+11.4f}i  {m.frequency_hz:9.3f}  {m.damping_ratio:+8.4f}  "
                  f"{m.character:9s}  " + "".join(f"{m.shares[g]:7.2f} " for g in groups)
                  + f"{m.slip_share:5.2f} {left:>5s} {phase:>6s}{flag}")
    print("\n'-': the mode does not move that wheel (no share, no phase)")
    return 0
