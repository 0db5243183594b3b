"""The verification report: sections of tables whose rows carry a check status, with run metadata, column headers
in words and units, every "-" explained, and figures; written atomically as Markdown (``report.md``) and as one
self-contained HTML file (``report.html``: tables and figures embedded, nothing fetched).

Rows keep the code names of their columns (the JSON of ``verify --json`` uses them); the rendered tables show
:data:`COLUMN_LABELS` (or a section's own ``labels``) instead.
"""

from __future__ import annotations

import base64
import datetime
import enum
import hashlib
import html
import os
import platform
import shlex
import subprocess
import sys
from dataclasses import dataclass, field

from comparisons.files import write_atomically


def rerun_command(recording: str) -> str:
    """The command that opens a recording, with the viewer of the environment shimmy runs in: it works in a shell
    where that environment is not activated."""
    viewer = os.path.join(os.path.dirname(sys.executable), "rerun")
    return f"{shlex.quote(viewer)} {shlex.quote(recording)}"


class CheckStatus(enum.Enum):
    """The one status of every check row (docs/verify.md, "The one rule").

    FAIL only where two models (or a model and the paper's printed value) differ beyond a stated tolerance in a
    well-posed quantity, or where a computation fails; what a model is *expected* to do is INFO; a case that
    could not be checked is COULD_NOT_CHECK with its reason, never counted as passed and never a non-zero exit."""

    PASS = "pass"
    FAIL = "FAIL"
    KNOWN_DIFFERENCE = "known difference"  # differs from the paper; listed with its reason in docs/results.md
    INFO = "info"                          # a measured number, or what a model is expected to do: not a check
    COULD_NOT_CHECK = "could not check"    # nothing to start from, nothing to compare (the note says why): no pass


@dataclass(frozen=True)
class Column:
    """How a column is shown: a header in words with its unit, and a factor from the stored value."""

    label: str
    factor: float = 1.0
    dash: str = ""          # what "-" means in this column ("" : the column does not apply to that row)


COLUMN_LABELS: dict[str, Column] = {
    "model": Column("model (tyre properties following pressure)"),
    "case": Column("case (tyre pressures)"),
    "pressure_bar": Column("tyre pressure [bar]"),
    "pressure_right_bar": Column("right tyre, wheel 1 [bar]"),
    "pressure_left_bar": Column("left tyre, wheel 2 [bar]"),
    "kind": Column("kind of case"),
    "reason": Column("why this case"),
    "quantity": Column("quantity"),
    "paper": Column("paper (printed)"),
    "computed": Column("computed", dash="not found"),
    "point": Column("what (Hopf point HB1.. by speed, eigenvalues, cycle fold, torus point, stable cycle)"),
    "paper_kmh": Column("paper [km/h]", dash="the paper prints no value for it"),
    "reduced_kmh": Column("reduced model [km/h]", dash="the reduced model has no such point or jump"),
    "mbs_reduced_kmh": Column("MBS with the reduced model's assumptions [km/h]",
                              dash="the MBS has no matching point, or did not jump"),
    "mbs_full_kmh": Column("MBS, full geometry [km/h]",
                           dash="the full geometry has no Hopf point matching this one (the mode vanished)"),
    "full_shift_kmh": Column("full geometry minus reduced model [km/h]",
                             dash="no full-geometry partner, so no shift"),
    "frequency_hz": Column("frequency at the Hopf point [Hz]"),
    "criticality": Column("criticality (supercritical: small stable cycles)", dash="not determined"),
    "branch": Column("limit-cycle branch"),
    "speed_kmh": Column("speed [km/h]"),
    "continuation_theta1_deg": Column("continuation: max |theta1| [deg]"),
    "mbs_reduced_theta1_deg": Column("MBS with the reduced model's assumptions: max |theta1| [deg]",
                                     dash="the MBS run did not settle (no finite amplitude)"),
    "relative_diff": Column("relative difference, MBS against the reduced model [relative, not %]",
                            dash="not compared in that row (Hopf table: only the eigenvalue rows hold it), or no "
                                 "finite MBS amplitude to compare"),
    "mbs_full_theta1_deg": Column("MBS, full geometry: max |theta1| [deg]",
                                  dash="the full-geometry run did not settle (no finite amplitude)"),
    "run": Column("run"),
    "continuation_kmh": Column("continuation point [km/h]"),
    "model_diff_kmh": Column("MBS minus reduced model [km/h]", dash="a model did not jump"),
    "final_L1": Column("final mode from start L1"),
    "final_L2": Column("final mode from start L2"),
    "final_1": Column("final mode from the first start"),
    "final_2": Column("final mode from the second start"),
    "assumption_off": Column("assumption switched off in the MBS"),
    "hopf_shifts_kmh": Column("Hopf speed shifts per Hopf point, the row's MBS side minus its reference side "
                              "[km/h]",
                              dash="'-' in the list: that Hopf point has no partner on the MBS side; '-' alone: "
                                   "neither side of the row has a Hopf point, so there is nothing to shift"),
    "peak_theta1_shift_deg": Column("shift of the peak max |theta1| (continued cycles) [deg]",
                                    dash="not computed in verify (shimmy assumptions continues them), or a cycle branch that did not complete"),
    "reduced_value": Column("reduced model (does not depend on the multibody dimensions)"),
    "plausible_axles": Column("over the plausible axles (median, 5-95 % range or share)"),
    "samples": Column("plausible axles sampled"),
    "soft_count": Column("axles whose full geometry sets in softly (lowest Hopf point supercritical)"),
    "hard_count": Column("axles whose full geometry jumps in (lowest Hopf point subcritical)"),
    "none_count": Column("axles whose full geometry has no Hopf point"),
    "undetermined_count": Column("axles whose onset l1 could not be decided"),
    "soft_share": Column("share of the axles that set in softly"),
    "hard_share": Column("share of the axles that jump in"),
    "reduced_onset": Column("reduced model's onset (soft, hard or none)"),
    "reduced_onset_l1": Column("reduced model's l1 at its lowest Hopf point", dash="no Hopf point"),
    "what": Column("what (full geometry: Hopf point, branch, orbit, special point, bistable window, kick)"),
    "first_lyapunov": Column("first Lyapunov coefficient l1", dash="not a Hopf point"),
    "eigenvalue_real": Column("Re of the eigenvalue of the mode (crossing at the Hopf point, or least damped) [1/s]",
                              dash="not a linear check"),
    "envelope_rate": Column("simulation: envelope rate of a small oscillation [1/s]",
                            dash="not a linear check, or the run stopped"),
    "simulation_theta1_deg": Column("simulation: max |theta1| [deg]",
                                    dash="no simulation in that row, or the run stopped"),
    "kick_deg": Column("kick threshold: initial theta1 [deg]", dash="not a kick row"),
    "window_end_kmh": Column("end of the full geometry's window the ramp leaves through [km/h]",
                             dash="not a ramp row"),
    "reduced_jump_kmh": Column("reduced model's jump in the same ramp [km/h]",
                               dash="not a ramp row, or the reduced model does not make this jump"),
    "theta1_diff": Column("max |theta1|, simulation against continuation: relative difference [relative, not %]",
                          dash="no orbit compared in that row"),
    "continuation_hz": Column("continuation: frequency [Hz]", dash="no orbit in that row"),
    "braking": Column("braking (brake slip of both wheels, or right / left)"),
    "free_kmh": Column("free rolling, reduced model [km/h]", dash="no free-rolling partner: a Hopf point braking adds"),
    "braked_kmh": Column("under braking, reduced model [km/h]",
                         dash="no partner under braking: the mode's window closed or left 0-400 km/h"),
    "shift_kmh": Column("braked minus free rolling [km/h]", dash="a point without a partner, so no shift"),
    "steady_state_deg": Column("straight running under braking: theta1, theta2, psi [deg]"),
    "simulation_hz": Column("simulation: frequency [Hz]",
                            dash="no simulation in that row, or no oscillation left to measure"),
    "frequency_diff": Column("frequency, simulation against continuation: relative difference [relative, not %]",
                             dash="no orbit compared in that row"),
    "damping_ratio": Column("least damping ratio (negative: shimmy)", dash="no value in that row"),
    "mode": Column("least damped mode", dash="no value in that row"),
    "status": Column("check"),
    "note": Column("note"),
    "error": Column("error"),
}
GENERIC_DASH = "does not apply to that kind of row (the table holds rows of several kinds)"
SUMMARY_COLUMNS = ("section", "checks", "pass", "known differences", "fail", "info", "could not check")
STATUS_TEXT = {
    CheckStatus.PASS: "the check passed",
    CheckStatus.FAIL: "the check failed (verify exits 1)",
    CheckStatus.KNOWN_DIFFERENCE: "differs from the paper for a reason listed in docs/results.md",
    CheckStatus.INFO: "a measured number, or what a model is expected to do: information, not a check",
    CheckStatus.COULD_NOT_CHECK: ("could not be checked (the note says why): never counted as passed, never makes "
                                  "verify exit 1"),
}


@dataclass(frozen=True)
class Row:
    cells: dict
    status: CheckStatus
    note: str = ""

    def __post_init__(self):
        # A row that fails or could not be checked says why: the rule's reason is part of the row.
        if self.status in (CheckStatus.FAIL, CheckStatus.COULD_NOT_CHECK) and not (self.note or
                                                                                   self.cells.get("error")):
            raise ValueError(f"a '{self.status.value}' row needs its reason in the note")


@dataclass(frozen=True)
class Section:
    key: str
    title: str
    columns: tuple[str, ...]
    rows: tuple[Row, ...]
    text: str = ""                      # what is compared and the tolerances used
    figures: tuple[str, ...] = ()       # file names relative to the report folder
    recordings: tuple[str, ...] = ()
    labels: dict = field(default_factory=dict)   # column -> Column or str, over COLUMN_LABELS
    # what the section adds to the verdict at the top (e.g. the margins' minima: verdict.MarginFact objects)
    verdict_facts: tuple = ()

    def count(self, status: CheckStatus) -> int:
        return sum(r.status is status for r in self.rows)

    @property
    def failed(self) -> bool:
        return self.count(CheckStatus.FAIL) > 0

    def column(self, name: str) -> Column:
        got = self.labels.get(name, COLUMN_LABELS.get(name))
        if got is None:
            return Column(name.replace("_", " "))
        return Column(got) if isinstance(got, str) else got

    def dashes(self) -> list[tuple[str, str]]:
        """(column header, what "-" means there) for every column that shows a "-" in some row."""
        out = []
        for name in self.columns:
            if any(_missing(r.cells.get(name)) or _dash_inside(r.cells.get(name)) for r in self.rows):
                col = self.column(name)
                out.append((col.label, col.dash or GENERIC_DASH))
        return out


@dataclass(frozen=True)
class RunMetadata:
    """What a report was made with: enough to reproduce it."""

    date_utc: str
    shimmy: str
    git_commit: str | None
    python: str
    numpy: str
    scipy: str
    exudyn: str
    rerun_sdk: str
    axle: str
    axle_sha256: str
    mode: str
    seconds: float | None = None
    command: str = ""

    def rows(self) -> list[tuple[str, str]]:
        return [("date (UTC)", self.date_utc), ("command", self.command or "-"), ("mode", self.mode),
                ("run time", "-" if self.seconds is None else f"{self.seconds:.1f} s"),
                ("shimmy", self.shimmy), ("git commit", self.git_commit or "- (not a git checkout)"),
                ("axle", self.axle), ("axle SHA-256", self.axle_sha256), ("python", self.python),
                ("numpy", self.numpy), ("scipy", self.scipy), ("exudyn", self.exudyn),
                ("rerun-sdk", self.rerun_sdk)]


@dataclass(frozen=True)
class Report:
    sections: tuple[Section, ...]
    quick: bool
    notes: tuple[str, ...] = field(default=())
    metadata: RunMetadata | None = None
    plan: object = None          # comparisons.verify.plan.Plan
    axle: object = None          # axles.axle.Axle
    verdict: object = None       # comparisons.verify.verdict.Verdict

    @property
    def failed(self) -> bool:
        return any(s.failed for s in self.sections)

    def count(self, status: CheckStatus) -> int:
        return sum(s.count(status) for s in self.sections)

    def nothing_to_check(self) -> list[Section]:
        """Sections that compared nothing: every row says "could not check", or there is no row at all."""
        return [s for s in self.sections if all(r.status is CheckStatus.COULD_NOT_CHECK for r in s.rows)]

    def overall(self) -> str:
        """FAILED, or how many equivalence checks passed, with the rows that could not be checked counted apart and
        the sections that checked nothing named: a run in which nothing was compared never reads as passed."""
        if self.failed:
            return "FAILED"
        passed = self.count(CheckStatus.PASS)
        text = f"all {passed} equivalence checks passed" if passed else "nothing was checked"
        unchecked = self.count(CheckStatus.COULD_NOT_CHECK)
        if unchecked:
            text += f"; {unchecked} could not be checked (counted apart)"
        empty = self.nothing_to_check()
        if empty:
            text += "; nothing checked in " + ", ".join(s.title for s in empty)
        return text

    def summary_rows(self) -> list[dict]:
        return [{"section": s.title, "checks": len(s.rows), "pass": s.count(CheckStatus.PASS),
                 "known differences": s.count(CheckStatus.KNOWN_DIFFERENCE), "fail": s.count(CheckStatus.FAIL),
                 "info": s.count(CheckStatus.INFO), "could not check": s.count(CheckStatus.COULD_NOT_CHECK)}
                for s in self.sections]


# --- metadata --------------------------------------------------------------------------------------------------

def _version(package: str) -> str:
    import importlib.metadata
    try:
        return importlib.metadata.version(package)
    except importlib.metadata.PackageNotFoundError:
        return "not installed"


def git_commit(folder: str | None = None) -> str | None:
    """The commit of the checkout this code runs from (with "+ local changes" when dirty), or None."""
    folder = folder or os.path.dirname(os.path.abspath(__file__))
    try:
        head = subprocess.run(["git", "rev-parse", "HEAD"], cwd=folder, capture_output=True, text=True, timeout=10)
        if head.returncode != 0:
            return None
        dirty = subprocess.run(["git", "status", "--porcelain", "--untracked-files=no"], cwd=folder,
                               capture_output=True, text=True, timeout=10)
    except (OSError, subprocess.SubprocessError):
        return None
    return head.stdout.strip() + (" + local changes" if dirty.stdout.strip() else "")


def axle_fingerprint(axle) -> tuple[str, str]:
    """(name, SHA-256) of an axle: the file's hash when it came from one, else a hash of every entry's SI value
    (so that two reports of the same axle carry the same hash)."""
    if axle is None:
        from axles.axle import paper_axle
        axle = paper_axle()
    if getattr(axle, "sha256", None) and not getattr(axle, "overrides", ()):
        return axle.label(), axle.sha256
    from axles.axle import entries
    text = ";".join(f"{name}={axle.value(name)!r}" for name in entries())
    return axle.label(), hashlib.sha256(text.encode()).hexdigest()


def run_metadata(quick: bool, axle=None, seconds: float | None = None, command: str = "",
                 now: datetime.datetime | None = None) -> RunMetadata:
    name, digest = axle_fingerprint(axle)
    now = now or datetime.datetime.now(datetime.timezone.utc)
    return RunMetadata(date_utc=now.strftime("%Y-%m-%d %H:%M:%S"), shimmy=_version("shimmy-axle"),
                       git_commit=git_commit(), python=platform.python_version(), numpy=_version("numpy"),
                       scipy=_version("scipy"), exudyn=_version("exudyn"), rerun_sdk=_version("rerun-sdk"),
                       axle=name, axle_sha256=digest, mode="quick" if quick else "full", seconds=seconds,
                       command=command)


# --- cells -----------------------------------------------------------------------------------------------------

def _missing(value) -> bool:
    """No value: shown as "-" and explained under the table (an empty text too, never a blank cell)."""
    return value is None or (isinstance(value, float) and value != value) or (isinstance(value, str)
                                                                               and not value.strip())


def _dash_inside(value) -> bool:
    return isinstance(value, str) and ("-," in value or value.strip() == "-" or value.endswith(", -"))


def _cell(value, factor: float = 1.0) -> str:
    if _missing(value):
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
