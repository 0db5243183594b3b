"""``shimmy params``: Table 1 of the paper, with units and sources."""

from __future__ import annotations

import argparse

from reduced_model.parameters import YANG2024

from ..options import add_output_options, emit_json, interface_unit, parse_overrides


def add_parser(sub) -> None:
    p = sub.add_parser("params", help="print the parameter set (Table 1) with units and sources")
    p.add_argument("--set", action="append", metavar="NAME=VALUE", dest="overrides",
                   help="show the table with an entry overridden; repeatable")
    add_output_options(p)
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    params = YANG2024.replace(**parse_overrides(args.overrides))
    rows = []
    for row in params.table():
        unit, factor = interface_unit(row["name"])
        rows.append({**row, "value": row["value"] / factor, "unit": unit})
    if args.json:
        emit_json({"parameter_set": "YANG2024", "parameters": rows})
        return 0
    print("Parameter set YANG2024 (Yang, Knowles & Mavros, Table 1); values in the units shown")
    print(f"{'name':10s} {'value':>12s}  {'unit':10s} {'description':58s} source")
    for r in rows:
        note = f" [printed {r['printed_as']}]" if r["printed_as"] else ""
        print(f"{r['name']:10s} {r['value']:12.6g}  {r['unit']:10s} {r['description']:58s} {r['source']}{note}")
    return 0
