"""``shimmy figures``: the paper's figures recomputed by this project, as PNG files."""

from __future__ import annotations

import argparse
import os
import sys
import time

from axles.axle import interface_text
from axles.limits import UsageError
from comparisons.cli.options import add_model_choice, add_output_options, build_fidelity, emit_json
from comparisons.cli.progress import progress
from comparisons.files import watch_folder

DEFAULT_OUT = os.path.join("docs", "figures")
EXIT_INCOMPLETE = 3     # a curve or branch stopped before leaving its window (as ``shimmy curves``)
EXIT_UNAVAILABLE = 4    # a requested figure needs what the project cannot compute yet


def add_parser(sub) -> None:
    p = sub.add_parser("figures", help="recompute the paper's figures as PNG files")
    p.add_argument("--out", default=DEFAULT_OUT, metavar="DIR",
                   help=f"folder for figNN_<name>.png (default {DEFAULT_OUT}; created if missing)")
    p.add_argument("--only", metavar="N[,N...]", help="figure numbers of the paper (default: every available one)")
    p.add_argument("--jobs", type=int, default=min(2, os.cpu_count() or 1), metavar="N",
                   help="worker processes (default: up to 2)")
    add_model_choice(p)
    add_output_options(p)
    p.set_defaults(run=run)


def parse_only(text: str | None) -> list[int] | None:
    from comparisons.figures import PAPER_TITLES
    if text is None:
        return None
    numbers = []
    for item in text.split(","):
        item = item.strip()
        try:
            n = int(item)
        except ValueError:
            raise UsageError(f"--only expects figure numbers separated by commas, got '{item}'") from None
        if n not in PAPER_TITLES:
            raise UsageError(f"--only: the paper has no figure {n} (figures 1-{max(PAPER_TITLES)})")
        numbers.append(n)
    if not numbers:
        raise UsageError("--only needs at least one figure number")
    return sorted(set(numbers))


def check_out_dir(path: str) -> None:
    """Create the folder and prove it is writable before minutes of computing, with a one-line reason if not."""
    from comparisons.files import OutputPathError, prepare_folder
    try:
        prepare_folder(path, "--out")
    except OutputPathError as exc:
        raise UsageError(interface_text(exc)) from None


def run(args: argparse.Namespace) -> int:
    from comparisons.figures import PAPER_TITLES, available_figures, make_figures, unavailable_reason

    requested = parse_only(args.only)
    if args.jobs < 1:
        raise UsageError(f"--jobs must be at least 1, got {args.jobs}")
    # --model mbs: the paper's figures for the MBS at --fidelity (or --assume), each beside the reduced model's
    fidelity = build_fidelity(args)
    wanted = requested if requested is not None else list(available_figures(fidelity))
    makeable = [n for n in wanted if unavailable_reason(n, fidelity) is None]
    missing = [n for n in (requested if requested is not None else sorted(PAPER_TITLES))
               if unavailable_reason(n, fidelity) is not None]
    check_out_dir(args.out)
    watch_folder(args.out)
    start = time.perf_counter()
    quiet = args.json or not sys.stderr.isatty()
    with progress(len(makeable), "figures", quiet) as bar:
        results = make_figures(makeable, args.out, jobs=args.jobs, on_done=lambda r: bar.update(1),
                               fidelity=fidelity)
    elapsed = time.perf_counter() - start
    if args.json:
        emit_json({"out": args.out, "seconds": elapsed, "model": args.model,
                   "fidelity": None if fidelity is None else fidelity.label,
                   "figures": [{"number": r.number, "name": r.name, "title": PAPER_TITLES[r.number],
                                "path": r.path, "seconds": r.seconds, "complete": r.complete,
                                "notes": list(r.notes)} for r in results],
                   "unavailable": [{"number": n, "title": PAPER_TITLES[n],
                                    "reason": unavailable_reason(n, fidelity)} for n in missing]})
    else:
        print(f"made {len(results)} figure(s) in {args.out} ({elapsed:.1f} s)")
        for r in results:
            flag = "" if r.complete else "  INCOMPLETE (see --json notes)"
            print(f"  fig {r.number:2d}  {r.path}  ({r.seconds:.1f} s){flag}")
        if missing:
            print("not made:" if requested is not None else "not available yet:")
            for n in missing:
                print(f"  fig {n:2d}  {PAPER_TITLES[n]}: {unavailable_reason(n, fidelity)}")
    code = 0
    if not all(r.complete for r in results):
        numbers = ", ".join(str(r.number) for r in results if not r.complete)
        sys.stderr.write(f"shimmy: incomplete: figure(s) {numbers}: a curve or branch stopped before leaving its "
                         "window (drawn anyway; the notes in --json say where)\n")
        code = EXIT_INCOMPLETE
    if requested is not None and missing:
        sys.stderr.write(f"shimmy: figure(s) {', '.join(map(str, missing))} cannot be made yet: "
                         f"{'; '.join(sorted({unavailable_reason(n, fidelity) for n in missing}))}\n")
        code = EXIT_UNAVAILABLE
    return code
