"""What ``shimmy sweep`` computes for one sample, and the Parquet schema of its rows (runs on the Dask workers).

A :class:`SweepTask` is everything a worker needs (the base axle, pressures, effects and what to compute); it is
sent to each worker once.  :func:`evaluate_batch` evaluates consecutive samples and returns one Arrow table: a
sample that fails (a meaningless value, a Newton iteration that does not converge) is a row with status
``failed`` and its error message, never a lost batch.  The numbers come from the same calls as the single-point
commands: :func:`bifurcation.equilibria.hopf.find_hopf_points` on the same family as ``shimmy hopf``,
:func:`comparisons.studies.assumption_study.assumption_study` (without cycles) as ``shimmy assumptions --no-cycles``, and
:func:`bifurcation.cycles.problem.cycle_diagram` as ``shimmy cycles``.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

import numpy as np
import pyarrow as pa

from comparisons.assumption_shifts import mbs_kmh, shift_kmh
from axles.axle import AxleData, entry, interface_text
from axles.units import BAR, KMH, kmh
from reduced_model.model import Effects
from reduced_model.modes import ModeClassifier
from axles.braking import FREE_ROLLING, Braking
from axles.pressures import TyrePressures
from comparisons.api import family_of
from comparisons.studies.bistable_map import MIN_WIDTH
from comparisons.studies.budget import DeadlineWatch, OutOfTime
from comparisons.studies.kick import bistable_windows

COMPUTE = ("hopf", "margins", "assumptions", "cycles")
# margins: the least damping ratio of straight running on this many even speeds from 0.5 km/h to vmax (default)
MARGIN_SPEEDS = 41
PRESSURE_LIMITS_BAR = (0.05, 20.0)
# Rough cost of one sample (s, one core) for batch sizing; measured on the paper's axle at 1.5 bar.
COST_S = {"hopf": 0.004, "lyapunov": 0.003, "mbs": 0.03, "margins": 0.016, "assumptions": 0.3, "cycles": 1.5}
# MBS cycle branches (--compute cycles --mbs F), per fidelity, mean over samples.  full: 16 plausible axles of the
# paper's truck at 1.5 bar, 0-400 km/h, 70 s of CPU in all in one process (4.4 s each; 9 without a Hopf point under
# a second, one violent axle 37 s; docs/sweeps.md).  reduced: not measured, taken as full's (any value above 1 s
# gives one sample per batch).
MBS_CYCLES_COST_S = {"reduced": 4.4, "full": 4.4}
# The MBS Hopf points' l1 (with --lyapunov, and always with MBS cycles, whose branch switching needs it)
MBS_LYAPUNOV_COST_S = 0.1
# mbs_onset: the lowest Hopf point's one-step branch with its end segment (0.43 s on the paper's axle at 1.5 bar),
# and where the onset is hard its branch over the side where straight running is stable (0.5-2 s, at most
# ONSET_WINDOW_BUDGET_S; 9 of 256 plausible axles at 1.5 bar)
MBS_ONSET_COST_S = 0.5


_MODES = ModeClassifier()


def mode_of(ratio: float, frequency_hz: float) -> str:
    """Hopf points, margins and cycles are labelled by the thresholds of :class:`reduced_model.modes.ModeClassifier`
    (:meth:`~reduced_model.modes.ModeClassifier.mode_name`)."""
    return _MODES.mode_name(ratio, frequency_hz)


def _column_safe(text: str) -> str:
    return re.sub(r"[^A-Za-z0-9]+", "_", text).strip("_")


@dataclass(frozen=True)
class SweepTask:
    """What every sample shares (SI inside the axle; pressures in bar, speeds in km/h as at the interface)."""

    axle: AxleData
    effects: tuple[str, ...]
    pressure_right_bar: float
    pressure_left_bar: float
    names: tuple[str, ...]                  # varied inputs, as given
    compute: tuple[str, ...] = ("hopf",)
    mbs: tuple[str, ...] = ()               # MBS fidelities whose Hopf points are computed too
    vmax_kmh: float = 400.0
    lyapunov: bool = False
    margin_speeds: int = MARGIN_SPEEDS      # speeds of the margins output
    mbs_lyapunov: tuple[str, ...] = ()      # MBS fidelities whose Hopf points get l1 without ``lyapunov`` too
    braking: Braking = FREE_ROLLING         # a steady braking of every sample (both models)
    # MBS fidelities whose lowest Hopf point, where the right-hand side has a kink there, gets a one-step cycle
    # branch with its end segment: how the shimmy sets in, and the size of the jump, where l1 cannot say (cheap:
    # about 0.4 s; the whole branches of ``--compute cycles`` say it too)
    mbs_onset: tuple[str, ...] = ()

    @property
    def mbs_cycles(self) -> bool:
        """The MBS fidelities' own cycle branches (``--compute cycles --mbs F``)."""
        return "cycles" in self.compute and bool(self.mbs)

    def mbs_l1(self, fidelity: str) -> bool:
        """Whether this MBS fidelity's Hopf points carry l1 (columns ``mbs_<fidelity>_hopf_l1``)."""
        return self.lyapunov or self.mbs_cycles or fidelity in self.mbs_lyapunov or fidelity in self.mbs_onset

    def cost_s(self) -> float:
        cost = COST_S["hopf"] + (COST_S["lyapunov"] if self.lyapunov else 0.0) + COST_S["mbs"] * len(self.mbs)
        cost += MBS_LYAPUNOV_COST_S * sum(self.mbs_l1(f) for f in self.mbs)
        cost += sum(MBS_CYCLES_COST_S[f] for f in self.mbs) if self.mbs_cycles else 0.0
        cost += MBS_ONSET_COST_S * len(self.mbs_onset) if not self.mbs_cycles else 0.0
        margins = (COST_S["margins"] * (1 + len(self.mbs)) * self.margin_speeds / MARGIN_SPEEDS
                   if "margins" in self.compute else 0.0)
        return cost + margins + sum(COST_S[c] for c in self.compute if c not in ("hopf", "margins"))

    def to_json(self) -> dict:
        return {"axle": self.axle.describe(), "effects": list(self.effects),
                "pressure_right_bar": self.pressure_right_bar, "pressure_left_bar": self.pressure_left_bar,
                "compute": list(self.compute), "mbs": list(self.mbs), "vmax_kmh": self.vmax_kmh,
                "lyapunov": self.lyapunov, "margin_speeds": self.margin_speeds,
                **({"mbs_lyapunov": list(self.mbs_lyapunov)} if self.mbs_lyapunov else {}),
                **({"mbs_onset": list(self.mbs_onset)} if self.mbs_onset else {}),
                **({"braking": self.braking.describe()} if self.braking.active else {})}

    # --- schema -------------------------------------------------------------------------------------------
    def assumption_names(self) -> list[str]:
        from comparisons.studies.assumption_study import study_fidelities
        return [name for name, _ in study_fidelities()]

    def schema(self) -> pa.Schema:
        floats, strings = pa.list_(pa.float64()), pa.list_(pa.string())
        fields = [pa.field("sample", pa.int64()), pa.field("batch", pa.int32())]
        fields += [pa.field(n, pa.float64()) for n in self.names]
        fields += [pa.field("status", pa.string()), pa.field("error", pa.string()),
                   pa.field("pressure_right_bar", pa.float64()), pa.field("pressure_left_bar", pa.float64())]
        if "hopf" in self.compute:
            fields += [pa.field("hopf_kmh", floats), pa.field("hopf_hz", floats), pa.field("hopf_mode", strings)]
            if self.lyapunov:
                fields += [pa.field("hopf_l1", floats), pa.field("hopf_criticality", strings)]
            fields += [pa.field("n_hopf", pa.int32()), pa.field("onset_kmh", pa.float64()),
                       pa.field("unstable_from_kmh", floats), pa.field("unstable_to_kmh", floats)]
        if "hopf" in self.compute or self.mbs_cycles:
            for f in self.mbs:
                c = f"mbs_{_column_safe(f)}"
                fields += [pa.field(f"{c}_hopf_kmh", floats), pa.field(f"{c}_hopf_hz", floats),
                           pa.field(f"{c}_hopf_mode", strings), pa.field(f"{c}_onset_kmh", pa.float64())]
                if "hopf" in self.compute:
                    fields.append(pa.field(f"{c}_shift_kmh", floats))
                if self.mbs_l1(f):
                    fields += [pa.field(f"{c}_hopf_l1", floats), pa.field(f"{c}_hopf_criticality", strings),
                               pa.field(f"{c}_hopf_criticality_by", strings), pa.field(f"{c}_hopf_kink", floats),
                               pa.field(f"{c}_hopf_onset", strings), pa.field(f"{c}_hopf_jump_deg", floats)]
                if f in self.mbs_onset:
                    fields += [pa.field(f"{c}_onset_window", pa.string()), pa.field(f"{c}_onset_window_kmh", floats)]
        if "margins" in self.compute:
            for c in [""] + [f"mbs_{_column_safe(f)}_" for f in self.mbs]:
                fields += [pa.field(f"{c}margin", pa.float64()), pa.field(f"{c}margin_kmh", pa.float64()),
                           pa.field(f"{c}margin_hz", pa.float64()), pa.field(f"{c}margin_mode", pa.string())]
        if "assumptions" in self.compute:
            for name in self.assumption_names():
                fields += [pa.field(f"shift_{name}_kmh", floats), pa.field(f"only_{name}_kmh", floats)]
        if "cycles" in self.compute:
            for c in [""] + [f"mbs_{_column_safe(f)}_" for f in self.mbs]:
                fields += [pa.field(f"{c}cycle_from_kmh", floats), pa.field(f"{c}cycle_to_kmh", floats),
                           pa.field(f"{c}cycle_status", strings), pa.field(f"{c}cycle_mode", strings),
                           pa.field(f"{c}cycle_peak_kmh", floats), pa.field(f"{c}cycle_peak_theta1_deg", floats),
                           pa.field(f"{c}cycle_peak_psi_deg", floats), pa.field(f"{c}cycle_peak_hz", floats),
                           pa.field(f"{c}cycles_complete", pa.bool_()), pa.field(f"{c}cycles_message", pa.string()),
                           pa.field(f"{c}peak_yaw_theta1_deg", pa.float64()),
                           pa.field(f"{c}peak_tramp_theta1_deg", pa.float64()),
                           pa.field(f"{c}bistable_from_kmh", floats), pa.field(f"{c}bistable_to_kmh", floats)]
        return pa.schema(fields)

    # --- one sample ---------------------------------------------------------------------------------------
    def sample_inputs(self, values: np.ndarray) -> tuple[AxleData, float, float]:
        """(axle, right bar, left bar) of one sample; :class:`ParameterError` for a meaningless value."""
        from axles.parameters import ParameterError
        right, left = self.pressure_right_bar, self.pressure_left_bar
        si = {}
        given = dict(zip(self.names, (float(v) for v in values)))
        if "pressure" in given:
            shift = given["pressure"] - (0.5 * (right + left))
            right, left = right + shift, left + shift
            if self.pressure_right_bar == self.pressure_left_bar:
                right = left = given["pressure"]
        right = given.get("pressure_right", right)
        left = given.get("pressure_left", left)
        for name, value in given.items():
            if name not in ("pressure", "pressure_right", "pressure_left"):
                si[name] = entry(name).to_si(value)
        lo, hi = PRESSURE_LIMITS_BAR
        for what, value in (("right tyre pressure", right), ("left tyre pressure", left)):
            if not (math.isfinite(value) and lo <= value <= hi):
                raise ParameterError(f"{what} {value:g} bar is outside [{lo:g}, {hi:g}] bar")
        return (self.axle.with_values(si) if si else self.axle), right, left

    def evaluate(self, values: np.ndarray) -> dict:
        """The output columns of one sample (raises on failure)."""
        from bifurcation.equilibria.hopf import find_hopf_points
        from reduced_model.model import ShimmyModel
        axle, right, left = self.sample_inputs(values)
        pressures = TyrePressures(right * BAR, left * BAR)
        effects = Effects.parse(self.effects)
        model = ShimmyModel(params=axle.params, effects=effects)
        vmax = self.vmax_kmh * KMH
        row: dict = {"pressure_right_bar": right, "pressure_left_bar": left}
        family = family_of(model, pressures, "pressure", self.braking)
        mbs_families = {}
        if "hopf" in self.compute:
            points = find_hopf_points(family, family.nominal, 0.0, vmax, lyapunov=self.lyapunov)
            row.update(_hopf_columns("", points))
            if self.lyapunov:
                row.update(_criticality_columns("", points))
            row["unstable_from_kmh"], row["unstable_to_kmh"] = _unstable_intervals(family, points, vmax)
        if self.mbs and ("hopf" in self.compute or self.mbs_cycles):
            from mbs_shimmy.fidelity import Fidelity
            from mbs_shimmy.model import MbsModel
            for f in self.mbs:
                c = f"mbs_{_column_safe(f)}_"
                mf = family_of(MbsModel(axle.params, effects, Fidelity.parse(f), axle.dims), pressures, "pressure",
                               self.braking)
                mbs_families[f] = mf
                diagram = None
                if self.mbs_cycles:
                    # the branches start at the diagram's own Hopf points (l1 included): those are the columns
                    try:
                        diagram = _cycle_diagram(mf, vmax)
                    except (OutOfTime, RuntimeError, np.linalg.LinAlgError) as exc:
                        # over its budget, or a continuation that raised instead of ending its branch with a
                        # status: the sample keeps its Hopf points, its cycles are unknown (null), never an empty
                        # set of branches
                        mp = find_hopf_points(mf, mf.nominal, 0.0, vmax, lyapunov=True)
                        row.update(failed_cycle_columns(c, _failure(exc)))
                    else:
                        mp = diagram.hopf
                        row.update(cycle_columns(c, mf, diagram))
                else:
                    mp = find_hopf_points(mf, mf.nominal, 0.0, vmax, lyapunov=self.mbs_l1(f))
                    if f in self.mbs_onset and mp:
                        diagram = _onset_branch(mf, mp[0], vmax)
                row.update(_hopf_columns(c, mp))
                if self.mbs_l1(f):
                    row.update(_criticality_columns(c, mp, mf, diagram))
                if f in self.mbs_onset:
                    row.update(_onset_window_columns(c, mf, mp, row[f"{c}hopf_onset"], vmax))
                if "hopf" in self.compute:
                    from comparisons.studies.assumption_study import match_hopf
                    # each reduced-model Hopf point's shift (MBS - reduced), None where the mode has no partner
                    shifts = {m.reduced_speed: shift_kmh(m) for m in match_hopf(points, mp)}
                    row[f"{c}shift_kmh"] = [shifts.get(h.p) for h in points]
        if "margins" in self.compute:
            speeds = np.linspace(family.primary_min, vmax, self.margin_speeds)
            row.update(_margin_columns("", family, speeds))
            for f, mf in mbs_families.items():     # the MBS Jacobians of the Hopf search are kept: only eigenvalues
                row.update(_margin_columns(f"mbs_{_column_safe(f)}_", mf, speeds))
        if "assumptions" in self.compute:
            from comparisons.studies.assumption_study import assumption_study
            study = assumption_study(axle.params, effects, pressures, dims=axle.dims, vmax=vmax, cycles=False)
            for r in study.rows:
                row[f"shift_{r.assumption}_kmh"] = [shift_kmh(h) for h in r.hopf if h.reduced_speed is not None]
                row[f"only_{r.assumption}_kmh"] = [mbs_kmh(h) for h in r.hopf if h.reduced_speed is None]
        if "cycles" in self.compute:
            try:
                row.update(cycle_columns("", family, _cycle_diagram(family, vmax)))
            except OutOfTime as stop:
                row.update(failed_cycle_columns("", _failure(stop)))
        return row


def _hopf_columns(prefix: str, points) -> dict:
    modes = [mode_of(abs(h.eigenvector[4]) / abs(h.eigenvector[0]), h.frequency_hz) for h in points]
    out = {f"{prefix}hopf_kmh": [kmh(h.p) for h in points], f"{prefix}hopf_hz": [h.frequency_hz for h in points],
           f"{prefix}hopf_mode": modes, f"{prefix}onset_kmh": kmh(points[0].p) if points else None}
    if not prefix:
        out["n_hopf"] = len(points)
    return out


def _margin_columns(prefix: str, family, speeds: np.ndarray) -> dict:
    """The least damping ratio of straight running over ``speeds`` (m/s): its minimum, where, its frequency and
    mode (labelled as the Hopf points are); null where nothing oscillates."""
    from bifurcation.equilibria.margins import MarginStatus, least_damped
    # The family was validated at this q by the Hopf search (margin_map would validate again: an Exudyn
    # linearisation per MBS fidelity, more than the eigenvalues cost).
    found = [m for m in (least_damped(family, v, family.nominal, vector=False) for v in speeds)
             if m.status is MarginStatus.OSCILLATORY]
    if not found:
        return {f"{prefix}margin": None, f"{prefix}margin_kmh": None, f"{prefix}margin_hz": None,
                f"{prefix}margin_mode": None}
    low = least_damped(family, min(found, key=lambda m: m.damping_ratio).p, family.nominal)   # with its vector
    v = low.eigenvector
    return {f"{prefix}margin": low.damping_ratio, f"{prefix}margin_kmh": kmh(low.p),
            f"{prefix}margin_hz": low.frequency_hz, f"{prefix}margin_mode": mode_of(abs(v[4]) / abs(v[0]),
                                                                                  low.frequency_hz)}


def _unstable_intervals(family, points, vmax: float) -> tuple[list[float], list[float]]:
    """Speed intervals (km/h) where straight running is unstable: between Hopf points, decided by the eigenvalues
    at each interval's midpoint."""
    from bifurcation.equilibria.hopf import eigenvalues
    q = family.nominal
    edges = [family.primary_min] + [h.p for h in points] + [vmax]
    lo, hi = [], []
    for a, b in zip(edges[:-1], edges[1:]):
        if b <= a:
            continue
        if eigenvalues(family, 0.5 * (a + b), q)[0].real > 0.0:
            if hi and abs(hi[-1] - a / KMH) < 1e-9:
                hi[-1] = b / KMH
            else:
                lo.append(a / KMH)
                hi.append(b / KMH)
    return lo, hi


def _criticality_columns(prefix: str, points, family=None, diagram=None) -> dict:
    """Each Hopf point's first Lyapunov coefficient and its criticality (null where undetermined).  For an MBS
    ``family`` also what the criticality rests on (``<prefix>hopf_criticality_by``): "l1" where the right-hand side
    is twice differentiable there; where it has a kink (the full geometry's camber force) l1's sign is no
    criticality, and it is the cycle branch's where ``diagram`` has one from that point ("branch"), else the kink
    coefficient's ("kink", ``<prefix>hopf_kink``) (:mod:`comparisons.studies.onset`).  And how the shimmy sets in
    there (``<prefix>hopf_onset``: "soft" or "hard", null where no branch says it at a kink) with the size of the
    jump a subcritical branch's fold makes (``<prefix>hopf_jump_deg``)."""
    from comparisons.studies.onset import read_onset
    out = {f"{prefix}hopf_l1": [h.first_lyapunov for h in points]}
    if family is None:
        out[f"{prefix}hopf_criticality"] = [h.criticality.value if h.criticality else None for h in points]
        return out
    readings = [read_onset(family, h, diagram) for h in points]
    out[f"{prefix}hopf_criticality"] = [r.criticality.value if r.criticality else None for r in readings]
    out[f"{prefix}hopf_criticality_by"] = [r.by for r in readings]
    out[f"{prefix}hopf_kink"] = [h.kink if math.isfinite(h.kink) else None for h in points]
    out[f"{prefix}hopf_onset"] = [r.kind for r in readings]
    out[f"{prefix}hopf_jump_deg"] = [r.jump_deg for r in readings]
    return out


def _onset_window_columns(prefix: str, family, points, onsets, vmax: float) -> dict:
    """Where the lowest Hopf point's onset is hard, the bistable window next to it (``<prefix>onset_window``: its
    kind, :class:`comparisons.studies.onset.OnsetWindow`; ``<prefix>onset_window_kmh``: [low, high] where there is
    one); null where the onset is soft or unknown, or there is no Hopf point."""
    from axles.units import from_kmh
    from comparisons.studies.onset import onset_window
    if not points or onsets[0] != "hard":
        return {f"{prefix}onset_window": None, f"{prefix}onset_window_kmh": None}
    found = onset_window(family, points[0], points, vmax, MIN_WIDTH, from_kmh(ONSET_WINDOW_PAST_KMH),
                         ONSET_WINDOW_BUDGET_S)
    return {f"{prefix}onset_window": found.kind,
            f"{prefix}onset_window_kmh": None if found.interval is None else [kmh(v) for v in found.interval]}


# how far short of the neighbouring Hopf point an onset window's branch stops (that point's own branch stays out)
ONSET_WINDOW_PAST_KMH = 0.5
# and its budget of wall clock: most take 0.5-2 s, but violent cycles that lift a wheel took 22-32 s (two of 256
# plausible axles at 1.5 bar: about 100 cycles on up to 640 mesh intervals), which verify's budget cannot carry
ONSET_WINDOW_BUDGET_S = 10.0


class _OnsetBranches:
    """The one-step branch at a Hopf point (:func:`_onset_branch`) as :func:`branch_onset` reads a diagram."""

    def __init__(self, branches):
        self.branches = branches


def _onset_branch(family, hopf, vmax: float):
    """A one-step cycle branch from ``hopf`` with its end segment (its cycle folds between the Hopf point and the
    first cycle), where the right-hand side has a kink there (``hopf.kink``, computed with l1 where the family
    says so: no second test); None elsewhere (l1 says it)."""
    import dataclasses
    from bifurcation.cycles.branches import branch_from_hopf
    from bifurcation.cycles.problem import CycleSettings
    if not math.isfinite(hopf.kink):
        return None
    s = CycleSettings()
    s = dataclasses.replace(s, continuation=dataclasses.replace(s.continuation, max_steps=1))
    return _OnsetBranches((branch_from_hopf(family, hopf, 0.0, vmax, settings=s),))


# Wall clock for one model's cycle branches of one sample: the paper's axle's take 2-4 s in the full geometry, but
# violent cycles that lift a wheel need minutes (a random plausible axle's 0.5 bar branch: 112 s, 2026-12-07); past
# the budget the sample's cycles are unknown (null, cycles_complete false, the message says where), never "none".
CYCLES_BUDGET_S = 30.0


def _cycle_diagram(family, vmax: float):
    """The sample's cycle branches over 0-``vmax`` within :data:`CYCLES_BUDGET_S` (:class:`OutOfTime` past it)."""
    import time

    from bifurcation.cycles.branches import cycle_diagram
    return cycle_diagram(family, family.nominal, 0.0, vmax,
                         accept_hook=DeadlineWatch(time.monotonic() + CYCLES_BUDGET_S, family.state_names))


def _branch_peak(family, branch):
    """The cycle of largest max |theta1| on the branch, refined as ``shimmy cycles`` refines it (the computed
    point where the refinement does not converge)."""
    from bifurcation.cycles.branches import branch_peak
    from bifurcation.special_points import ConvergenceError
    try:
        return branch_peak(family, branch, "theta1")
    except ConvergenceError:
        return branch.peak("theta1")


CYCLE_LISTS = ("from_kmh", "to_kmh", "status", "mode", "peak_kmh", "peak_theta1_deg", "peak_psi_deg", "peak_hz")


def _failure(exc: Exception) -> str:
    """Why a sample's cycles are unknown: past :data:`CYCLES_BUDGET_S`, or the continuation raised."""
    if isinstance(exc, OutOfTime):
        return f"over the budget of {CYCLES_BUDGET_S:g} s: stopped on {exc}"
    return f"{type(exc).__name__}: {interface_text(exc)}"


def failed_cycle_columns(prefix: str, error: str) -> dict:
    """The cycle columns of a continuation that failed as a whole: branches unknown (null), not complete."""
    return {**{f"{prefix}cycle_{k}": None for k in CYCLE_LISTS}, f"{prefix}cycles_complete": False,
            f"{prefix}cycles_message": f"cycle continuation failed: {error}",
            f"{prefix}peak_yaw_theta1_deg": None, f"{prefix}peak_tramp_theta1_deg": None,
            f"{prefix}bistable_from_kmh": None, f"{prefix}bistable_to_kmh": None}


def cycle_columns(prefix: str, family, diagram) -> dict:
    """Per cycle branch: its Hopf ends, status, and its cycle of largest max |theta1| (speed, amplitudes in
    degrees, frequency, mode by the same thresholds as the Hopf points); per mode the largest amplitude, null
    where a branch of that mode did not complete (its amplitudes are then a lower bound only)."""
    out = {k: [] for k in CYCLE_LISTS}
    for b in diagram.branches:
        out["from_kmh"].append(kmh(b.start.p) if b.start else None)
        out["to_kmh"].append(kmh(b.end.p) if b.end else None)
        out["status"].append(b.status.value)
        if not b.points:       # stopped before its first cycle: the mode of its Hopf point, no amplitude
            h = b.start
            out["mode"].append(mode_of(abs(h.eigenvector[4]) / abs(h.eigenvector[0]), h.frequency_hz) if h else None)
            for k in ("peak_kmh", "peak_theta1_deg", "peak_psi_deg", "peak_hz"):
                out[k].append(None)
            continue
        p = _branch_peak(family, b)
        t1, psi = p.max_abs("theta1"), p.max_abs("psi")
        out["mode"].append(mode_of(psi / t1 if t1 > 0 else math.nan, p.frequency_hz))
        out["peak_kmh"].append(kmh(p.p))
        out["peak_theta1_deg"].append(math.degrees(t1))
        out["peak_psi_deg"].append(math.degrees(psi))
        out["peak_hz"].append(p.frequency_hz)
    row = {f"{prefix}cycle_{k}": v for k, v in out.items()}
    for m in ("yaw", "tramp"):
        mine = [(b, t) for b, t, mm in zip(diagram.branches, out["peak_theta1_deg"], out["mode"]) if mm == m]
        whole = all(b.complete for b, _ in mine)
        row[f"{prefix}peak_{m}_theta1_deg"] = (max((t for _, t in mine if t is not None), default=None)
                                               if whole else None)
    # Every speed interval where two stable states coexist (a stable cycle beside stable straight running, or two
    # stable cycles), wherever on the branches: each is a fact; an incomplete diagram may miss some.
    windows = bistable_windows(diagram, family, MIN_WIDTH)
    row[f"{prefix}bistable_from_kmh"] = [kmh(a) for a, _ in windows]
    row[f"{prefix}bistable_to_kmh"] = [kmh(b) for _, b in windows]
    stopped = [b for b in diagram.branches if not b.complete]
    row[f"{prefix}cycles_complete"] = not stopped
    row[f"{prefix}cycles_message"] = ("; ".join(
        f"branch from {kmh(b.start.p):.3f} km/h stopped ({b.status.value}): {interface_text(b.message)}"
        for b in stopped) if stopped else None)
    return row


def _inputs(task: SweepTask, batch: int, start: int, values: np.ndarray) -> list[dict]:
    return [{"sample": start + i, "batch": batch, **{n: float(x) for n, x in zip(task.names, v)}}
            for i, v in enumerate(values)]


def evaluate_batch(task: SweepTask, batch: int, start: int, values: np.ndarray) -> pa.Table:
    """Rows ``start .. start + len(values) - 1`` of the sweep as one Arrow table (the unit of work on Dask)."""
    rows = _inputs(task, batch, start, values)
    for row, v in zip(rows, values):
        try:
            row.update(task.evaluate(v))
            row["status"] = "ok"
        except Exception as exc:  # recorded in the row: one bad sample never loses its batch
            row["status"], row["error"] = "failed", f"{type(exc).__name__}: {interface_text(exc)}"
    return pa.Table.from_pylist(rows, schema=task.schema())


def failed_batch(task: SweepTask, batch: int, start: int, values: np.ndarray, error: str) -> pa.Table:
    """A batch none of whose samples could be evaluated (every worker that ran it died): failed rows with
    ``error``, so that the sweep completes and says which samples are missing and why."""
    rows = [{**row, "status": "failed", "error": error} for row in _inputs(task, batch, start, values)]
    return pa.Table.from_pylist(rows, schema=task.schema())
