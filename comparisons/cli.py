"""The ``shimmy`` command: dispatches to :mod:`comparisons.commands`; bad input is one line on stderr, exit 2."""

from __future__ import annotations

import argparse
import importlib
import importlib.util
import sys

from reduced_model.parameters import ParameterError
from reduced_model.special_points import ConvergenceError

from .options import UsageError, resolve_pressures

COMMANDS = ("verify", "hopf", "curves", "cycles", "modes", "simulate", "assumptions", "figures", "params", "bench", "sweep")


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> None:  # one line, not usage + message
        sys.stderr.write(f"shimmy: error: {message}\n")
        raise SystemExit(2)


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="shimmy", description="Truck wheel shimmy: reduced model, bifurcations, multibody model")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND", parser_class=_Parser)
    for name in COMMANDS:
        # A command whose module is not written yet is simply not offered.
        if importlib.util.find_spec(f"comparisons.commands.{name}") is not None:
            importlib.import_module(f"comparisons.commands.{name}").add_parser(sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    args.argv = list(sys.argv[1:] if argv is None else argv)    # echoed in reports
    try:
        resolve_pressures(args)
        return int(args.run(args) or 0)
    except (UsageError, ParameterError) as exc:
        sys.stderr.write(f"shimmy: error: {exc}\n")
        return 2
    except ConvergenceError as exc:
        sys.stderr.write(f"shimmy: failed: {exc}\n")
        return 3
    except BrokenPipeError:  # output piped into head and the like
        sys.stderr.close()
        return 0
    except KeyboardInterrupt:
        sys.stderr.write("shimmy: interrupted\n")
        return 130


if __name__ == "__main__":
    sys.exit(main())
