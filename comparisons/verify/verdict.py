"""The verdict at the top of the verify report: what each model says about shimmy on this axle, and where the models
disagree, in words an engineer can act on.

Built from the plan's data alone (:class:`comparisons.verify.plan.Plan`: each model's scan of the pressure window and
both models' unstable windows at every planned case), never from text: a frozen :class:`Verdict` holds the facts,
its :meth:`Verdict.lines` and :meth:`Verdict.to_json` are made from them.
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass
from typing import Protocol

from comparisons.verify.plan import Plan
from comparisons.verify.scan import Boundary, BoundaryKind, Model, Window

BOUNDARY_SAME_BAR = 0.01      # boundaries closer than this are the same to the verdict's two decimals


@dataclass(frozen=True)
class CaseFacts:
    """One model's unstable windows at one planned case."""

    label: str
    pressure_right_bar: float
    pressure_left_bar: float
    windows: tuple[Window, ...]

    def modes(self) -> set[str]:
        return {w.mode for w in self.windows}

    def to_json(self) -> dict:
        return {"case": self.label, "pressure_right_bar": self.pressure_right_bar,
                "pressure_left_bar": self.pressure_left_bar, "windows": [w.to_json() for w in self.windows]}


def windows_text(windows: tuple[Window, ...]) -> str:
    return " and ".join(w.text() for w in windows)


@dataclass(frozen=True)
class ModelVerdict:
    """What one model says: its shimmy-free boundary over the pressure window and its windows at each case."""

    model: Model
    window_bar: tuple[float, float]
    boundary: Boundary
    cases: tuple[CaseFacts, ...]

    def boundary_text(self) -> str:
        lo, hi = self.window_bar
        b = self.boundary
        if b.kind is BoundaryKind.SHIMMY_FREE_ABOVE:
            return f"{self.model.label} is shimmy-free above {b.pressure_bar:.2f} bar"
        if b.kind is BoundaryKind.SHIMMY_AT_TOP:
            return f"{self.model.label} shimmies up to the top of the window ({hi:g} bar)"
        return f"{self.model.label} has no shimmy in the window ({lo:g}-{hi:g} bar)"

    def case_text(self, facts: CaseFacts) -> str:
        if not facts.windows:
            return f"{self.model.label} runs straight at every speed"
        return f"{self.model.label} shimmies {windows_text(facts.windows)}"

    def facts_at(self, label: str) -> CaseFacts | None:
        return next((f for f in self.cases if f.label == label), None)

    def to_json(self) -> dict:
        return {"model": self.model.value, "boundary": self.boundary.to_json(), "boundary_text": self.boundary_text(),
                "cases": [f.to_json() for f in self.cases]}


class DisagreementKind(enum.Enum):
    ONE_MODEL = "one model shimmies"         # at a case one model shimmies and the other runs straight
    MODE = "a mode in one model only"        # both shimmy, but a mode exists in one of them only
    BOUNDARY = "boundaries differ"           # the shimmy-free boundaries differ


@dataclass(frozen=True)
class Disagreement:
    kind: DisagreementKind
    shimmies: Model                          # the model that shimmies (ONE_MODEL, MODE), or has the higher boundary
    other: Model
    text: str
    case: str | None = None                  # the case's label (ONE_MODEL, MODE)

    def to_json(self) -> dict:
        return {"kind": self.kind.name.lower(), "shimmies": self.shimmies.value, "other": self.other.value,
                "case": self.case, "text": self.text}


class MarginFact(Protocol):
    """What a stability margin adds to the verdict: a sentence and its data
    (:class:`comparisons.verify.margins.MarginMinimum`, one per model, from the section "Stability margins")."""

    def text(self) -> str: ...

    def to_json(self) -> dict: ...


@dataclass(frozen=True)
class Verdict:
    models: tuple[ModelVerdict, ...]
    disagreements: tuple[Disagreement, ...]
    # per model, the least damping ratio of straight running over the operating window; added after the section
    # "Stability margins" has run (empty when it did not)
    margins: tuple[MarginFact, ...] = ()

    def of(self, model: Model) -> ModelVerdict | None:
        return next((m for m in self.models if m.model is model), None)

    def headline(self) -> str:
        """One sentence: the pressure above which no model shimmies, or why there is none."""
        kinds = {m.boundary.kind for m in self.models}
        names = " and ".join(m.model.label for m in self.models)
        both = "both models" if len(self.models) == 2 else names
        either = "either model" if len(self.models) == 2 else names
        if kinds == {BoundaryKind.NO_SHIMMY}:
            lo, hi = self.models[0].window_bar
            return f"No shimmy at any speed in {lo:g}-{hi:g} bar in {either}."
        if BoundaryKind.SHIMMY_AT_TOP in kinds:
            top = [m.model.label for m in self.models if m.boundary.kind is BoundaryKind.SHIMMY_AT_TOP]
            hi = self.models[0].window_bar[1]
            return (f"No tyre pressure up to {hi:g} bar is shimmy-free in {' and '.join(top)}: "
                    f"shimmy up to the top of the pressure window.")
        p = max(m.boundary.pressure_bar for m in self.models if m.boundary.pressure_bar is not None)
        return f"Shimmy-free at every speed in {both} above {p:.2f} bar."

    def lines(self) -> list[str]:
        """The verdict as sentences: headline, each model's boundary, the windows per case, the disagreements."""
        out = [self.headline()]
        out += [_sentence(m.boundary_text()) for m in self.models]
        for facts in self.models[0].cases:
            parts = [m.case_text(f) for m in self.models for f in [m.facts_at(facts.label)] if f is not None]
            out.append(f"At {facts.label}: " + "; ".join(parts) + ".")
        if len(self.models) == 2:
            out += [_sentence("the models disagree: " + d.text) for d in self.disagreements]
            if not self.disagreements:
                out.append("The models agree at every planned case on whether and in which modes the axle shimmies.")
        out += [m.text() for m in self.margins]
        return out

    def to_json(self) -> dict:
        return {"headline": self.headline(), "models": [m.to_json() for m in self.models],
                "disagreements": [d.to_json() for d in self.disagreements],
                "margins": [m.to_json() for m in self.margins],
                "lines": self.lines()}


def _sentence(text: str) -> str:
    return text[0].upper() + text[1:] + "."


def verdict_of(plan: Plan) -> Verdict:
    """The verdict of a plan (whose cases carry both models' windows, :func:`comparisons.verify.plan.case_windows`)."""
    models = []
    for scan in plan.scans:
        facts = tuple(CaseFacts(c.label, c.pressure_right_bar, c.pressure_left_bar, c.windows_of(scan.model))
                      for c in plan.cases if c.windows_of(scan.model) is not None)
        models.append(ModelVerdict(scan.model, scan.window_bar, scan.boundary, facts))
    return Verdict(tuple(models), tuple(disagreements(models)) if len(models) == 2 else ())


def _extent(boundary: Boundary) -> float:
    """How far up in pressure a model shimmies: its boundary, -inf for none, +inf up to the top."""
    if boundary.kind is BoundaryKind.SHIMMY_FREE_ABOVE:
        return boundary.pressure_bar
    return math.inf if boundary.kind is BoundaryKind.SHIMMY_AT_TOP else -math.inf


def disagreements(models: list[ModelVerdict]) -> list[Disagreement]:
    """Where the two models disagree: the boundaries, then every case where only one shimmies or a mode exists in
    one model only."""
    out = []
    a, b = models
    ea, eb = _extent(a.boundary), _extent(b.boundary)
    if a.boundary.kind is not b.boundary.kind or abs(ea - eb) >= BOUNDARY_SAME_BAR:
        high, low = (a, b) if ea > eb else (b, a)
        out.append(Disagreement(DisagreementKind.BOUNDARY, high.model, low.model,
                                f"{low.boundary_text()}, but {high.boundary_text()}"))
    for fa in a.cases:
        fb = b.facts_at(fa.label)
        if fb is None:
            continue
        for this, that, mine, theirs in ((a, b, fa, fb), (b, a, fb, fa)):
            if mine.windows and not theirs.windows:
                out.append(Disagreement(
                    DisagreementKind.ONE_MODEL, this.model, that.model,
                    f"{that.boundary_text()} and runs straight at {fa.label}; {this.model.label} shimmies at "
                    f"{fa.label} {windows_text(mine.windows)}", fa.label))
            elif mine.windows and theirs.windows:
                for mode in sorted(mine.modes() - theirs.modes()):
                    w = tuple(x for x in mine.windows if x.mode == mode)
                    out.append(Disagreement(
                        DisagreementKind.MODE, this.model, that.model,
                        f"at {fa.label} {this.model.label} shimmies {windows_text(w)}, a mode "
                        f"{that.model.label} lacks there", fa.label))
    return out
