"""``shimmy bench``: performance benchmarks, medians and ratios to an in-process baseline."""

from __future__ import annotations

import argparse

from axles.limits import UsageError
from comparisons.cli.benchmarks import BENCHMARKS, run_benchmarks
from comparisons.cli.options import add_output_options, emit_json
from comparisons.cli.progress import progress


def add_parser(sub) -> None:
    p = sub.add_parser("bench", help="run the performance benchmarks")
    p.add_argument("names", nargs="*", metavar="NAME", help="benchmarks to run (default: all)")
    add_output_options(p)
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    known = [b.name for b in BENCHMARKS]
    for name in args.names:
        if name not in known:
            raise UsageError(f"unknown benchmark '{name}' (known: {', '.join(known)})")
    count = len(args.names) or len(known)
    with progress(count, "benchmarks", args.json) as bar:
        results = run_benchmarks(args.names, progress=lambda done, total: bar.update(1))
    if args.json:
        emit_json({"baseline_s": results[0].baseline_s if results else None,
                   "benchmarks": [{"name": r.name, "description": r.description, "median_s": r.median_s,
                                   "runs_s": list(r.runs), "ratio_to_baseline": r.ratio, "target_s": r.target_s,
                                   "target_ratio": r.target_ratio, "meets_target": r.meets_target,
                                   "counts": r.counts} for r in results]})
        return 0
    if results:
        print(f"baseline (1000 x eig of 8x8): {results[0].baseline_s * 1e3:.2f} ms")
    for r in results:
        target = "" if r.target_s is None else (f"  target {r.target_s * 1e3:g} ms: "
                                                f"{'met' if r.meets_time_target else 'MISSED'}")
        if r.target_ratio is not None:
            target += f"  target ratio {r.target_ratio:g}: {'met' if r.meets_ratio_target else 'MISSED'}"
        print(f"{r.name:24s} median {r.median_s * 1e3:9.2f} ms over {len(r.runs)} runs "
              f"({r.ratio:7.2f} x baseline){target}   {r.description}")
        if r.counts:
            print(" " * 26 + ", ".join(f"{k.replace('_', ' ')} {_count_text(v)}" for k, v in r.counts.items()))
    return 0


def _count_text(value) -> str:
    """Counts as integers with thousands separators; small measured values (us per stage) to 0.1; a text (which
    derivatives a run used) as it is."""
    if isinstance(value, str):
        return value
    if isinstance(value, float) and abs(value) < 0.1 and value != 0.0:
        return f"{value:.2g}"      # a residual (2.8e-09) is no zero
    if isinstance(value, float) and abs(value) < 100 and value != int(value):
        return f"{value:.1f}"
    return f"{value:,.0f}"
