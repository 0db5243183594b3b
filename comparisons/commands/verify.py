"""``shimmy verify``: the project's main job (grows with each part: reduced model, cycles, multibody model)."""

from __future__ import annotations

import argparse

from ..options import add_output_options, emit_json
from ..verification import hopf_table


def add_parser(sub) -> None:
    p = sub.add_parser("verify", help="compare the models with the paper and with each other")
    add_output_options(p)
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    rows = hopf_table()
    if args.json:
        emit_json({"hopf_table": rows})
        return 0
    print("Hopf speeds of the section 3 model (reduced model) beside the paper's, km/h")
    print(f"{'pressure':>9s} {'point':>5s} {'paper':>9s} {'computed':>11s} {'diff':>8s} {'freq Hz':>8s}  "
          f"{'criticality':13s} agreement")
    for r in rows:
        paper = "-" if r["paper_kmh"] is None else f"{r['paper_kmh']:.2f}"
        comp = "-" if r["computed_kmh"] is None else f"{r['computed_kmh']:.4f}"
        diff = "-" if r["difference_kmh"] is None else f"{r['difference_kmh']:+.3f}"
        freq = "-" if r["frequency_hz"] is None else f"{r['frequency_hz']:.3f}"
        print(f"{r['pressure_bar']:7.2f} bar {r['point']:>5s} {paper:>9s} {comp:>11s} {diff:>8s} {freq:>8s}  "
              f"{r['criticality'] or '-':13s} {r['agreement']}")
    return 0
