"""How a verification report is written: cells with the digits their values warrant, the Markdown file
(``report.md``) and one self-contained HTML file (``report.html``: tables and figures embedded, nothing fetched),
both written atomically.  The report's content is :mod:`comparisons.verify.report`."""

from __future__ import annotations

import base64
import html
import os

from comparisons.files import write_atomically
from comparisons.verify.report import (
    STATUS_TEXT,
    SUMMARY_COLUMNS,
    Report,
    Section,
    is_missing,
    rerun_command,
)

# --- cells -----------------------------------------------------------------------------------------------------

def _cell(value, factor: float = 1.0) -> str:
    if is_missing(value):
        return "-"
    if isinstance(value, float):
        value = value * factor
        if value == 0.0:
            return "0"
        if abs(value) >= 1e4 or abs(value) < 1.0:
            # four significant digits: a relative difference of 1.234e-3 keeps them all (fixed decimals kept two)
            return f"{value:.4g}"
        return f"{value:.4f}".rstrip("0").rstrip(".")
    return str(value)


def markdown_table(columns, rows: list[dict], headers=None, factors=None) -> str:
    headers = list(headers or columns)
    factors = factors or {}
    lines = ["| " + " | ".join(h.replace("|", "\\|") for h in headers) + " |", "|" + "---|" * len(columns)]
    for r in rows:
        lines.append("| " + " | ".join(_cell(r.get(c), factors.get(c, 1.0)).replace("|", "\\|") for c in columns)
                     + " |")
    return "\n".join(lines)


def section_table(s: Section, with_note: bool = True) -> tuple[list[str], list[str], list[dict], dict]:
    """(column keys, headers in words, rows with status and note, factors) of a section."""
    keys = list(s.columns) + ["status"] + (["note"] if with_note else [])
    headers = [s.column(k).label for k in keys]
    rows = [{**r.cells, "status": r.status.value, "note": r.note} for r in s.rows]
    return keys, headers, rows, {k: s.column(k).factor for k in keys}


def _legend(report: Report) -> list[str]:
    used = {r.status for s in report.sections for r in s.rows}
    return [f"`{status.value}`: {text}" for status, text in STATUS_TEXT.items() if status in used]


# --- Markdown --------------------------------------------------------------------------------------------------

def _axle_lines(report: Report) -> list[str]:
    if report.axle is None:
        return []
    axle = report.axle
    out = [f"Axle: {axle.label()}" + (f" (sha256 {axle.sha256[:12]})" if axle.sha256 else "") + "."]
    if axle.inherited:
        out.append(f"Inherited from the paper's axle: {', '.join(axle.inherited)}.")
    return out


def _verdict_lines(report: Report) -> list[str]:
    return [] if report.verdict is None else report.verdict.lines()


VERDICT_TEXT = ("From the plan's scan of the pressure window with both models (the reduced model and the MBS with "
                "the full geometry) and both models' unstable speed windows at every planned case.")


def render_markdown(report: Report) -> str:
    out = ["# shimmy verification report", ""]
    for line in _axle_lines(report):
        out += [line, ""]
    lines = _verdict_lines(report)
    if lines:
        out += ["## Verdict", "", f"**{lines[0]}**", ""] + [f"- {x}" for x in lines[1:]] + ["", VERDICT_TEXT, ""]
    out += [f"Mode: {'quick' if report.quick else 'full'}. Overall: {report.overall()}.", ""]
    if report.metadata is not None:
        out += ["## Run", "", markdown_table(["what", "value"], [{"what": a, "value": b}
                                                                   for a, b in report.metadata.rows()]), ""]
    out += ["## Summary", "", markdown_table(SUMMARY_COLUMNS, report.summary_rows()), ""]
    out += ["Check column: " + "; ".join(_legend(report)) + ".", ""]
    for note in report.notes:
        out += [f"> {note}", ""]
    for s in report.sections:
        out += [f"## {s.title}", ""]
        if s.text:
            out += [s.text, ""]
        keys, headers, rows, factors = section_table(s)
        out += [markdown_table(keys, rows, headers, factors), ""]
        dashes = s.dashes()
        if dashes:
            out += ["A \"-\" in the table: " + "; ".join(f"*{h}*: {m}" for h, m in dashes) + ".", ""]
        out += [f"![{f}]({f})" for f in s.figures]
        if s.figures:
            out.append("")
        out += [f"Recording: [`{r}`]({r}) (open from this folder with `{rerun_command(r)}`)" for r in s.recordings]
        out.append("")
    return "\n".join(out)


# --- HTML ------------------------------------------------------------------------------------------------------

_CSS = """
body { font-family: system-ui, sans-serif; margin: 2em auto; max-width: 1200px; color: #222; padding: 0 1em; }
p, li, figcaption, blockquote { overflow-wrap: anywhere; }
.scroll { overflow-x: auto; max-width: 100%; margin: 0.8em 0; }
table { border-collapse: collapse; font-size: 0.88em; }
th.text, td.text { min-width: 14em; } th.note, td.note { min-width: 22em; }
th, td { border: 1px solid #ccc; padding: 0.25em 0.5em; vertical-align: top; }
th { background: #f2f2f2; text-align: left; }
td.num { text-align: right; font-variant-numeric: tabular-nums; }
td.pass { background: #e5f5e0; } td.FAIL { background: #fcbba1; font-weight: bold; }
td.known { background: #fff3cd; } td.info { background: #eef3fb; } td.nothing { background: #eeeeee; }
figure { margin: 1em 0; } figure img { max-width: 100%; border: 1px solid #ddd; }
.dash { font-size: 0.88em; color: #444; } code { background: #f4f4f4; padding: 0 0.2em; }
.overall-pass { color: #1a7f37; } .overall-fail { color: #b00020; }
"""


# Columns of sentences: a minimum width keeps them readable in a wide table (one word per line made a row about
# 12 lines tall); the table scrolls inside its own box instead of running off the page.
TEXT_COLUMNS = frozenset({"reason", "what", "kind", "quantity", "hopf_shifts_kmh", "error", "point", "braking",
                          "steady_state_deg"})


def _width_class(key: str) -> str:
    return "note" if key == "note" else "text" if key in TEXT_COLUMNS else ""


def _html_table(keys, headers, rows, factors, status_key: str | None = "status") -> str:
    head = "".join(f'<th class="{_width_class(k)}">{html.escape(h)}</th>' if _width_class(k)
                   else f"<th>{html.escape(h)}</th>" for k, h in zip(keys, headers))
    body = []
    for r in rows:
        cells = []
        for k in keys:
            v = r.get(k)
            text = html.escape(_cell(v, factors.get(k, 1.0)))
            cls = "num" if isinstance(v, (int, float)) and not isinstance(v, bool) else ""
            if k == status_key:
                cls = {"known difference": "known", "could not check": "nothing"}.get(str(v), str(v))
            elif _width_class(k) and not cls:
                cls = _width_class(k)
            cells.append(f'<td class="{cls}">{text}</td>' if cls else f"<td>{text}</td>")
        body.append("<tr>" + "".join(cells) + "</tr>")
    return f'<div class="scroll"><table><thead><tr>{head}</tr></thead><tbody>{"".join(body)}</tbody></table></div>'


def _embedded_png(folder: str, name: str) -> str:
    with open(os.path.join(folder, name), "rb") as fh:
        return "data:image/png;base64," + base64.b64encode(fh.read()).decode("ascii")


def _inline_code(text: str) -> str:
    """Escape, then show `code` spans as <code> (the section texts use Markdown backticks)."""
    parts = html.escape(text).split("`")
    return "".join(f"<code>{p}</code>" if i % 2 else p for i, p in enumerate(parts))


def render_html(report: Report, folder: str) -> str:
    """One self-contained page: figures are read from ``folder`` and embedded as data URIs."""
    overall = report.overall()
    out = ["<!DOCTYPE html>", '<html lang="en"><head><meta charset="utf-8">',
           "<title>shimmy verification report</title>", f"<style>{_CSS}</style></head><body>",
           "<h1>shimmy verification report</h1>", *(f"<p>{html.escape(x)}</p>" for x in _axle_lines(report))]
    lines = _verdict_lines(report)
    if lines:
        out += ['<h2 id="verdict">Verdict</h2>', f"<p><strong>{html.escape(lines[0])}</strong></p>",
                "<ul>" + "".join(f"<li>{html.escape(x)}</li>" for x in lines[1:]) + "</ul>",
                f"<p>{html.escape(VERDICT_TEXT)}</p>"]
    out += [f"<p>Mode: {'quick' if report.quick else 'full'}. Overall: <strong class="
           f"\"{'overall-fail' if report.failed else 'overall-pass'}\">{overall}</strong>.</p>"]
    if report.metadata is not None:
        rows = [{"what": a, "value": b} for a, b in report.metadata.rows()]
        out += ['<h2 id="run">Run</h2>', _html_table(["what", "value"], ["what", "value"], rows, {}, None)]
    out += ['<h2 id="summary">Summary</h2>',
            _html_table(list(SUMMARY_COLUMNS), list(SUMMARY_COLUMNS), report.summary_rows(), {}, None),
            "<p>Check column: " + "; ".join(_inline_code(x) for x in _legend(report)) + ".</p>"]
    for note in report.notes:
        out.append(f"<blockquote>{_inline_code(note)}</blockquote>")
    for s in report.sections:
        out.append(f'<h2 id="{html.escape(s.key)}">{html.escape(s.title)}</h2>')
        if s.text:
            out.append(f"<p>{_inline_code(s.text)}</p>")
        out.append(_html_table(*section_table(s)))
        dashes = s.dashes()
        if dashes:
            out.append('<p class="dash">A "-" in the table: ' + "; ".join(
                f"<em>{html.escape(h)}</em>: {html.escape(m)}" for h, m in dashes) + ".</p>")
        for f in s.figures:
            out.append(f'<figure><img alt="{html.escape(f)}" src="{_embedded_png(folder, f)}">'
                       f"<figcaption>{html.escape(f)}</figcaption></figure>")
        for r in s.recordings:
            out.append(f"<p>Recording: <code>{html.escape(r)}</code> (beside this report; open from its folder with "
                       f"<code>{html.escape(rerun_command(r))}</code>)</p>")
    out.append("</body></html>")
    return "\n".join(out)




def write_report(report: Report, folder: str) -> tuple[str, str]:
    """Write ``report.md`` and ``report.html`` into ``folder`` (atomically); returns their paths."""
    md, page = os.path.join(folder, "report.md"), os.path.join(folder, "report.html")
    write_atomically(md, render_markdown(report))
    write_atomically(page, render_html(report, folder))
    return md, page
