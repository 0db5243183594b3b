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

from axles.units import kmh
from comparisons.verify.plan import Plan
from comparisons.verify.scan import VMAX, Boundary, BoundaryKind, Model, Window
from reduced_model.family import MIN_SPEED

BOUNDARY_SAME_BAR = 0.01      # boundaries closer than this are the same to the verdict's two decimals
TOUCH = 1e-9                  # m/s: windows whose ends lie this close are one unstable stretch


def _range_text(low: float, high: float) -> str:
    return f"from {kmh(low):.1f} to {kmh(high):.1f} km/h"


@dataclass(frozen=True)
class ModeRange:
    """Where one mode grows inside an unstable stretch (m/s); a mode may grow on several disjoint ranges."""

    mode: str
    ranges: tuple[tuple[float, float], ...]

    def text(self, stretch: "Stretch") -> str:
        if self.ranges == ((stretch.low, stretch.high),):
            return f"{self.mode} throughout"
        return f"{self.mode} " + " and ".join(_range_text(a, b) for a, b in self.ranges)

    def to_json(self) -> dict:
        return {"mode": self.mode, "ranges_kmh": [[kmh(a), kmh(b)] for a, b in self.ranges]}


@dataclass(frozen=True)
class Stretch:
    """One maximal unstable speed interval of straight running (m/s) at one case: the windows between Hopf points
    that touch are one stretch, however many modes' Hopf points fall inside it; each mode with its own ranges."""

    low: float
    high: float
    modes: tuple[ModeRange, ...]

    @property
    def from_lowest(self) -> bool:
        return self.low <= MIN_SPEED

    @property
    def to_top(self) -> bool:
        return self.high >= VMAX

    def text(self) -> str:
        """"from 0.5 to 400.0 km/h, from the lowest speed and up to the top of the speed window (yaw throughout,
        tramp from 184.0 to 196.0 km/h)"."""
        ends = [e for e, on in (("from the lowest speed", self.from_lowest),
                                ("up to the top of the speed window", self.to_top)) if on]
        return (_range_text(self.low, self.high) + (", " + " and ".join(ends) if ends else "")
                + f" ({', '.join(m.text(self) for m in self.modes)})")

    def to_json(self) -> dict:
        return {"low_kmh": kmh(self.low), "high_kmh": kmh(self.high), "from_lowest_speed": self.from_lowest,
                "to_top_speed": self.to_top, "modes": [m.to_json() for m in self.modes], "text": self.text()}


def stretches(windows) -> tuple[Stretch, ...]:
    """The maximal unstable stretches of a case's windows (each between neighbouring Hopf points, by speed)."""
    groups: list[list[Window]] = []
    for w in sorted(windows, key=lambda w: w.low):
        if groups and w.low - groups[-1][-1].high <= TOUCH:
            groups[-1].append(w)
        else:
            groups.append([w])
    out = []
    for group in groups:
        modes = []
        for mode in dict.fromkeys(m for w in group for m in w.modes()):
            ranges: list[list[float]] = []
            for w in group:
                if mode not in w.modes():
                    continue
                if ranges and w.low - ranges[-1][1] <= TOUCH:
                    ranges[-1][1] = w.high
                else:
                    ranges.append([w.low, w.high])
            modes.append(ModeRange(mode, tuple((a, b) for a, b in ranges)))
        out.append(Stretch(group[0].low, group[-1].high, tuple(modes)))
    return tuple(out)


@dataclass(frozen=True)
class RobustnessShare:
    """Over the plausible multibody dimensions, the share of axles whose full geometry shimmies at one case (from
    the section "Robustness": its minimum margin negative), as the verdict adds it to the full geometry's line."""

    case: str             # the case's label ("1.5 bar")
    share: float
    samples: int

    def text(self) -> str:
        return (f"over its plausible dimensions the full geometry shimmies at {self.case} in {100 * self.share:.0f} % "
                f"of axles ({self.samples} sampled)")

    def to_json(self) -> dict:
        return {"case": self.case, "share": self.share, "samples": self.samples, "text": self.text()}


@dataclass(frozen=True)
class CaseFacts:
    """One model's unstable stretches at one planned case."""

    label: str
    pressure_right_bar: float
    pressure_left_bar: float
    windows: tuple[Stretch, ...]

    def modes(self) -> set[str]:
        return {m.mode for w in self.windows for m in w.modes}

    def to_json(self) -> dict:
        return {"case": self.label, "pressure_right_bar": self.pressure_right_bar,
                "pressure_left_bar": self.pressure_left_bar, "windows": [w.to_json() for w in self.windows]}


def windows_text(windows: tuple[Stretch, ...]) -> str:
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

    def case_text(self, facts: CaseFacts, robustness: tuple[RobustnessShare, ...] = ()) -> str:
        text = (f"{self.model.label} runs straight at every speed" if not facts.windows else
                f"{self.model.label} shimmies {windows_text(facts.windows)}")
        if self.model is Model.FULL:
            text += "".join(f"; {r.text()}" for r in robustness if r.case == facts.label)
        return text

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
    (:class:`comparisons.verify.margin_checks.MarginMinimum`, one per model, from the section "Stability margins")."""

    def text(self) -> str: ...

    def to_json(self) -> dict: ...


@dataclass(frozen=True)
class Verdict:
    models: tuple[ModelVerdict, ...]
    disagreements: tuple[Disagreement, ...]
    # per model, the least damping ratio of straight running over the operating window; added after the section
    # "Stability margins" has run (empty when it did not)
    margins: tuple[MarginFact, ...] = ()
    # the full geometry's share of shimmying axles over its plausible dimensions, by case; added after the section
    # "Robustness" has run (empty when it did not)
    robustness: tuple[RobustnessShare, ...] = ()
    # per model, its bistable regions in (V, p) and its stable-shimmy-free pressure; added after the section
    # "Bistable regions" has run (verify.bistable_rows.BistableFact; empty when it did not)
    bistable: tuple = ()

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
            parts = [m.case_text(f, self.robustness) for m in self.models for f in [m.facts_at(facts.label)]
                     if f is not None]
            out.append(f"At {facts.label}: " + "; ".join(parts) + ".")
        if len(self.models) == 2:
            out += [_sentence("the models disagree: " + d.text) for d in self.disagreements]
            if not self.disagreements:
                out.append("The models agree at every planned case on whether and in which modes the axle shimmies.")
        out += [m.text() for m in self.margins]
        out += [_sentence(b.text()) for b in self.bistable]
        return out

    def to_json(self) -> dict:
        bistable = {b.model: b.to_json() for b in self.bistable}
        models = [{**m.to_json(), **({"bistable": bistable[m.model]} if m.model in bistable else {})}
                  for m in self.models]
        return {"headline": self.headline(), "models": models,
                "disagreements": [d.to_json() for d in self.disagreements],
                "margins": [m.to_json() for m in self.margins],
                "robustness": [r.to_json() for r in self.robustness],
                "lines": self.lines()}


def _sentence(text: str) -> str:
    return text[0].upper() + text[1:] + "."


def verdict_of(plan: Plan) -> Verdict:
    """The verdict of a plan (whose cases carry both models' windows, :func:`comparisons.verify.plan.case_windows`)."""
    models = []
    for scan in plan.scans:
        facts = tuple(CaseFacts(c.label, c.pressure_right_bar, c.pressure_left_bar,
                                stretches(c.windows_of(scan.model)))
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
                    ranges = [r for w in mine.windows for m in w.modes if m.mode == mode for r in m.ranges]
                    out.append(Disagreement(
                        DisagreementKind.MODE, this.model, that.model,
                        f"at {fa.label} {this.model.label} shimmies in {mode} "
                        f"{' and '.join(_range_text(a, b) for a, b in ranges)}, a mode {that.model.label} lacks "
                        f"there", fa.label))
    return out
