"""``shimmy assumptions``: Hopf-speed and limit-cycle shifts when the reduced model's assumptions are dropped."""

from __future__ import annotations

import argparse

from comparisons import assumption_shifts as shifts
from axles.units import KMH, kmh
from comparisons.cli.options import (
    add_braking_options,
    add_model_options,
    add_output_options,
    add_speed_window,
    build_axle,
    build_model,
    emit_json,
    inputs_json,
    pressure_label,
)
from comparisons.cli.progress import StepProgress
from mbs_shimmy import assumptions_table
from axles.braking import PLANNED_BRAKINGS
from comparisons.studies.assumption_study import NO_SLIP, assumption_study, study_fidelities


def add_parser(sub) -> None:
    p = sub.add_parser("assumptions", help="shifts of the Hopf speeds and of the peak shimmy amplitude when each "
                                           "assumption of the reduced model is dropped, and what each geometric "
                                           "element of the full axle adds (multibody model)")
    add_model_options(p)
    add_braking_options(p)
    add_speed_window(p)
    p.add_argument("--no-cycles", action="store_true",
                   help="skip the limit cycles (a continuation of every cycle branch of each row's model, about "
                        "10-30 s a row); peaks and their shifts are then null")
    add_output_options(p)
    p.set_defaults(run=run)


def _fmt(value: float | None, spec: str) -> str:
    """The number, or "-" right-aligned to the field width of ``spec`` (a mode that vanished or appeared)."""
    if value is None:
        width = spec.lstrip("+").split(".")[0]
        return "-".rjust(int(width) if width.isdigit() else 1)
    return format(value, spec)


def run(args: argparse.Namespace) -> int:
    model = build_model(args)
    cycles = not args.no_cycles
    # the paper's assumption of no longitudinal slip, dropped at the command's braking or the planned levels
    brakings = (args.braking,) if args.braking.active else PLANNED_BRAKINGS
    rows = len(study_fidelities()) + len(brakings) + (1 if cycles else 0)
    # one line per row on stderr (a bar on a terminal): the continuation takes 10-30 s a row
    with StepProgress(total=rows, job="assumptions") as bar:
        study = assumption_study(model.params, model.effects, args.tyre_pressures, dims=build_axle(args).dims,
                                 vmax=args.vmax * KMH, cycles=cycles, progress=bar, brakings=brakings)
    if args.json:
        out = shifts.study_json(study)
        del out["pressure_bar"], out["effects"]
        emit_json({**inputs_json(args), **out})
        return 0
    effects = ",".join(model.effects.names) or "none (section 3 model)"
    print(f"Assumptions of the reduced model at {pressure_label(args)}, pressure effects: {effects}")
    print(f"  {build_axle(args).label()}")
    print("reduced-model Hopf speeds: " + (", ".join(f"{kmh(v):.2f}" for v in study.reduced_hopf_speeds) or "none")
          + " km/h")
    if cycles:
        print(f"largest limit cycle of the reduced model (continued): {shifts.peak_text(study.reduced_peak)}")
        print("peaks: max|theta1| of each side's largest cycle over its own continued branches")
    summary = {r.name: r.summary for r in assumptions_table().rows}
    elements = {r.name for r in assumptions_table().rows if r.element}
    for row in study.rows:
        if row.assumption.startswith(NO_SLIP):
            print(f"\n{row.assumption}: the paper's free-rolling wheels (reduced model) -> braking (reduced model, "
                  f"MF 6.1 combined slip, from the braked steady state)")
            sides = ("free rolling", "braking")
        elif row.assumption in elements:
            # a new element: full geometry without it (left) -> full geometry (right)
            print(f"\n{row.assumption} (full geometry without -> with the element): {summary[row.assumption]}")
            sides = ("without", "with")
        else:
            label = row.assumption if row.assumption == "full" else f"{row.assumption} off"
            print(f"\n{label}: {summary.get(row.assumption, 'all assumptions off')}")
            sides = ("reduced", "MBS")
        for h in row.hopf:
            print(f"  Hopf {_fmt(shifts.reduced_kmh(h), '9.3f')} -> {_fmt(shifts.mbs_kmh(h), '9.3f')} km/h"
                  f"   shift {_fmt(shifts.shift_kmh(h), '+9.3f')}")
        if cycles:
            print(f"  peak {sides[0]}: {shifts.peak_text(row.peak_reference)}")
            print(f"  peak {sides[1]}: {shifts.peak_text(row.peak_mbs)}")
            print(f"  peak theta1 shift {_fmt(shifts.peak_theta1_shift_deg(row), '+.3f')} deg")
    return 0
