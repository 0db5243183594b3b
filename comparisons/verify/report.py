"""The verification report: sections of tables whose rows carry a check status, with run metadata, column headers
in words and units, every "-" explained, and figures.  :mod:`comparisons.verify.rendering` writes it as Markdown
and HTML.

Rows keep the code names of their columns (the JSON of ``verify --json`` uses them); the rendered tables show
:data:`COLUMN_LABELS` (or a section's own ``labels``) instead.
"""

from __future__ import annotations

import datetime
import enum
import hashlib
import os
import platform
import shlex
import subprocess
import sys
from dataclasses import dataclass, field

from comparisons.studies.onset import JUMP_TOL_DEG


def is_missing(value) -> bool:
    """No value: shown as "-" and explained under the table (an empty text too, never a blank cell)."""
    return value is None or (isinstance(value, float) and value != value) or (isinstance(value, str)
                                                                               and not value.strip())


def has_dash_inside(value) -> bool:
    return isinstance(value, str) and ("-," in value or value.strip() == "-" or value.endswith(", -"))



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
    "soft_count": Column("axles whose full geometry sets in softly at its lowest Hopf point (from zero, or a jump "
                         f"below {JUMP_TOL_DEG:g} deg)"),
    "hard_count": Column("axles whose full geometry jumps in at its lowest Hopf point (a larger jump)"),
    "none_count": Column("axles whose full geometry has no Hopf point"),
    "undetermined_count": Column("axles whose onset nothing decided (no branch at a kink, or l1 not a number)"),
    "kink_jump_count": Column(f"soft onsets subcritical at the camber kink (a jump below {JUMP_TOL_DEG:g} deg)"),
    "kink_jump_max_deg": Column("largest such jump [deg]", dash="none"),
    "onset_window_count": Column("hard onsets with a bistable window next to them (from 0.5 km/h wide)"),
    "onset_windows_kmh": Column("those windows [km/h]", dash="none"),
    "onset_window_unknown": Column("hard onsets whose window is not known (branch stopped early or over its budget)"),
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
    "grid_step_bar": Column("pressure grid step [bar]", dash="not a map row"),
    "region_kmh": Column("bistable interval [km/h]", dash="not a region row"),
    "inside_kmh": Column("kick speed inside [km/h]", dash="not a region row"),
    "outside": Column("same kick outside (pressure, speed)",
                      dash="not a region row, or no point with one stable state was found"),
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
            if any(is_missing(r.cells.get(name)) or has_dash_inside(r.cells.get(name)) for r in self.rows):
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
