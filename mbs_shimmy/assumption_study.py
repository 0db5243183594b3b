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
from mbs_shimmy.limit_cycle import SteadyAmplitude, mbs_steady_amplitude, reduced_peak
from mbs_shimmy.linearisation import MbsFamily, MbsModel

KMH = 3.6
MATCH_FREQUENCY = 0.3     # relative frequency difference above which two Hopf points are different modes


@dataclass(frozen=True)
class HopfShift:
    reduced_kmh: float | None
    mbs_kmh: float | None
    reduced_hz: float | None
    mbs_hz: float | None

    @property
    def shift_kmh(self) -> float | None:
        if self.reduced_kmh is None or self.mbs_kmh is None:
            return None
        return self.mbs_kmh - self.reduced_kmh

    def to_json(self) -> dict:
        return {"reduced_kmh": self.reduced_kmh, "mbs_kmh": self.mbs_kmh, "shift_kmh": self.shift_kmh}


@dataclass(frozen=True)
class AssumptionRow:
    assumption: str                  # an assumption's name, or "full"
    hopf: tuple[HopfShift, ...]
    peak_theta1_mbs_deg: float | None
    peak_theta1_reduced_deg: float | None
    peak_settled: bool | None

    @property
    def peak_theta1_shift_deg(self) -> float | None:
        if self.peak_theta1_mbs_deg is None or self.peak_theta1_reduced_deg is None:
            return None
        return self.peak_theta1_mbs_deg - self.peak_theta1_reduced_deg

    def to_json(self) -> dict:
        return {"assumption": self.assumption, "hopf": [h.to_json() for h in self.hopf],
                "peak_theta1_shift_deg": self.peak_theta1_shift_deg}


@dataclass(frozen=True)
class AssumptionStudy:
    pressure_bar: float
    effects: tuple[str, ...]
    reduced_hopf_kmh: tuple[float, ...]
    peak_speed_kmh: float | None     # where the reduced model's limit cycle is largest (None: no cycle)
    peak_theta1_deg: float | None
    rows: tuple[AssumptionRow, ...]

    def to_json(self) -> dict:
        return {"pressure_bar": self.pressure_bar, "effects": list(self.effects),
                "peak_speed_kmh": self.peak_speed_kmh, "reduced_peak_theta1_deg": self.peak_theta1_deg,
                "rows": [r.to_json() for r in self.rows]}


def match_hopf(reduced: Sequence[HopfPoint], mbs: Sequence[HopfPoint]) -> tuple[HopfShift, ...]:
    """One-to-one matching by speed and frequency (Hungarian method); pairs of different modes stay apart."""
    n, m = len(reduced), len(mbs)
    pairs: list[tuple[int, int]] = []
    if n and m:
        cost = np.full((n, m), 1e6)
        for i, r in enumerate(reduced):
            for j, b in enumerate(mbs):
                if abs(b.omega - r.omega) <= MATCH_FREQUENCY * r.omega:
                    cost[i, j] = abs(b.speed - r.speed) * KMH / 10.0 + abs(b.omega - r.omega) / r.omega
        rows, cols = scipy.optimize.linear_sum_assignment(cost)
        pairs = [(i, j) for i, j in zip(rows, cols) if cost[i, j] < 1e6]
    matched_r = {i for i, _ in pairs}
    matched_m = {j for _, j in pairs}
    out = [HopfShift(reduced[i].speed_kmh, mbs[j].speed_kmh, reduced[i].frequency_hz, mbs[j].frequency_hz)
           for i, j in pairs]
    out += [HopfShift(r.speed_kmh, None, r.frequency_hz, None) for i, r in enumerate(reduced) if i not in matched_r]
    out += [HopfShift(None, b.speed_kmh, None, b.frequency_hz) for j, b in enumerate(mbs) if j not in matched_m]
    return tuple(sorted(out, key=lambda h: h.reduced_kmh if h.reduced_kmh is not None else h.mbs_kmh))


def study_fidelities() -> list[tuple[str, Fidelity]]:
    """Each assumption of the paper off alone, then all off (``full``), then ``full`` with one of the new
    geometric elements taken out again (that element's assumption on): the element's row compares that with
    ``full`` (:func:`study_rows`)."""
    rows = [(info.name, Fidelity.reduced().without(info.assumption)) for info in ASSUMPTIONS if not info.element]
    rows.append(("full", Fidelity.full()))
    rows += [(info.name, Fidelity(frozenset({info.assumption}))) for info in ASSUMPTIONS if info.element]
    return rows


def assumption_study(params: ShimmyParameters, effects: Effects, pressure: float, *,
                     dims: AxleDimensions = DEFAULT_DIMENSIONS, vmax: float = 400 / 3.6, cycles: bool = True,
                     settle: float = 12.0, progress=None) -> AssumptionStudy:
    """The shifts table at one pressure (Pa, or (right, left)).  ``cycles=False`` skips the cycle amplitudes (None)."""
    model = ShimmyModel(params, effects)
    q = SpeedFamily(model, pressure=pressure).nominal
    reduced = hopf_points(SpeedFamily(model, pressure=pressure), q, 0.0, vmax, lyapunov=False)
    peak: SteadyAmplitude | None = reduced_peak(model, pressure, vmax, settle) if cycles else None
    rows = []
    full_points = full_deg = full_settled = None

    def amplitude(fidelity):
        # start from the reduced model's cycle: the MBS's own one, if it has one there, is close
        r = mbs_steady_amplitude(params, effects, fidelity, pressure, peak.speed, peak.final_state, settle,
                                 dims=dims)
        return (math.degrees(r.theta1) if math.isfinite(r.theta1) else None), r.settled

    for k, (name, fidelity) in enumerate(study_fidelities()):
        family = MbsFamily(MbsModel(params, effects, fidelity, dims), pressure=pressure)
        mbs = hopf_points(family, q, 0.0, vmax, lyapunov=False)
        mbs_deg = red_deg = settled = None
        if name in ELEMENTS:
            # the element's worth: full geometry (mbs side) against full geometry without it (reference side)
            if peak is not None:
                red_deg, _ = amplitude(fidelity)
                mbs_deg, settled = full_deg, full_settled
            rows.append(AssumptionRow(name, match_hopf(mbs, full_points), mbs_deg, red_deg, settled))
        else:
            if peak is not None:
                mbs_deg, settled = amplitude(fidelity)
                red_deg = peak.theta1_deg
            rows.append(AssumptionRow(name, match_hopf(reduced, mbs), mbs_deg, red_deg, settled))
            if name == "full":
                full_points, full_deg, full_settled = mbs, mbs_deg, settled
        if progress is not None:
            progress(k + 1)
    return AssumptionStudy(q / 1e5, effects.names, tuple(h.speed_kmh for h in reduced),
                           peak.speed * KMH if peak else None, peak.theta1_deg if peak else None, tuple(rows))
