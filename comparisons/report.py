"""The verification report: sections of tables whose rows carry a check status, written atomically as Markdown."""

from __future__ import annotations

import enum
import os
from dataclasses import dataclass, field

from .files import atomic_path


class CheckStatus(enum.Enum):
    PASS = "pass"
    FAIL = "FAIL"
    KNOWN_DIFFERENCE = "known difference"  # differs from the paper; listed with its reason in the README
    INFO = "info"                          # a measured number with nothing to check against


@dataclass(frozen=True)
class Row:
    cells: dict
    status: CheckStatus
    note: str = ""


@dataclass(frozen=True)
class Section:
    key: str
    title: str
    columns: tuple[str, ...]
    rows: tuple[Row, ...]
    text: str = ""                      # what is compared and the tolerances used
    figures: tuple[str, ...] = ()       # file names relative to the report folder
    recordings: tuple[str, ...] = ()

    def count(self, status: CheckStatus) -> int:
        return sum(r.status is status for r in self.rows)

    @property
    def failed(self) -> bool:
        return self.count(CheckStatus.FAIL) > 0


@dataclass(frozen=True)
class Report:
    sections: tuple[Section, ...]
    quick: bool
    notes: tuple[str, ...] = field(default=())
    plan: object = None          # comparisons.verify_plan.Plan
    axle: object = None          # comparisons.axle.Axle

    @property
    def failed(self) -> bool:
        return any(s.failed for s in self.sections)

    def summary_rows(self) -> list[dict]:
        return [{"section": s.title, "checks": len(s.rows), "pass": s.count(CheckStatus.PASS),
                 "known differences": s.count(CheckStatus.KNOWN_DIFFERENCE), "fail": s.count(CheckStatus.FAIL),
                 "info": s.count(CheckStatus.INFO)} for s in self.sections]


def _cell(value) -> str:
    if value is None:
        return "-"
    if isinstance(value, float):
        return f"{value:.4g}" if abs(value) >= 1e4 or (value != 0 and abs(value) < 1e-3) else f"{value:.4f}".rstrip(
            "0").rstrip(".")
    return str(value)


def markdown_table(columns, rows: list[dict]) -> str:
    lines = ["| " + " | ".join(columns) + " |", "|" + "---|" * len(columns)]
    for r in rows:
        lines.append("| " + " | ".join(_cell(r.get(c)) for c in columns) + " |")
    return "\n".join(lines)


def render_markdown(report: Report) -> str:
    out = ["# shimmy verification report", ""]
    if report.axle is not None:
        out += [f"Axle: {report.axle.label()}" + (f" (sha256 {report.axle.sha256[:12]})" if report.axle.sha256
                                                  else "") + ".", ""]
        if report.axle.inherited:
            out += [f"Inherited from the paper's axle: {', '.join(report.axle.inherited)}.", ""]
    out += [f"Mode: {'quick' if report.quick else 'full'}. Overall: "
            f"{'FAILED' if report.failed else 'all equivalence checks passed'}.", "",
           "## Summary", "",
           markdown_table(["section", "checks", "pass", "known differences", "fail", "info"], report.summary_rows()),
           ""]
    for note in report.notes:
        out += [f"> {note}", ""]
    for s in report.sections:
        out += [f"## {s.title}", ""]
        if s.text:
            out += [s.text, ""]
        rows = [{**r.cells, "status": r.status.value, "note": r.note} for r in s.rows]
        out += [markdown_table(list(s.columns) + ["status", "note"], rows), ""]
        out += [f"![{f}]({f})" for f in s.figures]
        out += [f"Recording: [`{r}`]({r}) (open with `rerun {r}`)" for r in s.recordings]
        out.append("")
    return "\n".join(out)


def write_atomically(path: str, text: str) -> None:
    """Write ``text`` to ``path`` through a temporary file: never a truncated file at ``path``."""
    with atomic_path(path) as tmp:
        with open(tmp, "w", encoding="utf-8") as fh:
            fh.write(text)
            fh.flush()
            os.fsync(fh.fileno())
