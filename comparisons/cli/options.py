"""Command-line option parsing shared by the ``shimmy`` commands: units at the interface, model construction."""

from __future__ import annotations

import argparse
import functools
import json
import math
import os
import sys
from typing import Any

from reduced_model.model import Effects, ShimmyModel
from axles.axle import interface_text
from axles.parameters import ParameterError

# Second parameters of two-parameter diagrams: pressures and the four tyre properties.
SECOND_PARAMETERS = ("pressure", "pressure_left", "pressure_right", "a0", "t0", "sigma0", "k5_0", "brake_slip")
from axles.limits import PRESSURE_RANGE_BAR, SPEED_RANGE_KMH, UsageError
from axles.pressures import PRESSURE_PARAMS
from axles.braking import BRAKE_PARAMS


def parse_number(text: str, what: str, lo: float, hi: float, unit: str, lo_open: bool = False) -> float:
    """A finite number within [lo, hi] (``(lo, hi]`` with ``lo_open``) or :class:`UsageError` naming the range."""
    try:
        value = float(text)
    except (ValueError, TypeError):
        raise UsageError(f"{what} must be a number, got '{text}'") from None
    if not math.isfinite(value) or value > hi or value < lo or (lo_open and value == lo):
        bracket = "(" if lo_open else "["
        raise UsageError(f"{what} must be within {bracket}{lo:g}, {hi:g}] {unit}, got {text.strip()}")
    return value


def ranged(what: str, lo: float, hi: float, unit: str, lo_open: bool = False):
    """An argparse ``type`` for :func:`parse_number` (one-line errors through the parser)."""
    def parse(text: str) -> float:
        try:
            return parse_number(text, what, lo, hi, unit, lo_open)
        except UsageError as exc:
            raise argparse.ArgumentTypeError(str(exc)[len(what) + 1:]) from None  # argparse names the option
    return parse


def positive_float(what: str):
    """An argparse ``type``: a finite number above zero (settings without a physical range, e.g. tolerances)."""
    def parse(text: str) -> float:
        try:
            value = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"must be a number, got '{text}'") from None
        if not math.isfinite(value) or value <= 0.0:
            raise argparse.ArgumentTypeError(f"must be positive and finite, got {text}")
        return value
    return parse


def pressure_bar(what: str):
    """A pressure option, bar."""
    return ranged(what, *PRESSURE_RANGE_BAR, "bar")


def add_speed_window(p: argparse.ArgumentParser, vmin: bool = False) -> None:
    lo, hi = SPEED_RANGE_KMH
    if vmin:
        p.add_argument("--vmin", type=ranged("--vmin", 0.0, hi, "km/h"), default=0.0, metavar="KMH",
                       help=f"lower end of the speed window, km/h (default 0; within [0, {hi:g}])")
    p.add_argument("--vmax", type=ranged("--vmax", lo, hi, "km/h", lo_open=True), default=400.0, metavar="KMH",
                   help=f"upper end of the speed window, km/h (default 400; within ({lo:g}, {hi:g}]: the window "
                        f"must reach above {lo:g} km/h)")


def check_window(lo: float, hi: float, name: str, unit: str) -> None:
    """A second-parameter window (``--range LO HI``, interface units) inside the parameter's physical range."""
    if name in PRESSURE_PARAMS:
        a, b = PRESSURE_RANGE_BAR
    elif name in BRAKE_PARAMS:
        from axles.limits import BRAKE_SLIP_RANGE
        a, b = BRAKE_SLIP_RANGE
    else:
        from axles.axle import entry
        a, b = entry(name).range
    for v in (lo, hi):
        if not math.isfinite(v) or not a <= v <= b:
            raise UsageError(f"--range for {name} must lie within [{a:g}, {b:g}] {unit}, got {lo:g} {hi:g}")
    if not lo < hi:
        raise UsageError(f"--range needs LO < HI, got {lo:g} {hi:g}")


def parse_overrides(items: list[str] | None) -> dict[str, float]:
    """``NAME=VALUE`` strings to overrides in interface units (degrees, bar; see 'shimmy params')."""
    from comparisons.api import parse_settings
    try:
        return parse_settings(items or [])
    except ParameterError as exc:
        raise UsageError(interface_text(exc)) from None


def add_axle_option(p: argparse.ArgumentParser) -> None:
    p.add_argument("--axle", metavar="FILE.toml", help="the axle to use, from an axle file ('shimmy params --write' "
                                                        "makes one); default: the paper's truck")
    p.add_argument("--tyre", metavar="FILE.tir", help="the tyre entries from a Magic Formula 6.1/6.2 tyre property "
                                                      "file, on top of --axle and below --set")
    p.add_argument("--set", action="append", metavar="NAME=VALUE", dest="overrides",
                   help="override an axle entry, in the units of 'shimmy params' (degrees, bar, otherwise SI), "
                        "on top of --axle; repeatable")


def add_model_options(p: argparse.ArgumentParser, pressure_required: bool = True) -> None:
    p.add_argument("--pressure", type=pressure_bar("--pressure"), default=None, metavar="BAR",
                   help="inflation pressure of both tyres, bar" + ("" if pressure_required else " (default 2.5)"))
    p.add_argument("--pressure-left", type=pressure_bar("--pressure-left"), default=None, metavar="BAR",
                   help="left tyre (wheel 2, theta2) pressure, bar; the right takes --pressure")
    p.add_argument("--pressure-right", type=pressure_bar("--pressure-right"), default=None, metavar="BAR",
                   help="right tyre (wheel 1, theta1) pressure, bar; the left takes --pressure")
    add_effects_option(p)
    add_axle_option(p)
    p.set_defaults(pressure_required=pressure_required)


def add_effects_option(p: argparse.ArgumentParser) -> None:
    p.add_argument("--effects", default="", metavar="LIST",
                   help="pressure effects beyond the lateral force: comma list of hcl,pt,rl,vs, or all")


def pressures_of(args: argparse.Namespace):
    """The tyre pressures of ``--pressure``/``--pressure-left``/``--pressure-right`` (bar): a
    :class:`~axles.pressures.TyrePressures`, made here and only here for the command line (its range checked once,
    here); None for a command without pressure options.  The parser module stores it as ``args.tyre_pressures``."""
    if not hasattr(args, "pressure_required"):
        return None
    from axles.pressures import TyrePressures
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
    names = [("--pressure" if value is both else what) for what, value in
             (("--pressure-right", right), ("--pressure-left", left))]
    try:
        return TyrePressures.of_bar(right, left, right_name=names[0], left_name=names[1])
    except ParameterError as exc:
        raise UsageError(interface_text(exc)) from None


def add_braking_options(p: argparse.ArgumentParser) -> None:
    """``--brake-slip`` / ``--brake-force``: a steady braking of the front wheels (both models)."""
    from axles.limits import BRAKE_FORCE_RANGE_N, BRAKE_SLIP_RANGE
    group = p.add_mutually_exclusive_group()
    group.add_argument("--brake-slip", metavar="SLIP[,SLIP]", default=None,
                       help=f"steady brake slip of both wheels, or right,left (0 free rolling, 1 locked, negative "
                            f"driving: ISO kappa = -SLIP; within [{BRAKE_SLIP_RANGE[0]:g}, "
                            f"{BRAKE_SLIP_RANGE[1]:g}]; a value starting with '-' as --brake-slip=-0.05); MF 6.1 "
                            f"combined slip")
    group.add_argument("--brake-force", metavar="N[,N]", default=None,
                       help=f"steady brake force of both wheels, or right,left, N rearward (negative: a drive "
                            f"force, forward, as --brake-force=-2000; within [{BRAKE_FORCE_RANGE_N[0]:g}, "
                            f"{BRAKE_FORCE_RANGE_N[1]:g}] N and the tyre's grip)")


def braking_of(args: argparse.Namespace):
    """The braking of ``--brake-slip``/``--brake-force``: a :class:`~axles.braking.Braking`, made here and only
    here for the command line (its range checked once, here); free rolling without them, None for a command
    without braking options.  The parser module stores it as ``args.braking``."""
    if not hasattr(args, "brake_slip"):
        return None
    from axles.braking import FREE_ROLLING, Braking
    text, option = ((args.brake_slip, "--brake-slip") if args.brake_slip is not None
                    else (args.brake_force, "--brake-force"))
    if text is None:
        return FREE_ROLLING
    items = [t.strip() for t in text.split(",")]
    if len(items) not in (1, 2) or not all(items):
        raise UsageError(f"{option} takes one value or right,left, got '{text}'")
    values = []
    for item in items:
        try:
            values.append(float(item))
        except ValueError:
            raise UsageError(f"{option} must be a number (or right,left), got '{item}'") from None
    right, left = (values[0], values[0]) if len(values) == 1 else values
    try:
        return Braking.of_slip(right, left) if option == "--brake-slip" else Braking.of_force(right, left)
    except ParameterError as exc:
        raise UsageError(f"{option}: {exc}") from None


def braking_json(args: argparse.Namespace) -> dict:
    """The ``"braking"`` field of a JSON output, only under braking (free rolling: nothing, as before braking)."""
    braking = getattr(args, "braking", None)
    return {"braking": braking.describe()} if braking is not None and braking.active else {}


def braking_label(args: argparse.Namespace) -> str:
    """', brake slip 0.05' for text headers under braking, '' free rolling."""
    braking = getattr(args, "braking", None)
    return f", {braking}" if braking is not None and braking.active else ""


def pressures_json(args: argparse.Namespace) -> dict:
    """The pressure fields of every JSON output: left and right always, ``pressure_bar`` when they are equal."""
    p = args.tyre_pressures
    out = {"pressure_left_bar": p.left_bar, "pressure_right_bar": p.right_bar}
    if p.alike:
        out = {"pressure_bar": p.left_bar, **out}
    return out


def pressure_label(args: argparse.Namespace) -> str:
    """'1.5 bar' or 'right 1.5 / left 1.2 bar' for text headers."""
    return str(args.tyre_pressures)


def api_axle(args: argparse.Namespace):
    """The axle of the command (:class:`comparisons.api.Axle`): ``--axle`` (or the paper's) with ``--set`` on
    top, and ``--tyre`` between them."""
    path, tyre = getattr(args, "axle", None), getattr(args, "tyre", None)
    return _axle_of(path, _stamp(path), tyre, _stamp(tyre), tuple(getattr(args, "overrides", None) or ()))


def _stamp(path: str | None):
    """A file's mtime and size, so that a file written again is read again (None: no file, or the reader reports
    why it cannot be read)."""
    if path is None:
        return None
    try:
        info = os.stat(path)
    except (OSError, ValueError):
        return None
    return info.st_mtime_ns, info.st_size


@functools.lru_cache(maxsize=4)
def _axle_of(path: str | None, stamp, tyre: str | None, tyre_stamp, items: tuple[str, ...]):
    """One reading of the axle and tyre files per command, however many parts of it ask."""
    from comparisons.api import Axle
    try:
        axle = Axle.paper() if path is None else Axle.from_file(path)
        return (axle if tyre is None else axle.with_tyre(tyre)).with_set(*items)
    except ParameterError as exc:
        raise UsageError(interface_text(exc)) from None


def build_axle(args: argparse.Namespace):
    """The axle's entries (:class:`axles.axle.Axle`) of :func:`api_axle`."""
    return api_axle(args).data


def inputs_json(args: argparse.Namespace) -> dict:
    """What every JSON output echoes: the axle, the pressures and the pressure effects."""
    out = {"axle": build_axle(args).describe()}
    if hasattr(args, "pressure_left"):
        out.update(pressures_json(args))
    if hasattr(args, "effects"):
        out["effects"] = list(Effects.parse(args.effects).names)
    out.update(braking_json(args))
    return out


def add_model_choice(p: argparse.ArgumentParser) -> None:
    """``--model reduced|mbs`` with the MBS fidelity options."""
    p.add_argument("--model", choices=("reduced", "mbs"), default="reduced",
                   help="the paper's reduced model (default) or the Exudyn multibody model")
    p.add_argument("--fidelity", choices=("reduced", "full"), default=None,
                   help="MBS: all assumptions of the reduced model on (reduced, default) or all off (full)")
    p.add_argument("--assume", metavar="NAME[,NAME]", default=None,
                   help="MBS: keep exactly these assumptions on (see 'shimmy assumptions')")


def build_fidelity(args: argparse.Namespace, model: str | None = None):
    """The MBS fidelity from --fidelity/--assume; None for the reduced model (and an error if they are given).
    ``model``: the model asked for, when the command does not take --model (default ``args.model``)."""
    if (model or args.model) != "mbs":
        if args.fidelity is not None or args.assume is not None:
            raise UsageError("--fidelity and --assume apply to --model mbs only")
        return None
    if args.fidelity is not None and args.assume is not None:
        raise UsageError("give either --fidelity or --assume, not both")
    from comparisons.api import fidelity_of
    try:
        return fidelity_of(args.fidelity, args.assume)
    except ParameterError as exc:
        raise UsageError(interface_text(exc)) from None


def reduced_model(args: argparse.Namespace):
    """The reduced model of the options (:class:`comparisons.api.ReducedModel`): the axle and ``--effects``."""
    try:
        return api_axle(args).reduced(effects=args.effects)
    except ParameterError as exc:
        raise UsageError(interface_text(exc)) from None


def chosen_model(args: argparse.Namespace):
    """The model of ``--model`` (:class:`comparisons.api.ReducedModel` or :class:`comparisons.api.MultibodyModel`)."""
    reduced = reduced_model(args)      # --effects is checked before --fidelity/--assume, as always
    fidelity = build_fidelity(args)
    return reduced if fidelity is None else reduced.axle.mbs(fidelity, effects=reduced.effects)


def build_model_family(args: argparse.Namespace, param: str = "pressure"):
    """The API's family (:class:`comparisons.api.ModelFamily`) of the chosen model (reduced or MBS) over ``param``,
    at the operating pressures and braking."""
    from axles.braking import FREE_ROLLING
    braking = getattr(args, "braking", None) or FREE_ROLLING
    try:
        family = chosen_model(args).family(args.tyre_pressures, param, braking)
        if braking.active or param in BRAKE_PARAMS:
            family.problem.validate(family.q)   # a brake force beyond the tyre's grip, no steady state
    except ParameterError as exc:
        raise UsageError(interface_text(exc)) from None
    return family


def build_family(args: argparse.Namespace, param: str = "pressure"):
    """The toolkit's speed family of the chosen model over ``param`` (:func:`build_model_family`)."""
    return build_model_family(args, param).problem


def add_output_options(p: argparse.ArgumentParser, plot: bool = False) -> None:
    p.add_argument("--json", action="store_true", help="machine-readable output on stdout (schema in docs/json.md)")
    if plot:
        p.add_argument("--plot", metavar="FILE.png", help="draw the result into a PNG file")


def build_model(args: argparse.Namespace) -> ShimmyModel:
    """The reduced model of the axle with the chosen pressure effects."""
    return reduced_model(args).model


def check_output_path(path: str, what: str = "output", recording: bool = False) -> None:
    """Fail before the work, not after it, when an output file cannot be written where asked."""
    from comparisons.files import OutputPathError, check_output
    try:
        check_output(path, what, recording)
    except OutputPathError as exc:
        raise UsageError(interface_text(exc)) from None


def finite_json(obj: Any) -> Any:
    """``obj`` with every non-finite float (NaN, infinity) replaced by None: JSON has no such numbers."""
    if isinstance(obj, float):
        return obj if math.isfinite(obj) else None
    if isinstance(obj, dict):
        return {k: finite_json(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [finite_json(v) for v in obj]
    if hasattr(obj, "tolist") and hasattr(obj, "dtype"):   # numpy scalars and arrays
        return finite_json(obj.tolist())
    return obj


def emit_json(obj: Any) -> None:
    """Write ``obj`` as JSON on stdout; non-finite numbers become null (never NaN or Infinity)."""
    json.dump(finite_json(obj), sys.stdout, indent=2, allow_nan=False)
    sys.stdout.write("\n")




