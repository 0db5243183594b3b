"""What each assumption of the reduced model is worth: Hopf-speed and limit-cycle shifts when it is dropped.

For one pressure (and pressure effects, Table 1 overrides), rows are each assumption of the paper switched off
alone (all others on) and ``full`` (all off), each against the reduced model; then each new geometric element
(kingpin inclination, raised roll axis, lateral mounts, Ackermann arms, steering gear), measured as ``full``
against ``full`` without that element (its "reduced" side is then the MBS without the element).  Per row: every
Hopf point of the MBS against the reduced model's, matched
one-to-one by speed and frequency (a mode that vanishes or appears is unmatched: the other side is None), and
the steady theta1 amplitude of the MBS at the speed where the reduced model's limit cycle is largest, against the
reduced model's there (:mod:`mbs_shimmy.limit_cycle`).  The Hopf points of both models come from the same
defining system (:func:`reduced_model.bifurcation.equilibria.hopf.hopf_points`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Sequence

import numpy as np
import scipy.optimize

from mbs_shimmy.dimensions import DEFAULT_DIMENSIONS, AxleDimensions
from mbs_shimmy.fidelity import ASSUMPTIONS, Fidelity
from reduced_model.bifurcation.equilibria.hopf import HopfPoint, hopf_points
from reduced_model.family import SpeedFamily
from reduced_model.model import Effects, ShimmyModel
from reduced_model.parameters import ShimmyParameters

ELEMENTS = frozenset(info.name for info in ASSUMPTIONS if info.element)
from mbs_shimmy.limit_cycle import VMAX, SteadyAmplitude, mbs_steady_amplitude, reduced_peak
from mbs_shimmy.linearisation import MbsFamily, MbsModel

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
    assumption: str                  # an assumption's name, or "full"
    hopf: tuple[HopfShift, ...]
    peak_theta1_mbs: float | None       # rad
    peak_theta1_reduced: float | None   # rad
    peak_settled: bool | None


@dataclass(frozen=True)
class AssumptionStudy:
    pressure: float                  # Pa (the nominal pressure of the study's family)
    effects: tuple[str, ...]
    reduced_hopf_speeds: tuple[float, ...]   # m/s
    peak_speed: float | None         # m/s, where the reduced model's limit cycle is largest (None: no cycle)
    peak_theta1: float | None        # rad
    rows: tuple[AssumptionRow, ...]


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


def study_fidelities() -> list[tuple[str, Fidelity]]:
    """Each assumption of the paper off alone, then all off (``full``), then ``full`` with one of the new
    geometric elements taken out again (that element's assumption on): the element's row compares that with
    ``full`` (:func:`study_rows`)."""
    rows = [(info.name, Fidelity.reduced().without(info.assumption)) for info in ASSUMPTIONS if not info.element]
    rows.append(("full", Fidelity.full()))
    rows += [(info.name, Fidelity(frozenset({info.assumption}))) for info in ASSUMPTIONS if info.element]
    return rows


def assumption_study(params: ShimmyParameters, effects: Effects, pressure: float, *,
                     dims: AxleDimensions = DEFAULT_DIMENSIONS, vmax: float = VMAX, cycles: bool = True,
                     settle: float = 12.0, progress=None) -> AssumptionStudy:
    """The shifts table at one pressure (Pa, or (right, left)).  ``cycles=False`` skips the cycle amplitudes (None)."""
    model = ShimmyModel(params, effects)
    q = SpeedFamily(model, pressure=pressure).nominal
    reduced = hopf_points(SpeedFamily(model, pressure=pressure), q, 0.0, vmax, lyapunov=False)
    peak: SteadyAmplitude | None = reduced_peak(model, pressure, vmax, settle) if cycles else None
    rows = []
    full_points = full_amp = full_settled = None

    def amplitude(fidelity):
        # start from the reduced model's cycle: the MBS's own one, if it has one there, is close
        r = mbs_steady_amplitude(params, effects, fidelity, pressure, peak.speed, peak.final_state, settle,
                                 dims=dims)
        return (r.theta1 if math.isfinite(r.theta1) else None), r.settled

    for k, (name, fidelity) in enumerate(study_fidelities()):
        family = MbsFamily(MbsModel(params, effects, fidelity, dims), pressure=pressure)
        mbs = hopf_points(family, q, 0.0, vmax, lyapunov=False)
        mbs_amp = red_amp = settled = None
        if name in ELEMENTS:
            # the element's worth: full geometry (mbs side) against full geometry without it (reference side)
            if peak is not None:
                red_amp, _ = amplitude(fidelity)
                mbs_amp, settled = full_amp, full_settled
            rows.append(AssumptionRow(name, match_hopf(mbs, full_points), mbs_amp, red_amp, settled))
        else:
            if peak is not None:
                mbs_amp, settled = amplitude(fidelity)
                red_amp = peak.theta1
            rows.append(AssumptionRow(name, match_hopf(reduced, mbs), mbs_amp, red_amp, settled))
            if name == "full":
                full_points, full_amp, full_settled = mbs, mbs_amp, settled
        if progress is not None:
            progress(k + 1)
    return AssumptionStudy(q, effects.names, tuple(h.p for h in reduced),
                           peak.speed if peak else None, peak.theta1 if peak else None, tuple(rows))
