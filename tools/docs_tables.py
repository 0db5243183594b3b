"""The docs' tables that the code already knows, generated from its registries so that they cannot drift.

A generated table sits in a markdown file between ``<!-- generated: NAME -->`` and ``<!-- end generated -->``;
NAME is a key of :data:`TABLES`.  Usage (from the repository root)::

    .venv/bin/python tools/docs_tables.py --write    # rewrite every marked block from the code
    .venv/bin/python tools/docs_tables.py --check    # exit 1 and name each block that differs from the code
    .venv/bin/python tools/docs_tables.py --show NAME

``tests/docs/test_docs_tables.py`` runs the check.
"""

from __future__ import annotations

import argparse
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
# The markdown files that may hold generated blocks: the README and everything under docs/.
DOC_GLOBS = ("README.md", "docs/**/*.md", "mbs_shimmy/README.md")
BLOCK = re.compile(r"(<!-- generated: (?P<name>[\w-]+) -->\n)(?P<body>.*?)(<!-- end generated -->)", re.S)


def _table(header: tuple[str, ...], rows: list[tuple[str, ...]]) -> str:
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(cell.replace("|", "\\|") for cell in row) + " |" for row in rows]
    return "\n".join(lines) + "\n"


def _range(lo: float, hi: float) -> str:
    # The same number format as 'shimmy params' prints ranges in.
    return f"[{lo:g}, {hi:g}]"


def axle_entries() -> str:
    """Every axle entry as ``shimmy params --json`` reports it for the paper's axle."""
    from axles.axle import paper_axle
    from comparisons.cli.commands.params import rows_of
    rows = []
    for r in rows_of(paper_axle()):
        plausible = _range(*r["plausible"]) if "plausible" in r else ""
        rows.append((f"`{r['name']}`", r["section"], f"{r['value']:.6g}", r["unit"], _range(*r["range"]), plausible,
                     r["description"]))
    return _table(("name", "section", "paper's axle", "unit", "physical range", "plausible range", "what"), rows)


def tyre_file_keys() -> str:
    """The one table from a .tir file's keys to the axle's tyre entries (:data:`axles.tyre_mapping.TYRE_KEYS`)."""
    from axles.axle import entries
    from axles.tyre_mapping import MISSING_MEANING, TYRE_KEYS
    rows = []
    for k in TYRE_KEYS:
        e = entries()[k.entry]
        how = ("- " if k.sign < 0 else "") + (" x ".join((k.key,) + k.scales))
        rows.append((f"[{k.section}] {k.key}", f"`{k.entry}`", k.symbol, e.si_unit, how, MISSING_MEANING[k.missing],
                     k.enters, k.note))
    return _table(("file section, key", "axle entry", "paper's symbol", "unit (SI)", "entry =", "when the file has none",
                   "used by", "decision"), rows)


def input_ranges() -> str:
    """The command-line inputs that are not axle entries, from :mod:`axles.limits`."""
    from axles.limits import (
        ANGLE_RANGE_DEG,
        BRAKE_FORCE_RANGE_N,
        BRAKE_SLIP_RANGE,
        DURATION_RANGE_S,
        MAX_CYCLES,
        MBS_MAX_DURATION,
        PRESSURE_RANGE_BAR,
        RAMP_TIME_RANGE_S,
        RATE_RANGE_DEG_S,
        SPEED_RANGE_KMH,
    )
    p_lo, p_hi = PRESSURE_RANGE_BAR
    v_lo, v_hi = SPEED_RANGE_KMH
    rows = [
        ("`--pressure`, `--pressure-left`, `--pressure-right`", f"{p_lo:g}-{p_hi:g} bar"),
        ("`--speed`, `--ramp FROM:TO`", f"{v_lo:g}-{v_hi:g} km/h"),
        ("`--vmax`", f"above {v_lo:g}, at most {v_hi:g} km/h (a window must reach above {v_lo:g} km/h, where the "
                     f"slip model holds)"),
        ("`--vmin`", f"0-{v_hi:g} km/h, below `--vmax` (`cycles`: equal to it asks for the orbits at that one speed)"),
        ("`--duration`, `--ramp` SECONDS",
         f"{DURATION_RANGE_S[0]:g}-{DURATION_RANGE_S[1]:g} s, ramp {RAMP_TIME_RANGE_S[0]:g}-{RAMP_TIME_RANGE_S[1]:g} s "
         f"(`--model mbs`: at most {MBS_MAX_DURATION:g} s of duration)"),
        ("`--initial` angles / rates", f"{ANGLE_RANGE_DEG[0]:g} to {ANGLE_RANGE_DEG[1]:g} deg / "
                                       f"{RATE_RANGE_DEG_S[0]:g} to {RATE_RANGE_DEG_S[1]:g} deg/s"),
        ("`--brake-slip SLIP[,SLIP]`", f"{BRAKE_SLIP_RANGE[0]:g}-{BRAKE_SLIP_RANGE[1]:g} per wheel (0 free rolling, "
                                       f"1 locked, negative driving: ISO kappa = -slip)"),
        ("`--brake-force N[,N]`", f"{BRAKE_FORCE_RANGE_N[0]:g}-{BRAKE_FORCE_RANGE_N[1]:g} N per wheel (rearward; "
                                  f"negative driving), and below the tyre's peak brake (or drive) force at its "
                                  f"pressure"),
        ("`--range LO HI`", f"inside the physical range of the parameter (pressures {p_lo:g}-{p_hi:g} bar, brake slip "
                            f"{BRAKE_SLIP_RANGE[0]:g}-{BRAKE_SLIP_RANGE[1]:g}), LO < HI"),
        ("`simulate` work", f"the fastest oscillation of the axle times the duration must stay below {MAX_CYCLES:g} "
                            f"periods (a stiff tie rod on a light wheel oscillates at kHz; the integrators must "
                            f"resolve every period)"),
    ]
    return _table(("input", "range"), rows)


def exit_codes() -> str:
    from comparisons.cli.main import EXIT_CODES
    return _table(("code", "meaning"), [(str(code), meaning) for code, meaning in EXIT_CODES.items()])


def assumption_switches() -> str:
    """The switches of the multibody model: the reduced model's assumptions, then the full axle's elements."""
    from mbs_shimmy.fidelity import ASSUMPTIONS
    rows = [(f"`{a.name}`", "element of the full axle" if a.element else "assumption of the paper", a.summary,
             a.enters, a.full_geometry) for a in ASSUMPTIONS]
    return _table(("switch", "kind", "assumption", "where it enters (2.1)-(2.11)", "full geometry instead"), rows)


TABLES = {"axle-entries": axle_entries, "input-ranges": input_ranges, "exit-codes": exit_codes,
          "assumption-switches": assumption_switches, "tyre-file-keys": tyre_file_keys}


def doc_files(root: Path = ROOT) -> list[Path]:
    found: set[Path] = set()
    for pattern in DOC_GLOBS:
        found.update(root.glob(pattern))
    return sorted(found)


def render(text: str, where: str, cache: dict[str, str]) -> str:
    """``text`` with every marked block replaced by its table; an unknown NAME is an error, not a silent skip."""
    def replace(m: re.Match) -> str:
        name = m.group("name")
        if name not in TABLES:
            raise SystemExit(f"{where}: unknown generated table '{name}' (known: {', '.join(TABLES)})")
        if name not in cache:
            cache[name] = TABLES[name]()
        return m.group(1) + cache[name] + m.group(4)
    return BLOCK.sub(replace, text)


def drifted(root: Path = ROOT, write: bool = False) -> list[str]:
    """``file: table`` for every block that differs from the code (rewritten when ``write``)."""
    cache: dict[str, str] = {}
    out = []
    for path in doc_files(root):
        text = path.read_text(encoding="utf-8")
        where = str(path.relative_to(root))
        new = render(text, where, cache)
        if new != text:
            old_blocks = {m.start(): m.group("body") for m in BLOCK.finditer(text)}
            new_blocks = list(BLOCK.finditer(new))
            for (_, body), m in zip(sorted(old_blocks.items()), new_blocks):
                if body != m.group("body"):
                    out.append(f"{where}: {m.group('name')}")
            if write:
                path.write_text(new, encoding="utf-8")
    return out


def used_tables(root: Path = ROOT) -> set[str]:
    return {m.group("name") for path in doc_files(root) for m in BLOCK.finditer(path.read_text(encoding="utf-8"))}


def main(argv: list[str] | None = None) -> int:
    sys.path.insert(0, str(ROOT))
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    how = ap.add_mutually_exclusive_group(required=True)
    how.add_argument("--write", action="store_true", help="rewrite the marked blocks from the code")
    how.add_argument("--check", action="store_true", help="exit 1 if a marked block differs from the code")
    how.add_argument("--show", metavar="NAME", choices=sorted(TABLES), help="print one table")
    args = ap.parse_args(argv)
    if args.show:
        print(TABLES[args.show](), end="")
        return 0
    changed = drifted(write=args.write)
    missing = sorted(set(TABLES) - used_tables())
    for name in missing:
        print(f"docs_tables: table '{name}' is not placed in any doc", file=sys.stderr)
    for item in changed:
        print(f"docs_tables: {'rewrote' if args.write else 'drifted'}: {item}", file=sys.stderr)
    if args.check:
        return 1 if changed or missing else 0
    return 1 if missing else 0


if __name__ == "__main__":
    sys.exit(main())
