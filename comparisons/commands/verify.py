"""``shimmy verify``: the main job; compares the models with the paper and with each other, writes a report."""

from __future__ import annotations

import argparse
import os
import sys

from ..options import UsageError, add_output_options, emit_json, progress
from ..report import markdown_table, render_markdown, write_atomically
from ..verification import SECTIONS, run_verification


def add_parser(sub) -> None:
    p = sub.add_parser("verify", help="compare the models with the paper and with each other; write a report")
    p.add_argument("--out", default="shimmy-report", metavar="DIR",
                   help="folder for report.md, figures and recordings (default ./shimmy-report)")
    p.add_argument("--quick", action="store_true", help="fewer speeds and shorter runs (under 2 minutes)")
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


def run(args: argparse.Namespace) -> int:
    prepare_out(args.out)
    with progress(len(SECTIONS), "verify", args.json) as bar:
        report = run_verification(args.out, args.quick, progress=lambda done, total: bar.update(1))
    path = os.path.join(args.out, "report.md")
    try:
        write_atomically(path, render_markdown(report))
    except OSError as exc:
        raise UsageError(f"cannot write {path}: {exc.strerror or exc}") from None
    if args.json:
        emit_json({"report": path, "failed": report.failed, "summary": report.summary_rows(),
                   "sections": [{"key": s.key, "title": s.title,
                                 "rows": [{**r.cells, "status": r.status.value, "note": r.note} for r in s.rows]}
                                for s in report.sections]})
    else:
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
