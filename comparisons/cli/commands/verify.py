"""``shimmy verify``: the main job; compares the models with the paper and with each other, writes a report."""

from __future__ import annotations

import argparse
import dataclasses
import shlex
import sys
import time

from axles.axle import interface_text
from axles.limits import UsageError
from axles.parameters import ParameterError
from comparisons.cli.options import (
    add_axle_option,
    add_braking_options,
    add_output_options,
    build_axle,
    emit_json,
    positive_float,
)
from comparisons.cli.progress import StepProgress
from comparisons.files import OutputPathError, prepare_folder
from comparisons.verify.rendering import markdown_table, write_report
from comparisons.verify.report import SUMMARY_COLUMNS, run_metadata
from comparisons.verify.run import run_verification


def add_parser(sub) -> None:
    p = sub.add_parser("verify", help="compare the models with the paper and with each other; write a report",
                       description="The main job: run the reduced model (the paper's equations) and the geometrically "
                                   "full multibody model side by side on planned pressures and speeds, check them "
                                   "against each other and against the paper's printed numbers, and write a report "
                                   "(report.html, report.md, figures, Rerun recordings) into --out. Prints the "
                                   "verdict, a summary and the report's path; exits 1 if an equivalence check "
                                   "fails.")
    p.add_argument("--out", default="shimmy-report", metavar="DIR",
                   help="folder for report.md, figures and recordings (default ./shimmy-report)")
    p.add_argument("--quick", action="store_true", help="fewer speeds and shorter runs (under a minute)")
    add_axle_option(p)
    p.add_argument("--pressure-left", type=positive_float("--pressure-left"), metavar="BAR",
                   help="also verify this asymmetric case: left tyre (wheel 2) pressure, bar (needs --pressure-right)")
    p.add_argument("--pressure-right", type=positive_float("--pressure-right"), metavar="BAR",
                   help="right tyre (wheel 1) pressure of the asymmetric case, bar")
    p.add_argument("--no-recordings", action="store_true", help="write no Rerun recordings")
    add_braking_options(p)
    add_output_options(p)
    p.set_defaults(run=run)


def prepare_out(path: str) -> None:
    try:
        prepare_folder(path, "--out")
    except OutputPathError as exc:
        raise UsageError(interface_text(exc)) from None


def run(args: argparse.Namespace) -> int:
    asymmetric = None
    if (args.pressure_left is None) != (args.pressure_right is None):
        raise UsageError("verify: give both --pressure-left and --pressure-right for an asymmetric case")
    if args.pressure_left is not None:
        asymmetric = (args.pressure_right, args.pressure_left)
    axle = build_axle(args)
    try:   # before planning: entries that contradict each other (after --set too) cannot make a multibody axle
        axle.check_consistent()
    except ParameterError as exc:
        raise UsageError(interface_text(exc)) from None
    prepare_out(args.out)
    start = time.perf_counter()
    with StepProgress(job="verify") as progress:
        report = run_verification(args.out, args.quick, axle=axle, asymmetric=asymmetric,
                                  from_file=args.axle is not None or bool(args.overrides),
                                  recordings=not args.no_recordings, progress=progress,
                                  announce=progress.set_steps, braking=args.braking)
    command = "shimmy " + " ".join(shlex.quote(a) for a in args.argv)
    report = dataclasses.replace(report, metadata=run_metadata(args.quick, axle, time.perf_counter() - start,
                                                               command))
    try:
        path, page = write_report(report, args.out)
    except OSError as exc:
        raise UsageError(f"cannot write the report into {args.out}: {exc.strerror or exc}") from None
    if args.json:
        emit_json({"report": path, "html": page, "failed": report.failed, "axle": axle.describe(),
                   "metadata": dataclasses.asdict(report.metadata),
                   "verdict": report.verdict.to_json(),
                   "plan": report.plan.to_json(), "plan_notes": list(report.plan.notes),
                   "scans": [scan.to_json() for scan in report.plan.scans],
                   "summary": report.summary_rows(),
                   "sections": [{"key": s.key, "title": s.title,
                                 "rows": [{**r.cells, "status": r.status.value, "note": r.note} for r in s.rows]}
                                for s in report.sections]})
    else:
        # The verdict and the count of checks per section; the tables themselves are in the report (a full run's
        # would be some 360 lines here).
        print(axle.label())
        print("\nVerdict")
        print("\n".join(report.verdict.lines()))
        print("\nSummary (checks per section)")
        print(markdown_table(list(SUMMARY_COLUMNS), report.summary_rows()))
        print(f"\nOverall: {report.overall()}")
        print(f"\nThe report, every table with its notes: {page}\n(the same as Markdown: {path})")
    if report.failed:
        sys.stderr.write("shimmy: verification failed: see the FAIL rows in the report\n")
        return 1
    return 0
