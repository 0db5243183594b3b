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
    p.add_argument("--write-tir", metavar="FILE.tir", help="write the axle's tyre as a Magic Formula 6.1 property file "
                                                           "(read it back with --tyre)")
    add_output_options(p)
    p.set_defaults(run=run)


def tyre_report(axle) -> dict | None:
    """What the axle's tyre file gave and did not give (None without one), for the text and JSON output: the
    keys neither model uses, the entries the file lacks, and the extended model's trail and relaxation length at
    the nominal pressure beside the section 3 model's constants t0 and sigma0."""
    if axle.tyre_file is None:
        return None
    from axles.tyre_file import read_tir
    from reduced_model.tyre import pneumatic_trail, relaxation_length
    tyre = read_tir(axle.tyre_file)
    p = axle.params
    return {"file": axle.tyre_file, "fittyp": tyre.fittyp, "unused": list(tyre.unused),
            "absent_zero": list(tyre.zeros), "absent_kept_from_axle": list(tyre.kept),
            "absent_sections": list(tyre.absent_sections),
            "nominal_trail_m": float(pneumatic_trail(p, 0.0, p.pi0)),
            "nominal_relaxation_length_m": relaxation_length(p, p.pi0)}


def print_tyre(report: dict, axle) -> None:
    print(f"\ntyre: {report['file']} (FITTYP {report['fittyp']}); the entries above come from it as "
          f"docs/axle-files.md's table says")
    if report["absent_zero"]:
        print(f"  not in the file, 0 (the term is absent, as in MF 6.1): {', '.join(report['absent_zero'])}")
    if report["absent_kept_from_axle"]:
        print(f"  not in the file, kept from the axle: {', '.join(report['absent_kept_from_axle'])}")
    if report["absent_sections"]:
        print(f"  sections not in the file: {', '.join(report['absent_sections'])}")
    print(f"  at the nominal pressure the extended model has trail {report['nominal_trail_m']:.6g} m (t0 = "
          f"{axle.params.t0:g} m) and relaxation length {report['nominal_relaxation_length_m']:.6g} m (sigma0 = "
          f"{axle.params.sigma0:g} m)")
    if report["unused"]:
        grouped: dict[str, list[str]] = {}
        for item in report["unused"]:
            section, _, key = item.partition(" ")
            grouped.setdefault(section, []).append(key)
        print(f"  in the file, not used by either model ({len(report['unused'])}):")
        for section, keys in grouped.items():
            print(f"    {section} {', '.join(keys)}")


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
    for given, flag in ((args.write, "--write"), (args.write_tir, "--write-tir")):
        if given is not None:
            if not given.strip():
                raise UsageError(f"{flag} needs a file name")
            check_output_path(given)
    axle = build_axle(args)
    rows = rows_of(axle)
    written = None
    tyre = tyre_report(axle)
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
    if args.write_tir is not None:
        from axles.tyre_file import format_tir
        from comparisons.files import write_atomically
        try:
            write_atomically(args.write_tir, format_tir(axle))
        except OSError as exc:
            raise UsageError(f"cannot write {args.write_tir}: {exc.strerror or exc}") from None
    if args.json:
        emit_json({"parameter_set": axle.name, "axle": axle.describe(),
                   "pressure_range_bar": list(axle.pressure_range_bar), "parameters": rows,
                   **({"tyre": tyre} if tyre else {}),
                   **({"written": args.write, "written_name": written} if args.write else {}),
                   **({"written_tir": args.write_tir} if args.write_tir else {})})
        return 0
    if args.write is not None:
        sections = [r["section"] for r in rows]
        print(f"wrote {args.write}: axle file name = \"{written}\", {len(rows)} entries ({sections.count('table1')} "
              f"of Table 1, {sections.count('multibody')} multibody dimensions with their plausible ranges) and the "
              f"pressure range {axle.pressure_range_bar[0]:g}-{axle.pressure_range_bar[1]:g} bar, from "
              f"{axle.label()}")
        print(f"edit it, then: shimmy verify --axle {shlex.quote(args.write)} --quick")
        if tyre:
            print_tyre(tyre, axle)
        if args.write_tir:
            print(f"tyre property file written to {args.write_tir}")
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
    if tyre:
        print_tyre(tyre, axle)
    if args.write_tir:
        print(f"tyre property file written to {args.write_tir}")
    return 0
