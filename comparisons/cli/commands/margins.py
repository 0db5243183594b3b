"""``shimmy margins``: the least damping ratio of straight running over speed and tyre pressure, reduced model or
MBS, with the mode it belongs to."""

from __future__ import annotations

import argparse
import sys

from axles.limits import SPEED_RANGE_KMH, UsageError
from comparisons.cli.options import (
    add_axle_option,
    add_braking_options,
    add_effects_option,
    add_model_choice,
    add_output_options,
    add_speed_window,
    api_axle,
    braking_label,
    check_window,
    chosen_model,
    emit_json,
    inputs_json,
)
from axles.parameters import ParameterError
from comparisons.cli.progress import progress

# The API's argument names in its messages, as this command's options.
OPTION_NAMES = {"pressure_points": "--pressures", "speed_points": "--speeds", "vmin_kmh": "--vmin",
                "vmax_kmh": "--vmax"}


def add_parser(sub) -> None:
    p = sub.add_parser("margins", help="stability margins: the least damping ratio of straight running over speed "
                                       "and pressure")
    p.add_argument("--range", nargs=2, type=float, metavar=("LO", "HI"), default=None,
                   help="tyre pressures (both tyres alike), bar (default: the axle's [operating] window)")
    add_effects_option(p)
    add_axle_option(p)
    add_model_choice(p)
    add_braking_options(p)
    add_speed_window(p, vmin=True)
    p.add_argument("--speeds", type=int, default=201, metavar="N", help="speeds of the grid (default 201)")
    p.add_argument("--pressures", type=int, default=31, metavar="N", help="pressures of the grid (default 31)")
    add_output_options(p, plot=True)
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    from comparisons.api import stability_margins
    lo, hi = args.range if args.range is not None else api_axle(args).data.pressure_range_bar
    if args.range is not None:
        check_window(lo, hi, "pressure", "bar")
    model = chosen_model(args)
    rows = args.pressures if lo < hi else 1
    try:
        with progress(rows, "margins: pressures of the grid", args.json or not sys.stderr.isatty()) as bar:
            result = stability_margins(model, (lo, hi), max(args.vmin, SPEED_RANGE_KMH[0]), args.vmax,
                                       args.pressures, args.speeds, progress=lambda: bar.update(1),
                                       braking=args.braking)
    except ParameterError as exc:
        text = str(exc)
        for name, option in OPTION_NAMES.items():
            text = text.replace(name, option)
        raise UsageError(text) from None
    if args.plot:
        from comparisons.figures.margin_figures import plot_margin_map
        plot_margin_map(result.study, args.plot, title=f"Least damping ratio, {model.label()}"
                                                       f"{braking_label(args)}")
    if args.json:
        fidelity = {"model": "mbs", "fidelity": model.fidelity.label} if args.model == "mbs" else {"model": "reduced"}
        emit_json({**inputs_json(args), **fidelity, **result.study.to_json()})
        return 0
    print(result)
    print(f"  {api_axle(args).data.label()}")
    if args.plot:
        print(f"  plot written to {args.plot}")
    sys.stdout.flush()
    return 0
