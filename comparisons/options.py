"""Command-line option parsing shared by the ``shimmy`` commands: units at the interface, model construction."""

from __future__ import annotations

import argparse
import json
import math
import sys
from typing import Any

from reduced_model.model import Effects, ShimmyModel
from reduced_model.parameters import ParameterError

from .units import BAR, KMH, interface_of

# Second parameters of two-parameter diagrams: pressures and the four tyre properties.
SECOND_PARAMETERS = ("pressure", "pressure_left", "pressure_right", "a0", "t0", "sigma0", "k5_0")
PRESSURE_PARAMS = ("pressure", "pressure_left", "pressure_right")


class UsageError(Exception):
    """Bad input from the command line: reported as one line, exit code 2."""


def interface_unit(name: str) -> tuple[str, float]:
    """(unit label, SI per interface unit) of an axle entry or a pressure at the command line."""
    if name in PRESSURE_PARAMS:
        return "bar", BAR
    from .axle import entry
    return interface_of(entry(name).si_unit)


def _number(what: str, allow_zero: bool):
    def parse(text: str) -> float:
        try:
            value = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{what} must be a number, got '{text}'") from None
        if not math.isfinite(value) or value < 0.0 or (value == 0.0 and not allow_zero):
            raise argparse.ArgumentTypeError(f"{what} must {'not be negative' if allow_zero else 'be positive'}, "
                                             f"got {text}")
        return value
    return parse


def positive_float(what: str):
    return _number(what, allow_zero=False)


def non_negative_float(what: str):
    return _number(what, allow_zero=True)


def add_speed_window(p: argparse.ArgumentParser, vmin: bool = False) -> None:
    if vmin:
        p.add_argument("--vmin", type=non_negative_float("--vmin"), default=0.0, metavar="KMH",
                       help="lower end of the speed window, km/h (default 0; never below 0.5)")
    p.add_argument("--vmax", type=positive_float("--vmax"), default=400.0, metavar="KMH",
                   help="upper end of the speed window, km/h (default 400)")


def parse_overrides(items: list[str] | None) -> dict[str, float]:
    """``NAME=VALUE`` strings to overrides in interface units (degrees, bar; see 'shimmy params')."""
    from .axle import entries
    overrides: dict[str, float] = {}
    for item in items or []:
        name, sep, text = item.partition("=")
        name = name.strip()
        if not sep or not name or not text.strip():
            raise UsageError(f"--set expects NAME=VALUE, got '{item}'")
        if name not in entries():
            from .axle import entry
            try:
                entry(name, "parameter")
            except ParameterError as exc:
                raise UsageError(f"{exc} in --set") from None
        try:
            value = float(text)
        except ValueError:
            raise UsageError(f"--set {name}: '{text}' is not a number") from None
        overrides[name] = value
    return overrides


def add_axle_option(p: argparse.ArgumentParser) -> None:
    p.add_argument("--axle", metavar="FILE.toml", help="the axle to use, from an axle file ('shimmy params --write' "
                                                        "makes one); default: the paper's truck")
    p.add_argument("--set", action="append", metavar="NAME=VALUE", dest="overrides",
                   help="override an axle entry, in the units of 'shimmy params' (degrees, bar, otherwise SI), "
                        "on top of --axle; repeatable")


def add_model_options(p: argparse.ArgumentParser, pressure_required: bool = True) -> None:
    p.add_argument("--pressure", type=positive_float("--pressure"), default=None, metavar="BAR",
                   help="inflation pressure of both tyres, bar" + ("" if pressure_required else " (default 2.5)"))
    p.add_argument("--pressure-left", type=positive_float("--pressure-left"), default=None, metavar="BAR",
                   help="left tyre (wheel 2, theta2) pressure, bar; the right takes --pressure")
    p.add_argument("--pressure-right", type=positive_float("--pressure-right"), default=None, metavar="BAR",
                   help="right tyre (wheel 1, theta1) pressure, bar; the left takes --pressure")
    p.add_argument("--effects", default="", metavar="LIST",
                   help="pressure effects beyond the lateral force: comma list of hcl,pt,rl,vs, or all")
    add_axle_option(p)
    p.set_defaults(pressure_required=pressure_required)


def resolve_pressures(args: argparse.Namespace) -> None:
    """Fill ``args.pressure_right``/``pressure_left`` (bar) and ``args.pressure`` (their mean) from the options."""
    if getattr(args, "_pressures_resolved", False) or not hasattr(args, "pressure_required"):
        return
    both, left, right = args.pressure, args.pressure_left, args.pressure_right
    if both is None and (left is None or right is None):
        if left is None and right is None and not args.pressure_required:
            both = 2.5
        elif left is None and right is None:
            raise UsageError("--pressure BAR is required (or both --pressure-left and --pressure-right)")
        else:
            given = "--pressure-left" if left is not None else "--pressure-right"
            raise UsageError(f"{given} sets one tyre; give --pressure for the other "
                             f"(or both --pressure-left and --pressure-right)")
    right = both if right is None else right
    left = both if left is None else left
    for what, value in (("--pressure-right", right), ("--pressure-left", left)):
        if not 0.05 <= value <= 20.0:
            raise UsageError(f"{what if value is not both else '--pressure'} must be within [0.05, 20] bar, "
                             f"got {value:g}")
    args.pressure_right, args.pressure_left = float(right), float(left)
    args.pressure = args.pressure_right if right == left else 0.5 * (right + left)
    args._pressures_resolved = True


def operating_pressure(args: argparse.Namespace) -> float | tuple[float, float]:
    """Tyre pressures for the models, Pa: one value when both tyres are alike, else (right, left)."""
    resolve_pressures(args)
    r, l = args.pressure_right * BAR, args.pressure_left * BAR
    return r if args.pressure_right == args.pressure_left else (r, l)


def pressures_json(args: argparse.Namespace) -> dict:
    """The pressure fields of every JSON output: left and right always, ``pressure_bar`` when they are equal."""
    resolve_pressures(args)
    out = {"pressure_left_bar": args.pressure_left, "pressure_right_bar": args.pressure_right}
    if args.pressure_left == args.pressure_right:
        out = {"pressure_bar": args.pressure_left, **out}
    return out


def pressure_label(args: argparse.Namespace) -> str:
    """'1.5 bar' or 'right 1.5 / left 1.2 bar' for text headers."""
    resolve_pressures(args)
    if args.pressure_left == args.pressure_right:
        return f"{args.pressure_left:g} bar"
    return f"right {args.pressure_right:g} / left {args.pressure_left:g} bar"


def build_axle(args: argparse.Namespace):
    """The axle of the command: ``--axle`` (or the paper's) with ``--set`` on top; cached on ``args``."""
    cached = getattr(args, "_axle", None)
    if cached is not None:
        return cached
    from .axle_file import axle_from_path_or_paper
    try:
        axle = axle_from_path_or_paper(getattr(args, "axle", None))
        overrides = parse_overrides(getattr(args, "overrides", None))
        axle = axle.with_overrides(overrides) if overrides else axle
    except ParameterError as exc:
        raise UsageError(str(exc)) from None
    args._axle = axle
    return axle


def inputs_json(args: argparse.Namespace) -> dict:
    """What every JSON output echoes: the axle, the pressures and the pressure effects."""
    out = {"axle": build_axle(args).describe()}
    if hasattr(args, "pressure_left"):
        out.update(pressures_json(args))
    if hasattr(args, "effects"):
        out["effects"] = list(Effects.parse(args.effects).names)
    return out


def add_model_choice(p: argparse.ArgumentParser) -> None:
    """``--model reduced|mbs`` with the MBS fidelity options."""
    p.add_argument("--model", choices=("reduced", "mbs"), default="reduced",
                   help="the paper's reduced model (default) or the Exudyn multibody model")
    p.add_argument("--fidelity", choices=("reduced", "full"), default=None,
                   help="MBS: all assumptions of the reduced model on (reduced, default) or all off (full)")
    p.add_argument("--assume", metavar="NAME[,NAME]", default=None,
                   help="MBS: keep exactly these assumptions on (see 'shimmy assumptions')")


def build_fidelity(args: argparse.Namespace):
    """The MBS fidelity from --fidelity/--assume; None for the reduced model (and an error if they are given)."""
    if args.model != "mbs":
        if args.fidelity is not None or args.assume is not None:
            raise UsageError("--fidelity and --assume apply to --model mbs only")
        return None
    if args.fidelity is not None and args.assume is not None:
        raise UsageError("give either --fidelity or --assume, not both")
    from mbs_shimmy import Fidelity
    try:
        return Fidelity.parse(args.assume if args.assume is not None else (args.fidelity or "reduced"))
    except ParameterError as exc:
        raise UsageError(str(exc)) from None


def build_family(args: argparse.Namespace, param: str = "pressure"):
    """The speed family of the chosen model (reduced or MBS) over ``param``, at the operating pressures."""
    model = build_model(args)
    fidelity = build_fidelity(args)
    pressure = operating_pressure(args)
    if fidelity is None:
        from reduced_model.family import SpeedFamily
        return SpeedFamily(model, param, pressure=pressure)
    from mbs_shimmy import MbsFamily
    return MbsFamily.of(model.params, model.effects, fidelity, dims=build_axle(args).dims, param=param,
                        pressure=pressure)


def add_output_options(p: argparse.ArgumentParser, plot: bool = False) -> None:
    p.add_argument("--json", action="store_true", help="machine-readable output on stdout (schema in README)")
    if plot:
        p.add_argument("--plot", metavar="FILE.png", help="draw the result into a PNG file")


def build_model(args: argparse.Namespace) -> ShimmyModel:
    """The reduced model of the axle with the chosen pressure effects."""
    axle = build_axle(args)
    try:
        effects = Effects.parse(args.effects)
    except ParameterError as exc:
        raise UsageError(str(exc)) from None
    return ShimmyModel(params=axle.params, effects=effects)


def check_output_path(path: str) -> None:
    """Fail before the work, not after it, when an output file cannot be written where asked."""
    import os
    folder = os.path.dirname(os.path.abspath(path))
    if os.path.isdir(path):
        raise UsageError(f"{path}: a directory is in the way")
    if not os.path.isdir(folder):
        raise UsageError(f"{path}: the folder {folder} does not exist")
    if not os.access(folder, os.W_OK | os.X_OK):
        raise UsageError(f"{path}: the folder is not writable")


def emit_json(obj: Any) -> None:
    json.dump(obj, sys.stdout, indent=2)
    sys.stdout.write("\n")


def ticker(bar):
    """A ``progress(done, total)`` callback that moves a :func:`progress` bar."""
    def tick(done: int, total: int) -> None:
        bar.total = total
        bar.n = done
        bar.refresh()
    return tick


def progress(total: int, description: str, quiet: bool):
    """A tqdm progress bar on stderr; silent under --json or when stderr is not a terminal."""
    from tqdm import tqdm
    return tqdm(total=total, desc=description, disable=quiet or not sys.stderr.isatty(), leave=False,
                file=sys.stderr)
