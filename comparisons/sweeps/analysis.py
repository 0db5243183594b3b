"""What a sweep tells: sensitivity of an output to each varied input, stability maps and a tornado chart.

Sensitivity: with ``--design saltelli`` (and every sample giving the output) Sobol' first-order and total indices
from :func:`SALib.analyze.sobol.analyze` (Saltelli et al. 2010 estimators, bootstrap confidence intervals);
otherwise standardized regression coefficients SRC_j = b_j sd(x_j) / sd(y) of a least-squares linear fit
(Saltelli et al., Global Sensitivity Analysis: The Primer, 2008, section 1.2.5), with the fit's R^2, which says how
much of the variance a linear model explains (SRC_j^2 sums to about R^2 for independent inputs).

The tornado chart shows for each input the change of the output, by that linear fit, as the input goes from its
5th to its 95th percentile with the others at their means.  The stability map shades, over the first varied
input and speed, the fraction of samples whose straight running is unstable (0 or 1 on a one-input grid), with
the reduced model's Hopf curves from continuation (:func:`bifurcation.equilibria.hopf_curves.hopf_diagram`, other inputs at
the base axle) drawn over it; with two or more inputs a second map shows the shimmy onset speed over the first two.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field

import numpy as np
import pyarrow as pa

from axles.limits import UsageError
from comparisons.sweeps.design import Design
from comparisons.sweeps.sample import SweepTask
from axles.pressures import TyrePressures
from comparisons.api import family_of

DEFAULT_OUTPUT = "onset_kmh"
# The output of the sensitivities when --output is not given: that of the first of these that --compute asks for.
DEFAULT_OUTPUTS = {"hopf": DEFAULT_OUTPUT, "cycles": "peak_yaw_theta1_deg", "margins": "margin",
                   "assumptions": "shift_full_kmh[0]"}
SWING_QUANTILES = (0.05, 0.95)


@dataclass(frozen=True)
class OutputChoice:
    """A numeric output column, or element ``index`` of a list column (``hopf_kmh[0]``)."""

    column: str
    index: int | None = None

    @property
    def label(self) -> str:
        return self.column if self.index is None else f"{self.column}[{self.index}]"

    @classmethod
    def parse(cls, text: str | None, task: SweepTask) -> "OutputChoice":
        text = text or next(DEFAULT_OUTPUTS[c] for c in DEFAULT_OUTPUTS if c in task.compute)
        m = re.fullmatch(r"\s*([A-Za-z0-9_]+)\s*(?:\[\s*(\d+)\s*\])?\s*", text)
        schema = task.schema()
        if not m or m.group(1) not in schema.names:
            numeric = [f.name for f in schema if f.name not in task.names and
                       (pa.types.is_floating(f.type) or pa.types.is_integer(f.type) or
                        (pa.types.is_list(f.type) and pa.types.is_floating(f.type.value_type)))
                       and f.name not in ("sample", "batch")]
            raise UsageError(f"--output: '{text}' is not an output of this sweep (numeric: {', '.join(numeric)})")
        typ = schema.field(m.group(1)).type
        index = None if m.group(2) is None else int(m.group(2))
        if pa.types.is_list(typ) != (index is not None):
            raise UsageError(f"--output {text}: " + ("a list column needs an index, e.g. "
                                                     f"{m.group(1)}[0]" if index is None else "not a list column"))
        if not (pa.types.is_floating(typ) or pa.types.is_integer(typ) or
                (pa.types.is_list(typ) and pa.types.is_floating(typ.value_type))):
            raise UsageError(f"--output {text}: not a numeric column")
        return cls(m.group(1), index)

    def values(self, table: pa.Table) -> np.ndarray:
        """One float per row, NaN where the sample failed or has no such value."""
        col = table.column(self.column).to_pylist()
        if self.index is not None:
            col = [v[self.index] if v is not None and len(v) > self.index else None for v in col]
        return np.array([math.nan if v is None else float(v) for v in col])


@dataclass(frozen=True)
class Sensitivity:
    output: str
    method: str                          # "sobol", "src" or "none"
    names: tuple[str, ...]
    used: int                            # samples with a value of the output
    total: int
    indices: dict = field(default_factory=dict)    # name -> {"S1", "S1_conf", "ST", "ST_conf"} or {"src"}
    r2: float | None = None
    swing: dict = field(default_factory=dict)      # name -> (output at 5th, at 95th percentile of the input)
    centre: float | None = None
    note: str = ""

    def to_json(self) -> dict:
        return {"output": self.output, "method": self.method, "samples_used": self.used, "samples": self.total,
                "r2": self.r2, "indices": self.indices,
                "tornado": {k: {"low_input": v[0], "high_input": v[1]} for k, v in self.swing.items()},
                "centre": self.centre, "note": self.note}

    def lines(self) -> list[str]:
        head = f"sensitivity of {self.output} ({self.used} of {self.total} samples have it)"
        if self.method == "none":
            return [f"{head}: {self.note}"]
        out = [head + (f", {self.note}" if self.note else "") + ":"]
        for n in sorted(self.names, key=lambda n: -abs(self._key(n))):
            ix = self.indices[n]
            lo, hi = self.swing.get(n, (math.nan, math.nan))
            if self.method == "sobol":
                text = (f"S1 = {ix['S1']:+.3f} +- {ix['S1_conf']:.3f}, ST = {ix['ST']:.3f} +- {ix['ST_conf']:.3f}")
            else:
                text = f"SRC = {ix['src']:+.3f}"
            out.append(f"  {n:28s} {text}   5-95 % swing {hi - lo:+.4g}")
        if self.method == "src":
            out.append(f"  linear fit R^2 = {self.r2:.3f}" + ("  (below 0.7: the output is far from linear in the "
                                                              "inputs; SRC ranks only roughly)" if self.r2 < 0.7
                                                             else ""))
        return out

    def _key(self, name: str) -> float:
        ix = self.indices[name]
        return ix.get("ST", ix.get("src", 0.0))


def _linear_fit(X: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, float]:
    """(coefficients b of y ~ a + X b, R^2)."""
    A = np.column_stack([np.ones(len(y)), X])
    coef, *_ = np.linalg.lstsq(A, y, rcond=None)
    resid = y - A @ coef
    ss = float(np.sum((y - y.mean()) ** 2))
    return coef[1:], (1.0 - float(np.sum(resid ** 2)) / ss) if ss > 0 else math.nan


def sensitivity(table: pa.Table, design: Design, output: OutputChoice) -> Sensitivity:
    """Sobol' indices when the design is Saltelli's and complete, else standardized regression coefficients."""
    names = design.names
    X = np.column_stack([table.column(n).to_numpy() for n in names])
    y = output.values(table)
    ok = np.isfinite(y)
    base = dict(output=output.label, names=names, used=int(ok.sum()), total=len(y))
    if ok.sum() < len(names) + 2:
        return Sensitivity(method="none", note="too few samples have this output for a sensitivity estimate",
                           **base)
    Xo, yo = X[ok], y[ok]
    sd_x, sd_y = Xo.std(axis=0), yo.std()
    if sd_y == 0.0:
        return Sensitivity(method="none", note="the output does not change over the sweep", **base)
    b, r2 = _linear_fit(Xo, yo)
    lo_q, hi_q = np.quantile(Xo, SWING_QUANTILES, axis=0)
    centre = float(yo.mean())
    swing = {n: (centre + b[j] * (lo_q[j] - Xo[:, j].mean()), centre + b[j] * (hi_q[j] - Xo[:, j].mean()))
             for j, n in enumerate(names)}
    swing = {n: (float(a), float(c)) for n, (a, c) in swing.items()}
    if design.kind == "saltelli" and ok.all():
        from SALib.analyze import sobol
        problem = {"num_vars": len(names), "names": list(names),
                   "bounds": [list(v.bounds) for v in design.variations]}
        si = sobol.analyze(problem, y, calc_second_order=False, seed=design.seed or 0)
        indices = {n: {k: float(si[k][j]) for k in ("S1", "S1_conf", "ST", "ST_conf")} for j, n in enumerate(names)}
        return Sensitivity(method="sobol", indices=indices, r2=r2, swing=swing, centre=centre,
                           note=f"Sobol' indices (SALib, {design.base_samples} base samples)", **base)
    note = "" if design.kind != "saltelli" else "some samples lack the output: SRC instead of Sobol' indices"
    indices = {n: {"src": float(b[j] * sd_x[j] / sd_y) if sd_x[j] > 0 else 0.0} for j, n in enumerate(names)}
    return Sensitivity(method="src", indices=indices, r2=r2, swing=swing, centre=centre, note=note, **base)


# --- figures ------------------------------------------------------------------------------------------------

def _unit(name: str) -> str:
    from axles.axle import interface_unit
    return interface_unit(name)[0]


def _continuation_curves(task: SweepTask, name: str, lo: float, hi: float):
    """Hopf curves of the reduced model over input ``name`` (interface units) at the base axle, or None when the
    reduced model does not depend on it (a multibody dimension)."""
    from axles.axle import entry
    from axles.units import BAR, KMH
    from bifurcation.equilibria.hopf_curves import hopf_diagram
    from reduced_model.model import Effects, ShimmyModel
    if name in ("pressure", "pressure_left", "pressure_right"):
        factor = BAR
    elif entry(name).section == "table1":
        factor = entry(name).to_si(1.0)
    else:
        return None
    r, l = task.pressure_right_bar * BAR, task.pressure_left_bar * BAR
    family = family_of(ShimmyModel(task.axle.params, Effects.parse(task.effects)), TyrePressures(r, l), name,
                       task.braking)
    diagram = hopf_diagram(family, lo * factor, hi * factor, 0.0, task.vmax_kmh * KMH)
    return [(c.qs / factor, c.ps / KMH) for c in diagram.curves]


def stability_fraction(table: pa.Table, name: str, edges: np.ndarray, speeds: np.ndarray) -> np.ndarray:
    """Fraction of the (successful) samples in each bin of input ``name`` unstable at each speed (km/h):
    shape (len(speeds), len(edges) - 1), NaN for an empty bin."""
    x = table.column(name).to_numpy()
    ok = np.array([s == "ok" for s in table.column("status").to_pylist()])
    lo_l, hi_l = table.column("unstable_from_kmh").to_pylist(), table.column("unstable_to_kmh").to_pylist()
    count = np.zeros((len(speeds), len(edges) - 1))
    seen = np.zeros(len(edges) - 1)
    k = np.clip(np.searchsorted(edges, x, side="right") - 1, 0, len(edges) - 2)
    for i in np.nonzero(ok)[0]:
        seen[k[i]] += 1
        for a, b in zip(lo_l[i], hi_l[i]):
            count[(speeds >= a) & (speeds <= b), k[i]] += 1
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(seen > 0, count / np.maximum(seen, 1), np.nan)


def _bin_edges(values: np.ndarray, design: Design, j: int) -> np.ndarray:
    v = design.variations[j]
    if v.kind == "grid":
        g = v.grid()
        if len(g) == 1:
            return np.array([g[0] - 0.5, g[0] + 0.5])
        mid = 0.5 * (g[1:] + g[:-1])
        return np.concatenate([[g[0] - (mid[0] - g[0])], mid, [g[-1] + (g[-1] - mid[-1])]])
    lo, hi = np.nanmin(values), np.nanmax(values)
    bins = int(np.clip(math.sqrt(len(values)) / 2, 5, 60))
    return np.linspace(lo, hi, bins + 1)


def draw_stability_map(ax, table: pa.Table, design: Design, task: SweepTask) -> None:
    name = design.names[0]
    x = table.column(name).to_numpy()
    edges = _bin_edges(x, design, 0)
    speed_edges = np.linspace(0.0, task.vmax_kmh, 401)
    frac = stability_fraction(table, name, edges, 0.5 * (speed_edges[1:] + speed_edges[:-1]))
    mesh = ax.pcolormesh(edges, speed_edges, frac, cmap="Reds", vmin=0.0, vmax=1.0, shading="flat")
    ax.figure.colorbar(mesh, ax=ax, label="fraction of samples unstable" if len(design.names) > 1 or
                       design.kind != "grid" else "unstable (1) / stable (0)")
    curves = _continuation_curves(task, name, float(edges[0]), float(edges[-1]))
    for i, (q, v) in enumerate(curves or []):
        ax.plot(q, v, "k-", lw=1.2, label="Hopf curves, continuation (base axle)" if i == 0 else None)
    if curves:
        ax.legend(loc="upper right", fontsize=8)
    ax.set_xlim(edges[0], edges[-1])
    ax.set_ylim(0.0, task.vmax_kmh)
    ax.set_xlabel(f"{name} ({_unit(name)})")
    ax.set_ylabel("speed (km/h)")
    others = ", ".join(design.names[1:])
    ax.set_title("Straight running unstable (shaded)" + (f"\nover all samples of {others}" if others else ""),
                 fontsize=10)


def draw_onset_map(ax, table: pa.Table, design: Design, task: SweepTask) -> None:
    """Lowest Hopf speed over the first two inputs; hollow markers: no shimmy in the speed window; x: failed."""
    a, b = design.names[:2]
    x, y = table.column(a).to_numpy(), table.column(b).to_numpy()
    status = np.array([s == "ok" for s in table.column("status").to_pylist()])
    onset = np.array([math.nan if v is None else v for v in table.column("onset_kmh").to_pylist()])
    has = status & np.isfinite(onset)
    size = max(4.0, min(40.0, 6000.0 / max(len(x), 1)))
    lo, hi = (float(np.min(onset[has])), float(np.max(onset[has]))) if has.any() else (0.0, task.vmax_kmh)
    sc = ax.scatter(x[has], y[has], c=onset[has], s=size, cmap="viridis_r", vmin=lo, vmax=max(hi, lo + 1e-9),
                    linewidths=0)
    ax.scatter(x[status & ~has], y[status & ~has], s=size, facecolors="none", edgecolors="0.5", linewidths=0.5,
               label="no Hopf point in the window")
    if (~status).any():
        ax.scatter(x[~status], y[~status], s=size * 1.5, marker="x", c="k", linewidths=0.8, label="failed")
    ax.figure.colorbar(sc, ax=ax, label="shimmy onset: lowest Hopf speed (km/h)")
    ax.set_xlabel(f"{a} ({_unit(a)})")
    ax.set_ylabel(f"{b} ({_unit(b)})")
    ax.set_title("Shimmy onset speed", fontsize=10)
    if (status & ~has).any() or (~status).any():
        ax.legend(loc="upper right", fontsize=8)


def draw_tornado(ax, sens: Sensitivity) -> None:
    names = sorted(sens.swing, key=lambda n: abs(sens.swing[n][1] - sens.swing[n][0]))
    for i, n in enumerate(names):
        lo, hi = sens.swing[n]
        ax.barh(i, hi - sens.centre, left=sens.centre, color="tab:red", label="input at 95th percentile" if i == 0
                else None)
        ax.barh(i, lo - sens.centre, left=sens.centre, color="tab:blue", label="input at 5th percentile" if i == 0
                else None)
    ax.axvline(sens.centre, color="k", lw=0.8)
    ax.set_yticks(range(len(names)), [f"{n} ({_unit(n)})" for n in names], fontsize=8)
    ax.set_xlabel(sens.output)
    method = {"sobol": "Sobol'", "src": "SRC"}[sens.method]
    r2 = f", linear fit R² = {sens.r2:.2f}" if sens.r2 is not None else ""
    ax.set_title(f"Tornado: {sens.output}, 5-95 % of each input\n(linear fit over {sens.used} samples{r2}; "
                 f"{method})", fontsize=9)
    ax.legend(loc="lower right", fontsize=8)


def write_plot(path: str, table: pa.Table, design: Design, task: SweepTask, output: OutputChoice,
               sens: Sensitivity) -> None:
    from matplotlib.figure import Figure

    from comparisons.files import atomic_path
    panels = []
    if "hopf" in task.compute:
        panels.append("map")
        if len(design.names) >= 2:
            panels.append("onset")
    if sens.method != "none" and len(design.names) >= 1:
        panels.append("tornado")
    if not panels:
        raise UsageError("--plot: nothing to draw (no Hopf points computed and no sensitivity)")
    fig = Figure(figsize=(5.6 * len(panels), 4.6))
    axes = fig.subplots(1, len(panels), squeeze=False)
    for ax, what in zip(axes[0], panels):
        if what == "map":
            draw_stability_map(ax, table, design, task)
        elif what == "onset":
            draw_onset_map(ax, table, design, task)
        else:
            draw_tornado(ax, sens)
    fig.suptitle(f"shimmy sweep: {len(design)} samples ({design.kind}), {task.axle.name}", fontsize=10)
    fig.tight_layout()
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=110, format="png")
