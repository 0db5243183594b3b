"""Command-line option parsing shared by the ``shimmy`` commands: units at the interface, model construction."""

from __future__ import annotations

import argparse
import json
import math
import sys
from typing import Any

from reduced_model.model import Effects, ShimmyModel
from reduced_model.parameters import YANG2024, ParameterError, ShimmyParameters

KMH = 1.0 / 3.6   # m/s per km/h
BAR = 1e5         # Pa per bar

# Second parameters of two-parameter diagrams (the list: pressure and the four tyre properties).
SECOND_PARAMETERS = ("pressure", "a0", "t0", "sigma0", "k5_0")

# Table 1 entries shown (and set) in other units than SI at the interface.
INTERFACE_UNITS = {"pi0": ("bar", BAR)}


class UsageError(Exception):
    """Bad input from the command line: reported as one line, exit code 2."""


def interface_unit(name: str) -> tuple[str, float]:
    """(unit label, SI per interface unit) of a Table 1 entry or 'pressure' at the command line."""
    if name == "pressure":
        return "bar", BAR
    return INTERFACE_UNITS.get(name, (ShimmyParameters.unit(name), 1.0))


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
    """``NAME=VALUE`` strings (interface units) to SI overrides of Table 1."""
    overrides: dict[str, float] = {}
    for item in items or []:
        name, sep, text = item.partition("=")
        name = name.strip()
        if not sep or not name or not text.strip():
            raise UsageError(f"--set expects NAME=VALUE, got '{item}'")
        if name not in ShimmyParameters.names():
            raise UsageError(f"unknown parameter '{name}' in --set (see 'shimmy params')")
        try:
            value = float(text)
        except ValueError:
            raise UsageError(f"--set {name}: '{text}' is not a number") from None
        overrides[name] = value * interface_unit(name)[1]
    return overrides


def add_model_options(p: argparse.ArgumentParser, pressure_required: bool = True) -> None:
    p.add_argument("--pressure", type=positive_float("--pressure"), required=pressure_required,
                   default=None if pressure_required else 2.5, metavar="BAR",
                   help="tyre inflation pressure, bar" + ("" if pressure_required else " (default 2.5)"))
    p.add_argument("--effects", default="", metavar="LIST",
                   help="pressure effects beyond the lateral force: comma list of hcl,pt,rl,vs, or all")
    p.add_argument("--set", action="append", metavar="NAME=VALUE", dest="overrides",
                   help="override a Table 1 entry (units as in 'shimmy params'); repeatable")


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


def build_family(args: argparse.Namespace, param: str = "pressure", pressure: float | None = None):
    """The speed family of the chosen model (reduced or MBS) over ``param``."""
    model = build_model(args)
    fidelity = build_fidelity(args)
    pressure = pressure if pressure is not None else args.pressure * BAR
    if fidelity is None:
        from reduced_model.family import SpeedFamily
        return SpeedFamily(model, param, pressure=pressure)
    from mbs_shimmy import MbsFamily
    return MbsFamily.of(model.params, model.effects, fidelity, param=param, pressure=pressure)


def add_output_options(p: argparse.ArgumentParser, plot: bool = False) -> None:
    p.add_argument("--json", action="store_true", help="machine-readable output on stdout (schema in README)")
    if plot:
        p.add_argument("--plot", metavar="FILE.png", help="draw the result into a PNG file")


def build_model(args: argparse.Namespace) -> ShimmyModel:
    try:
        effects = Effects.parse(args.effects)
        params = YANG2024.replace(**parse_overrides(args.overrides))
    except ParameterError as exc:
        raise UsageError(str(exc)) from None
    return ShimmyModel(params=params, effects=effects)


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
