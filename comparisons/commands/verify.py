"""``shimmy verify``: the main job; compares the models with the paper and with each other, writes a report."""

from __future__ import annotations

import argparse
import os
import sys
import time

from ..options import (
    UsageError,
    add_axle_option,
    add_output_options,
    build_axle,
    emit_json,
    positive_float,
)
from ..report import markdown_table, render_markdown, write_atomically
from ..verification import run_verification


def add_parser(sub) -> None:
    p = sub.add_parser("verify", help="compare the models with the paper and with each other; write a report")
    p.add_argument("--out", default="shimmy-report", metavar="DIR",
                   help="folder for report.md, figures and recordings (default ./shimmy-report)")
    p.add_argument("--quick", action="store_true", help="fewer speeds and shorter runs (under a minute)")
    add_axle_option(p)
    p.add_argument("--pressure-left", type=positive_float("--pressure-left"), metavar="BAR",
                   help="also verify this asymmetric case: left tyre (wheel 2) pressure, bar (needs --pressure-right)")
    p.add_argument("--pressure-right", type=positive_float("--pressure-right"), metavar="BAR",
                   help="right tyre (wheel 1) pressure of the asymmetric case, bar")
    p.add_argument("--no-recordings", action="store_true", help="write no Rerun recordings")
    add_output_options(p)
    p.set_defaults(run=run)


def prepare_out(path: str) -> None:
    if os.path.exists(path) and not os.path.isdir(path):
        raise UsageError(f"--out {path}: a file is in the way (need a folder)")
    try:
        os.makedirs(path, exist_ok=True)
    except OSError as exc:
        raise UsageError(f"--out {path}: cannot create the folder ({exc.strerror})") from None
    if not os.access(path, os.W_OK | os.X_OK):
        raise UsageError(f"--out {path}: folder is not writable")


class StepReporter:
    """Progress naming each step: a bar line on a terminal, one line per finished step otherwise (stderr)."""

    def __init__(self, quiet: bool):
        self.quiet = quiet
        self.tty = sys.stderr.isatty()
        self.start = time.monotonic()
        self.current = None

    def __call__(self, message: str) -> None:
        if self.quiet:
            return
        elapsed = time.monotonic() - self.start
        if self.tty:
            sys.stderr.write(f"\r\033[K[{elapsed:6.1f} s] {message[:110]}")
            sys.stderr.flush()
        elif self.current is not None and not message.startswith("done: "):
            sys.stderr.write(f"[{elapsed:6.1f} s] {self.current}\n")
        if message.startswith("done: "):
            if not self.tty:
                sys.stderr.write(f"[{elapsed:6.1f} s] {message}\n")
            self.current = None
        else:
            self.current = message

    def close(self) -> None:
        if not self.quiet and self.tty:
            sys.stderr.write("\r\033[K")


def run(args: argparse.Namespace) -> int:
    asymmetric = None
    if (args.pressure_left is None) != (args.pressure_right is None):
        raise UsageError("verify: give both --pressure-left and --pressure-right for an asymmetric case")
    if args.pressure_left is not None:
        asymmetric = (args.pressure_right, args.pressure_left)
    prepare_out(args.out)
    axle = build_axle(args)
    reporter = StepReporter(args.json)
    try:
        report = run_verification(args.out, args.quick, axle=axle, asymmetric=asymmetric,
                                  from_file=args.axle is not None or bool(args.overrides),
                                  recordings=not args.no_recordings, progress=reporter)
    finally:
        reporter.close()
    path = os.path.join(args.out, "report.md")
    try:
        write_atomically(path, render_markdown(report))
    except OSError as exc:
        raise UsageError(f"cannot write {path}: {exc.strerror or exc}") from None
    if args.json:
        emit_json({"report": path, "failed": report.failed, "axle": axle.describe(),
                   "plan": report.plan.to_json(), "plan_notes": list(report.plan.notes),
                   "summary": report.summary_rows(),
                   "sections": [{"key": s.key, "title": s.title,
                                 "rows": [{**r.cells, "status": r.status.value, "note": r.note} for r in s.rows]}
                                for s in report.sections]})
    else:
        print(axle.label())
        for s in report.sections:
            print(f"\n{s.title}")
            print(markdown_table(list(s.columns) + ["status"],
                                 [{**r.cells, "status": r.status.value} for r in s.rows]))
        print("\nSummary")
        print(markdown_table(["section", "checks", "pass", "known differences", "fail", "info"],
                             report.summary_rows()))
        print(f"\nreport written to {path}")
    if report.failed:
        sys.stderr.write("shimmy: verification failed: see the FAIL rows in the report\n")
        return 1
    return 0
