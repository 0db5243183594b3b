"""``shimmy params``: the axle's entries (Table 1 and the multibody dimensions) with units, ranges and sources."""

from __future__ import annotations

import argparse
import os
import shlex

from axles.axle import entries
from axles.limits import UsageError
from comparisons.cli.options import add_axle_option, add_output_options, build_axle, check_output_path, emit_json


def add_parser(sub) -> None:
    p = sub.add_parser("params", help="print the axle (Table 1 and the multibody dimensions) with units, physical "
                                      "ranges and sources; --write makes an axle file to edit")
    add_axle_option(p)
    p.add_argument("--write", metavar="FILE.toml", help="write the axle as an axle file named after the file "
                                                        "(mytruck.toml: name = \"mytruck\"), start from the paper's "
                                                        "truck, edit it, read it back with --axle; prints what it "
                                                        "wrote instead of the table")
    add_output_options(p)
    p.set_defaults(run=run)


def rows_of(axle) -> list[dict]:
    rows = []
    for name, e in entries().items():
        lo, hi = e.range
        row = {"name": name, "section": e.section, "value": e.to_interface(axle.value(name)), "unit": e.unit,
               "range": [lo, hi], "description": e.description, "source": e.source}
        if e.section == "table1":
            row["printed_as"] = e.printed
        else:
            row["plausible"] = [e.to_interface(v) for v in axle.plausible_range(name)]
        rows.append(row)
    return rows


def run(args: argparse.Namespace) -> int:
    if args.write is not None:
        if not args.write.strip():
            raise UsageError("--write needs a file name")
        check_output_path(args.write)
    axle = build_axle(args)
    rows = rows_of(axle)
    written = None
    if args.write is not None:
        from axles.axle_file import format_axle
        from comparisons.files import write_atomically
        # The file is the user's own axle from now on: it is named after the file, not after the axle it started
        # from (the paper's YANG2024), so that reports and JSON name the axle the user edits.
        written = os.path.splitext(os.path.basename(args.write))[0] or axle.name
        try:
            write_atomically(args.write, format_axle(axle, name=written))
        except OSError as exc:
            raise UsageError(f"cannot write {args.write}: {exc.strerror or exc}") from None
    if args.json:
        emit_json({"parameter_set": axle.name, "axle": axle.describe(),
                   "pressure_range_bar": list(axle.pressure_range_bar), "parameters": rows,
                   **({"written": args.write, "written_name": written} if args.write else {})})
        return 0
    if args.write is not None:
        sections = [r["section"] for r in rows]
        print(f"wrote {args.write}: axle file name = \"{written}\", {len(rows)} entries ({sections.count('table1')} "
              f"of Table 1, {sections.count('multibody')} multibody dimensions with their plausible ranges) and the "
              f"pressure range {axle.pressure_range_bar[0]:g}-{axle.pressure_range_bar[1]:g} bar, from "
              f"{axle.label()}")
        print(f"edit it, then: shimmy verify --axle {shlex.quote(args.write)} --quick")
        return 0
    print(f"Axle {axle.shown_name}: {axle.label().split(': ', 1)[1]}; values in the units shown, "
          f"physical range in brackets")
    for section, title in (("table1", "Table 1 (Yang, Knowles & Mavros)"),
                           ("multibody", "multibody dimensions the paper does not give (plausible range after the "
                                         "physical one)")):
        print(f"\n{title}")
        print(f"{'name':26s} {'value':>11s}  {'unit':10s} {'range':22s} description; source")
        for r in rows:
            if r["section"] != section:
                continue
            rng = f"[{r['range'][0]:g}, {r['range'][1]:g}]"
            extra = f" plausible [{r['plausible'][0]:g}, {r['plausible'][1]:g}]" if "plausible" in r else ""
            note = f" [printed {r['printed_as']}]" if r.get("printed_as") else ""
            print(f"{r['name']:26s} {r['value']:11.6g}  {r['unit']:10s} {rng:22s} {r['description']}; "
                  f"{r['source']}{note}{extra}")
    print(f"\npressure range for 'shimmy verify --axle': {axle.pressure_range_bar[0]:g}-{axle.pressure_range_bar[1]:g}"
          f" bar")
    if axle.inherited:
        print(f"inherited from the paper's axle (base = YANG2024): {', '.join(axle.inherited)}")
    return 0
