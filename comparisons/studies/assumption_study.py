"""What each assumption of the reduced model is worth: Hopf-speed and limit-cycle shifts when it is dropped.

For one pressure (and pressure effects, Table 1 overrides), rows are each assumption of the paper switched off
alone (all others on) and ``full`` (all off), each against the reduced model; then each new geometric element
(kingpin inclination, raised roll axis, lateral mounts, Ackermann arms, steering gear, ...), measured as ``full``
against ``full`` without that element (its "reduced" side is then the MBS without the element).  Per row: every
Hopf point of the MBS against the reduced model's, matched one-to-one by speed and frequency (a mode that vanishes
or appears is unmatched: the other side is None), and the largest limit cycle of each side, each from its own
continued cycle branches over the speed window (:mod:`comparisons.studies.cycle_peak`: the MBS variant's branches on
Exudyn, the reduced model's on its equations), with the speed where it occurs, its mode and stability.  The Hopf
points of both models come from the same defining system
(:func:`bifurcation.equilibria.hopf.find_hopf_points`).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Callable, Sequence

import numpy as np
import scipy.optimize

from comparisons.studies.cycle_peak import CyclePeak, continued_peak
from axles.dimensions import DEFAULT_DIMENSIONS, AxleDimensions
from mbs_shimmy.fidelity import ASSUMPTIONS, Fidelity
from comparisons.studies.limit_cycle import VMAX
from mbs_shimmy.model import MbsModel
from bifurcation.equilibria.hopf import HopfPoint, find_hopf_points
from reduced_model.model import Effects, ShimmyModel
from axles.parameters import ShimmyParameters
from axles.braking import Braking
from axles.pressures import TyrePressures
from comparisons.api import family_of

ELEMENTS = frozenset(info.name for info in ASSUMPTIONS if info.element)

MATCH_FREQUENCY = 0.3     # relative frequency difference above which two Hopf points are different modes
# Speed difference (m/s) that weighs as much as a relative frequency difference of 1 when pairing Hopf points.
MATCH_SPEED = 2.7777777777777777   # 10 km/h


@dataclass(frozen=True)
class HopfShift:
    """A Hopf point of the reference side and its partner on the MBS side; None where a mode has no partner.
    The shift is left to the reader: in km/h it is the difference of the converted speeds."""

    reduced_speed: float | None     # m/s
    mbs_speed: float | None         # m/s
    reduced_hz: float | None
    mbs_hz: float | None


@dataclass(frozen=True)
class AssumptionRow:
    """One switch: the Hopf points of both sides, matched, and each side's largest cycle (None: not computed).
    The reference side is the reduced model, or for an element's row the full geometry without the element; the
    MBS side the variant of the row, or for an element's row the full geometry."""

    assumption: str                  # an assumption's name, or "full"
    hopf: tuple[HopfShift, ...]
    peak_mbs: CyclePeak | None = None
    peak_reference: CyclePeak | None = None
    seconds: float = field(default=0.0, compare=False)   # cost of the row (its Hopf search, continuation)

    @property
    def peak_theta1_mbs(self) -> float | None:
        """rad; 0 where the side has no cycle, None when not computed or incomplete."""
        return None if self.peak_mbs is None else self.peak_mbs.theta1

    @property
    def peak_theta1_reduced(self) -> float | None:
        return None if self.peak_reference is None else self.peak_reference.theta1


@dataclass(frozen=True)
class AssumptionStudy:
    pressure: float                  # Pa (the nominal pressure of the study's family)
    effects: tuple[str, ...]
    reduced_hopf_speeds: tuple[float, ...]   # m/s
    reduced_peak: CyclePeak | None   # the reduced model's largest cycle (None: cycles not computed)
    rows: tuple[AssumptionRow, ...]

    @property
    def peak_speed(self) -> float | None:
        """m/s, where the reduced model's limit cycle is largest (None: no cycle, or not computed)."""
        return None if self.reduced_peak is None else self.reduced_peak.speed

    @property
    def peak_theta1(self) -> float | None:
        return None if self.reduced_peak is None else self.reduced_peak.theta1


def match_hopf(reduced: Sequence[HopfPoint], mbs: Sequence[HopfPoint]) -> tuple[HopfShift, ...]:
    """One-to-one matching by speed and frequency (Hungarian method); pairs of different modes stay apart."""
    n, m = len(reduced), len(mbs)
    pairs: list[tuple[int, int]] = []
    if n and m:
        cost = np.full((n, m), 1e6)
        for i, r in enumerate(reduced):
            for j, b in enumerate(mbs):
                if abs(b.omega - r.omega) <= MATCH_FREQUENCY * r.omega:
                    cost[i, j] = abs(b.p - r.p) / MATCH_SPEED + abs(b.omega - r.omega) / r.omega
        rows, cols = scipy.optimize.linear_sum_assignment(cost)
        pairs = [(i, j) for i, j in zip(rows, cols) if cost[i, j] < 1e6]
    matched_r = {i for i, _ in pairs}
    matched_m = {j for _, j in pairs}
    out = [HopfShift(reduced[i].p, mbs[j].p, reduced[i].frequency_hz, mbs[j].frequency_hz)
           for i, j in pairs]
    out += [HopfShift(r.p, None, r.frequency_hz, None) for i, r in enumerate(reduced) if i not in matched_r]
    out += [HopfShift(None, b.p, None, b.frequency_hz) for j, b in enumerate(mbs) if j not in matched_m]
    return tuple(sorted(out, key=lambda h: h.reduced_speed if h.reduced_speed is not None else h.mbs_speed))


NO_SLIP = "no_longitudinal_slip"


def braking_row_name(braking: Braking) -> str:
    """'no_longitudinal_slip (brake slip 0.05)': the row of the paper's assumption of free-rolling wheels, dropped
    at one braking level."""
    return f"{NO_SLIP} ({braking})"


def study_fidelities() -> list[tuple[str, Fidelity]]:
    """Each assumption of the paper off alone, then all off (``full``), then ``full`` with one of the new
    geometric elements taken out again (that element's assumption on): the element's row compares that with
    ``full`` (:func:`study_rows`)."""
    rows = [(info.name, Fidelity.reduced().without(info.assumption)) for info in ASSUMPTIONS if not info.element]
    rows.append(("full", Fidelity.full()))
    rows += [(info.name, Fidelity(frozenset({info.assumption}))) for info in ASSUMPTIONS if info.element]
    return rows


def assumption_study(params: ShimmyParameters, effects: Effects, pressures: TyrePressures, *,
                     dims: AxleDimensions = DEFAULT_DIMENSIONS, vmax: float = VMAX, cycles: bool = True,
                     only: Sequence[str] | None = None,
                     progress: Callable[[int, int, str], None] | None = None,
                     brakings: Sequence[Braking] = ()) -> AssumptionStudy:
    """The shifts table at the tyres' ``pressures`` over speeds up to ``vmax`` (m/s).

    ``cycles=False`` skips the continuation of cycles (peaks None).  ``only``: the names of the rows wanted (an
    element's row brings ``full`` with it, whose peak it needs).  ``progress(done, total, name)`` after each row
    (the reduced model's continuation counts as one).  ``brakings``: one row per braking level for the paper's
    assumption of no longitudinal slip (:func:`braking_row_name`): the reduced model free rolling (reference side)
    against the reduced model under that braking, from its steady state (other side)."""
    names = [n for n, _ in study_fidelities()]
    wanted = set(names if only is None else only)
    unknown = wanted - set(names)
    if unknown:
        raise ValueError(f"no row named {', '.join(sorted(unknown))} (rows: {', '.join(names)})")
    if wanted & ELEMENTS:
        wanted.add("full")
    fidelities = [(n, f) for n, f in study_fidelities() if n in wanted]
    total = len(fidelities) + len(brakings) + (1 if cycles else 0)
    done = 0
    model = ShimmyModel(params, effects)
    family = family_of(model, pressures)
    q = family.nominal
    peak = None
    if cycles:
        peak, diagram = continued_peak(family, q, 0.0, vmax)
        reduced = diagram.hopf
        done += 1
        if progress is not None:
            progress(done, total, "reduced model")
    else:
        reduced = find_hopf_points(family, q, 0.0, vmax, lyapunov=False)
    rows = []
    full_points = full_peak = None
    for name, fidelity in fidelities:
        start = time.perf_counter()
        mbs_family = family_of(MbsModel(params, effects, fidelity, dims), pressures)
        if cycles:
            mbs_peak, mbs_diagram = continued_peak(mbs_family, q, 0.0, vmax)
            mbs = mbs_diagram.hopf
        else:
            mbs_peak, mbs = None, find_hopf_points(mbs_family, q, 0.0, vmax, lyapunov=False)
        seconds = time.perf_counter() - start
        if name in ELEMENTS:
            # the element's worth: full geometry (mbs side) against full geometry without it (reference side)
            rows.append(AssumptionRow(name, match_hopf(mbs, full_points), full_peak, mbs_peak, seconds))
        else:
            rows.append(AssumptionRow(name, match_hopf(reduced, mbs), mbs_peak, peak, seconds))
            if name == "full":
                full_points, full_peak = mbs, mbs_peak
        done += 1
        if progress is not None:
            progress(done, total, name)
    for braking in brakings:
        start = time.perf_counter()
        braked = family_of(model, pressures, "pressure", braking)
        if cycles:
            braked_peak, braked_diagram = continued_peak(braked, q, 0.0, vmax)
            points = braked_diagram.hopf
        else:
            braked_peak, points = None, find_hopf_points(braked, q, 0.0, vmax, lyapunov=False)
        rows.append(AssumptionRow(braking_row_name(braking), match_hopf(reduced, points), braked_peak, peak,
                                  time.perf_counter() - start))
        done += 1
        if progress is not None:
            progress(done, total, rows[-1].assumption)
    rows = [r for r in rows if only is None or r.assumption in only or r.assumption.startswith(NO_SLIP)]
    return AssumptionStudy(q, effects.names, tuple(h.p for h in reduced), peak, tuple(rows))

