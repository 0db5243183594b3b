"""How far the full-geometry verdicts hold over the plausible range of every dimension nobody measured.

Each multibody entry of the axle with a plausible range (:meth:`axles.axle.AxleData.plausible_range`; new
geometry entries join automatically through :func:`axles.axle.entries`) is sampled uniformly on that range
(scrambled Sobol' sequence, the same axles at every pressure), and for each sample the MBS Hopf points are
computed with every assumption on (``reduced``) and off (``full``) by ``shimmy sweep`` on Dask.  Check: with every
assumption on, the MBS reproduces the reduced model's Hopf points in every plausible axle (the dimensions must not
enter then).  Information: in what fraction of plausible axles each mode exists with the full geometry, and each
reduced-model Hopf point's shift (median and 5-95 % range) and the dimension it depends on most (SRC), and whether
the full geometry's shimmy sets in softly or jumps in (the sign of l1 at its lowest Hopf point).
"""

from __future__ import annotations

import math
import os
import shutil
from dataclasses import dataclass

import numpy as np
import pyarrow as pa

from axles.axle import AxleData, entries
from comparisons.sweeps.design import Design, Variation, make_design
from comparisons.sweeps.sample import SweepTask
from comparisons.verify.context import HOPF_TOL_KMH, Context, shimmy_cases
from comparisons.verify.plan import CaseKind
from comparisons.verify.report import CheckStatus, Row, Section
from axles.pressures import TyrePressures

SAMPLES_FULL = 256
SAMPLES_QUICK = 32
MARGIN_SPEEDS_FULL = 41       # the coarse speed grid of each sample's minimum margin (0.5-400 km/h)
MARGIN_SPEEDS_QUICK = 21
MARGIN_TOL = 1e-9             # MBS with every assumption on against the reduced model
SEED = 2024
QUANTILES = (0.05, 0.5, 0.95)
FIGURE = "robustness.png"


def plausible_variations(axle: AxleData) -> list[Variation]:
    """A uniform input over each multibody entry's plausible range (interface units)."""
    out = []
    for name, e in entries().items():
        if e.section != "multibody":
            continue
        r = axle.plausible_range(name)
        if r is None or not r[0] < r[1]:
            continue
        out.append(Variation(name, "uniform", e.to_interface(r[0]), e.to_interface(r[1])))
    return out


def robustness_pressures(axle: AxleData) -> tuple[tuple[float, float], ...]:
    """(right, left) bar: the paper's two operating pressures for its axle; else the thirds of the axle's pressure
    range (``shimmy verify`` passes the cases of its plan instead)."""
    if axle.is_paper:
        return ((1.5, 1.5), (2.5, 2.5))
    lo, hi = axle.pressure_range_bar
    return tuple((round(lo + k * (hi - lo) / 3, 3),) * 2 for k in (1, 2))


def pressure_label(right: float, left: float) -> str:
    """As verify labels its cases."""
    return f"{right:g} bar" if right == left else f"R {right:g} / L {left:g} bar"


@dataclass(frozen=True)
class PressureStudy:
    pressure_right_bar: float
    pressure_left_bar: float
    design: Design
    table: pa.Table
    file: str
    reduced_onset_l1: float | None = None   # l1 of the reduced model's lowest Hopf point (None: no Hopf point)
    # whether the axle's full geometry is twice differentiable at straight running (its l1 well posed); None: not
    # known (mbs_shimmy.linearisation.MbsFamily.twice_differentiable)
    full_smooth: bool | None = None

    @property
    def label(self) -> str:
        return pressure_label(self.pressure_right_bar, self.pressure_left_bar)

    def _ok(self) -> np.ndarray:
        return np.array([s == "ok" for s in self.table.column("status").to_pylist()])

    def column(self, name: str) -> list:
        return [v for v, ok in zip(self.table.column(name).to_pylist(), self._ok()) if ok]

    def _errors(self) -> list[str]:
        return [e for e in self.table.column("error").to_pylist() if e is not None]

    @property
    def impossible(self) -> list[str]:
        """Errors of sampled axles that cannot exist (a dimension inconsistent with Table 1): excluded."""
        return [e for e in self._errors() if e.startswith("ParameterError:")]

    @property
    def failed(self) -> int:
        """Samples that failed for any other reason (a computation that did not converge): a failed check."""
        return len(self._errors()) - len(self.impossible)

    def reduced_points(self) -> list[tuple[float, str]]:
        """(speed, mode) of the reduced model's Hopf points (they do not depend on the multibody dimensions)."""
        speeds, modes = self.column("hopf_kmh"), self.column("hopf_mode")
        return list(zip(speeds[0], modes[0])) if speeds else []

    def mode_fraction(self, mode: str) -> float:
        rows = self.column("mbs_full_hopf_mode")
        return sum(mode in r for r in rows) / len(rows) if rows else math.nan

    def shifts(self, i: int) -> np.ndarray:
        """Full-geometry shift of reduced Hopf point i per sample (NaN: no partner in that axle)."""
        return np.array([math.nan if s[i] is None else s[i] for s in self.column("mbs_full_shift_kmh")])

    def worst_reduced_fidelity_error(self) -> float:
        worst = 0.0
        for red, mbs in zip(self.column("hopf_kmh"), self.column("mbs_reduced_hopf_kmh")):
            if len(red) != len(mbs):
                return math.inf
            worst = max([worst] + [abs(a - b) for a, b in zip(red, mbs)])
        return worst

    def onsets(self) -> dict[str, int]:
        """How the full geometry's shimmy sets in at its lowest Hopf point, counted over the axles that exist:
        ``soft`` (the amplitude grows from zero, or jumps by less than :data:`~comparisons.studies.onset.JUMP_TOL_DEG`),
        ``hard`` (it jumps to a larger cycle), ``none`` (no Hopf point in 0-400 km/h), ``undetermined`` (nothing
        said it: no branch where the right-hand side has a kink, or l1 not a number where it has none).  Read from
        the sweep's ``mbs_full_hopf_onset``: the one-step branch with its end segment at a kink (``mbs_onset``),
        l1's sign where the right-hand side is smooth."""
        out = dict.fromkeys(ONSETS, 0)
        for kinds, l1 in zip(self.column("mbs_full_hopf_onset"), self.column("mbs_full_hopf_l1")):
            out[onset_kind(kinds[0] if kinds else None, bool(l1))] += 1
        return out

    def onset_windows(self) -> dict[str, list]:
        """The hard onsets' bistable windows next to their Hopf point, by kind (``window``: the [low, high] km/h of
        each; ``none``, ``no_stable_side``, ``incomplete``: the samples), from the sweep's ``mbs_full_onset_window``
        (:func:`comparisons.studies.onset.onset_window`)."""
        out: dict[str, list] = {"window": [], "none": [], "no_stable_side": [], "incomplete": []}
        if "mbs_full_onset_window" not in self.table.column_names:     # a sweep without mbs_onset
            return out
        for kind, interval in zip(self.column("mbs_full_onset_window"), self.column("mbs_full_onset_window_kmh")):
            if kind is not None:
                out.setdefault(kind, []).append(interval if kind == "window" else None)
        return out

    def kink_jumps(self) -> list[float]:
        """The jumps (deg) of the soft onsets that are subcritical by a branch's fold: the fold the kink makes."""
        return [j[0] for j, k, c in zip(self.column("mbs_full_hopf_jump_deg"), self.column("mbs_full_hopf_onset"),
                                        self.column("mbs_full_hopf_criticality"))
                if j and j[0] is not None and k[0] == "soft" and c[0] == "subcritical"]

    def margins(self, prefix: str) -> np.ndarray:
        """The minimum margin of each sampled axle (NaN: nothing oscillates)."""
        return np.array([math.nan if m is None else m for m in self.column(f"{prefix}margin")])

    def worst_reduced_fidelity_margin_error(self) -> float:
        a, b = self.margins(""), self.margins("mbs_reduced_")
        if not np.array_equal(np.isnan(a), np.isnan(b)):
            return math.inf
        return float(np.nanmax(np.abs(a - b))) if np.isfinite(a).any() else 0.0

    def most_influential(self, i: int) -> tuple[str, float] | None:
        """(dimension, SRC) with the largest |SRC| for the shift of reduced Hopf point i."""
        y = self.shifts(i)
        ok = np.isfinite(y)
        if ok.sum() < len(self.design.names) + 2 or np.std(y[ok]) == 0.0:
            return None
        X = np.column_stack([np.array(self.column(n)) for n in self.design.names])[ok]
        A = np.column_stack([np.ones(ok.sum()), X])
        b = np.linalg.lstsq(A, y[ok], rcond=None)[0][1:]
        src = b * X.std(axis=0) / y[ok].std()
        j = int(np.argmax(np.abs(src)))
        return self.design.names[j], float(src[j])


ONSETS = ("soft", "hard", "none", "undetermined")


def onset_kind(kind: str | None, has_hopf: bool) -> str:
    """One of :data:`ONSETS` from a Hopf point's onset reading ("soft", "hard" or None)."""
    if not has_hopf:
        return "none"
    return kind if kind in ("soft", "hard") else "undetermined"


def l1_onset(l1: float | None) -> str | None:
    """The reduced model's onset (smooth: l1 says it): "soft" for l1 < 0, "hard" for l1 > 0, None otherwise."""
    if l1 is None or not math.isfinite(l1) or l1 == 0.0:
        return None
    return "soft" if l1 < 0.0 else "hard"


def reduced_onset_l1(axle: AxleData, right: float, left: float) -> float | None:
    """l1 of the reduced model's lowest Hopf point in 0-400 km/h (the same in every plausible axle)."""
    from axles.units import BAR, KMH
    from bifurcation.equilibria.hopf import find_hopf_points
    from comparisons.api import Axle
    family = Axle(axle).reduced().problem(TyrePressures(right * BAR, left * BAR))
    points = find_hopf_points(family, family.nominal, 0.0, 400.0 * KMH)
    return points[0].first_lyapunov if points else None


def full_geometry_smooth(axle: AxleData, right: float, left: float) -> bool | None:
    """Whether the axle's full geometry is twice differentiable at straight running (at 40 km/h), so that the l1
    the onsets are counted by is that of a smooth normal form."""
    from axles.units import BAR, KMH
    from comparisons.api import Axle
    family = Axle(axle).mbs("full").problem(TyrePressures(right * BAR, left * BAR))
    return family.twice_differentiable(np.zeros(family.n), 40.0 * KMH, family.nominal)


def run_robustness(axle: AxleData, out_dir: str, samples: int, *,
                   pressures: tuple[tuple[float, float], ...] | None = None, seed: int = SEED,
                   margin_speeds: int = MARGIN_SPEEDS_FULL,
                   scheduler: str | None = None, workers: int | None = None, processes: bool = True,
                   message=lambda text: None) -> list[PressureStudy]:
    """One sweep per (right, left) pressure pair over the plausible dimensions; Parquet files
    ``robustness_<p>bar.parquet`` (``robustness_1.5bar.parquet``) in ``out_dir``."""
    from comparisons.sweeps.run import DaskCluster, run_sweep
    design = make_design(plausible_variations(axle), samples, seed, "sobol")
    studies = []
    with DaskCluster(scheduler, workers, processes) as cluster:   # one cluster for every pressure
        for right, left in pressures or robustness_pressures(axle):
            label = pressure_label(right, left)
            message(f"Robustness: {samples} plausible axles at {label}")
            task = SweepTask(axle=axle, effects=(), pressure_right_bar=right, pressure_left_bar=left,
                             names=design.names, compute=("hopf", "margins"), mbs=("reduced", "full"),
                             margin_speeds=margin_speeds, mbs_lyapunov=("full",), mbs_onset=("full",))
            from comparisons.verify.file_names import case_file_name
            path = os.path.join(out_dir, case_file_name("robustness", "parquet", right, left))
            if os.path.isdir(path + ".parts"):   # left by an interrupted verify: its outputs are made afresh
                shutil.rmtree(path + ".parts")
            run = run_sweep(task, design, path, cluster=cluster)
            studies.append(PressureStudy(right, left, design, run.table, os.path.basename(path),
                                         reduced_onset_l1(axle, right, left),
                                         full_geometry_smooth(axle, right, left)))
    return studies


def _pct(x: float) -> str:
    return f"{100 * x:.0f} %"


def study_rows(studies: list[PressureStudy]) -> list[Row]:
    rows = []
    for s in studies:
        n = len(s.column("status"))   # axles that exist
        worst = s.worst_reduced_fidelity_error()
        ok = worst <= HOPF_TOL_KMH and s.failed == 0
        if s.impossible:
            first = s.impossible[0].split(": ", 1)[1]
            rows.append(Row({"case": s.label, "quantity": "sampled axles that cannot exist",
                             "plausible_axles": f"{len(s.impossible)} of {s.table.num_rows} excluded"},
                            CheckStatus.INFO, f"e.g. {first}"))
        rows.append(Row({"case": s.label, "quantity": "MBS with every assumption on = reduced model",
                         "reduced_value": f"{len(s.reduced_points())} Hopf points",
                         "plausible_axles": f"max abs diff {worst:.2g} km/h in {n} axles"},
                        CheckStatus.PASS if ok else CheckStatus.FAIL,
                        "" if ok else (f"{s.failed} samples failed" if s.failed else
                                       f"differs by more than {HOPF_TOL_KMH} km/h")))
        rows += margin_rows(s)
        rows.append(onset_row(s))
        present = {m for _, m in s.reduced_points()}
        for mode in ("yaw", "tramp"):
            rows.append(Row({"case": s.label, "quantity": f"{mode} mode present (full geometry)",
                             "reduced_value": "yes" if mode in present else "no",
                             "plausible_axles": f"{_pct(s.mode_fraction(mode))} of {n} axles"}, CheckStatus.INFO))
        for i, (speed, mode) in enumerate(s.reduced_points()):
            y = s.shifts(i)
            have = np.isfinite(y)
            cells = {"case": s.label, "quantity": f"HB{i + 1} ({mode}) shift, full geometry",
                     "reduced_value": f"{speed:.2f} km/h"}
            if have.any():
                p5, p50, p95 = np.quantile(y[have], QUANTILES)
                top = s.most_influential(i)
                cells["plausible_axles"] = (f"{p50:+.1f} km/h (5-95 %: {p5:+.1f} to {p95:+.1f}); partner in "
                                            f"{_pct(have.mean())}")
                note = f"most influential: {top[0]} (SRC {top[1]:+.2f})" if top else ""
            else:
                cells["plausible_axles"] = "no partner in any axle: the mode vanishes with the full geometry"
                note = ""
            rows.append(Row(cells, CheckStatus.INFO, note))
    return rows


def onset_row(s: PressureStudy) -> Row:
    """Soft or hard onset of the full geometry's shimmy over the plausible axles, at its lowest Hopf point (a
    one-step branch with its end segment where its right-hand side has a kink, l1 where it has none); the reduced
    model's for comparison (one verdict: it does not depend on the dimensions)."""
    from comparisons.studies.onset import JUMP_TOL_DEG
    counts = s.onsets()
    n = sum(counts.values())
    l1 = s.reduced_onset_l1
    kind = onset_kind(l1_onset(l1), l1 is not None)
    jumps = s.kink_jumps()
    reduced = {"soft": "soft (HB1 supercritical", "hard": "hard (HB1 subcritical", "none": "no Hopf point",
               "undetermined": "undetermined (l1"}[kind] + (f", l1 = {l1:.3g})" if l1 is not None else "")
    share = {k: (v / n if n else math.nan) for k, v in counts.items()}
    text = ", ".join(f"{label} in {_pct(share[k])}" for k, label in
                     (("soft", "soft"), ("hard", "hard"), ("none", "no Hopf point"),
                      ("undetermined", "undetermined")) if k != "undetermined" or counts[k]) + f" of {n} axles"
    with_hopf = counts["soft"] + counts["hard"]
    note = (f"of the {with_hopf} axles whose straight running loses stability: {_pct(counts['soft'] / with_hopf)} "
            f"soft, {_pct(counts['hard'] / with_hopf)} hard" if with_hopf else "")
    if jumps:
        note += (f"; {len(jumps)} of the soft ones are subcritical at the camber kink, their small unstable cycles "
                 f"folding back at {min(jumps):.2g}-{max(jumps):.2g} deg (below {JUMP_TOL_DEG:g} deg: a jump of that "
                 f"size, soft in practice)")
    from comparisons.sweeps.sample import ONSET_WINDOW_BUDGET_S
    windows = s.onset_windows()
    if counts["hard"]:
        widths = [b - a for a, b in windows["window"]]
        note += (f"; bistable window next to a hard onset (its branch over the side where straight running is stable, "
                 f"windows from 0.5 km/h): {len(widths)} of {counts['hard']}"
                 + (f", {min(widths):.2f}-{max(widths):.2f} km/h wide" if widths else "")
                 + (f"; {len(windows['none'])} without one (no stable cycle on that side of the branch)"
                    if windows["none"] else "")
                 + (f"; {len(windows['no_stable_side'])} with straight running unstable on both sides"
                    if windows["no_stable_side"] else "")
                 + (f"; {len(windows['incomplete'])} not known (the branch stopped early, or ran past its "
                    f"{ONSET_WINDOW_BUDGET_S:g} s budget)" if windows["incomplete"] else ""))
    if s.full_smooth is False:
        note += ("; " if note else "") + ("the full geometry has a kink at straight running (its camber force), "
                                          "where l1 is no criticality: each onset is read from a one-step cycle "
                                          "branch with its end segment")
    # the counts as numbers too (verify --json); reduced_* are the reduced model's, the same in every axle
    return Row({"case": s.label, "quantity": "onset of shimmy, full geometry: soft (from zero, or a jump below "
                                             f"{JUMP_TOL_DEG:g} deg) or hard, at the lowest Hopf point",
                "reduced_value": reduced, "plausible_axles": text,
                "samples": n, **{f"{k}_count": v for k, v in counts.items()},
                "kink_jump_count": len(jumps), "kink_jump_max_deg": max(jumps) if jumps else None,
                "onset_window_count": len(windows["window"]), "onset_windows_kmh": windows["window"],
                "onset_window_unknown": len(windows["incomplete"]),
                **{f"{k}_share": share[k] for k in ("soft", "hard")},
                "reduced_onset": kind, "reduced_onset_l1": l1}, CheckStatus.INFO, note)


def shimmy_share(s: PressureStudy):
    """The share of the plausible axles whose full geometry shimmies at this case (its minimum margin over the
    speeds negative), for the verdict; None when no axle has an oscillating mode."""
    from comparisons.verify.verdict import RobustnessShare
    full = s.margins("mbs_full_")
    have = np.isfinite(full)
    if not have.any():
        return None
    return RobustnessShare(s.label, float(np.mean(full[have] < 0)), int(have.sum()))


def margin_rows(s: PressureStudy) -> list[Row]:
    """The minimum margin over the coarse speed grid: the check that the dimensions do not enter with every
    assumption on, and its spread with the full geometry."""
    worst = s.worst_reduced_fidelity_margin_error()
    ok = worst <= MARGIN_TOL
    reduced = s.margins("")
    speeds, modes = s.column("margin_kmh"), s.column("margin_mode")
    value = ("-" if not reduced.size or np.isnan(reduced[0]) else
             f"{reduced[0]:+.4f} at {speeds[0]:.0f} km/h ({modes[0]})")
    rows = [Row({"case": s.label, "quantity": "minimum margin: MBS with every assumption on = reduced model",
                 "reduced_value": value, "plausible_axles": f"max abs diff {worst:.2g} in {len(reduced)} axles"},
                CheckStatus.PASS if ok else CheckStatus.FAIL, "" if ok else f"differs by more than {MARGIN_TOL:g}")]
    full = s.margins("mbs_full_")
    have = np.isfinite(full)
    cells = {"case": s.label, "quantity": "minimum margin, full geometry (least damping ratio)",
             "reduced_value": value}
    if have.any():
        p5, p50, p95 = np.quantile(full[have], QUANTILES)
        cells["plausible_axles"] = (f"{p50:+.4f} (5-95 %: {p5:+.4f} to {p95:+.4f}); negative (shimmy) in "
                                    f"{_pct(float(np.mean(full[have] < 0)))}")
    else:
        cells["plausible_axles"] = "no oscillating mode in any axle"
    rows.append(Row(cells, CheckStatus.INFO))
    return rows


def planned_pressures(ctx: Context) -> tuple[tuple[float, float], ...] | None:
    """The first two symmetric cases of verify's plan where the reduced model shimmies, and its asymmetric case."""
    if ctx.plan is None:
        return None
    cases = shimmy_cases(ctx)
    pairs = [(c.pressure_right_bar, c.pressure_left_bar) for c in cases if c.kind is not CaseKind.ASYMMETRIC][:2]
    pairs += [(c.pressure_right_bar, c.pressure_left_bar) for c in cases if c.kind is CaseKind.ASYMMETRIC]
    return tuple(dict.fromkeys(pairs)) or None


def plot_robustness(studies: list[PressureStudy], path: str) -> None:
    """Per case: the full geometry's Hopf speeds over the plausible axles (one dot per axle and point, by
    frequency) against the reduced model's (vertical lines)."""
    from matplotlib.figure import Figure

    from comparisons.files import atomic_path
    fig = Figure(figsize=(5.2 * len(studies), 3.8))
    axes = fig.subplots(1, len(studies), squeeze=False)
    for ax, s in zip(axes[0], studies):
        for speed, mode in s.reduced_points():
            ax.axvline(speed, color="tab:red" if mode == "tramp" else "tab:blue", lw=1.2, ls="--")
        for k, (speeds, hz, modes) in enumerate(zip(s.column("mbs_full_hopf_kmh"), s.column("mbs_full_hopf_hz"),
                                                    s.column("mbs_full_hopf_mode"))):
            colours = ["tab:red" if m == "tramp" else "tab:blue" for m in modes]
            ax.scatter(speeds, hz, s=8, c=colours, alpha=0.5, linewidths=0)
        n = len(s.column("status"))
        if not any(s.column("mbs_full_hopf_kmh")):
            ax.text(200, 8, "no full-geometry Hopf point\nin any plausible axle", ha="center", va="center")
        ax.set_ylim(0, 16)
        ax.set_title(f"{s.label}: full geometry in {n} plausible axles (dots),\nreduced model (dashed); "
                     f"blue yaw, red tramp", fontsize=9)
        ax.set_xlim(0, 400)
        ax.set_xlabel("Hopf speed [km/h]")
        ax.set_ylabel("frequency [Hz]")
    fig.tight_layout()
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=100, format="png")


def robustness_section(ctx: Context) -> Section:
    """The ``shimmy verify`` section for the context's axle."""
    axle = ctx.axle
    samples = SAMPLES_QUICK if ctx.quick else SAMPLES_FULL
    # quick: a few dozen samples, less work than starting worker processes; one worker in this process
    margin_speeds = MARGIN_SPEEDS_QUICK if ctx.quick else MARGIN_SPEEDS_FULL
    studies = run_robustness(axle, ctx.out, samples, pressures=planned_pressures(ctx), processes=not ctx.quick,
                             margin_speeds=margin_speeds, message=ctx.progress)
    names = ", ".join(studies[0].design.names)
    plot_robustness(studies, os.path.join(ctx.out, FIGURE))
    return Section(
        verdict_facts=tuple(share for s in studies for share in [shimmy_share(s)] if share is not None),
        key="robustness", title="Robustness: the full-geometry verdicts over plausible multibody dimensions",
        columns=("case", "quantity", "reduced_value", "plausible_axles"), rows=tuple(study_rows(studies)),
        figures=(FIGURE,),
        text=(f"{samples} plausible axles at the planned cases: {names} drawn uniformly from each one's plausible range (axle file "
              f"`[plausible]`, scrambled Sobol' sample, seed {SEED}), the same axles at each pressure; MBS Hopf points "
              f"with every assumption on and off, 0-400 km/h, computed by `shimmy sweep` on a local Dask cluster "
              f"(results: {', '.join(f'`{s.file}`' for s in studies)}). Check: with every assumption on the MBS keeps "
              f"the reduced model's Hopf points to {HOPF_TOL_KMH} km/h and its minimum margin (least damping ratio of "
              f"straight running on {margin_speeds} speeds in 0.5-400 km/h) to {MARGIN_TOL:g} in every axle. "
              f"Information: how often each mode exists with the full geometry, each Hopf point's shift (median, "
              f"5-95 %) and the dimension its shift depends on most (standardized regression coefficient), and the "
              f"full geometry's minimum margin (median, 5-95 %, share of axles where it is negative), and in what "
              f"share of the axles its shimmy sets in softly (the amplitude grows from zero, or jumps by less than a "
              f"twentieth of a degree) or jumps in, at its lowest Hopf point: where the full geometry's right-hand "
              f"side has a kink at straight running (its camber force) from a one-step cycle branch with the folds "
              f"between it and the Hopf point, elsewhere from l1, beside the reduced model's (l1)."))
