"""The ``shimmy verify`` section "Stability margins": how far straight running is from shimmy, for both models.

The least damping ratio of straight running (:mod:`bifurcation.equilibria.margins`, the mode named
as ``shimmy modes`` names it) is mapped over the axle's operating window: its pressures (axle file ``[operating]``,
both tyres alike) and the plan's speeds (0.5-400 km/h), for the reduced model (section 3) and the MBS with the full
geometry.  Checks, each of which can fail:

* the MBS with every assumption of the reduced model on has the reduced model's map (:data:`MAP_TOL`, absolute, on
  every node);
* along the speed at the planned cases and at the ends and middle of the pressure window, the zero level of the
  margin (Brent's method between the nodes where it changes sign) lies on the Hopf points of ``hopf_points``
  (:data:`ZERO_RTOL` relative), and every Hopf point across which the margin changes sign is found, for the
  reduced model and the full geometry.  An axle with no Hopf point has a map with no zero level: checked too.

Information: each model's minimum margin over the window with its speed, pressure, frequency and mode.
"""

from __future__ import annotations

import os
from dataclasses import dataclass

import numpy as np

from axles.units import BAR, kmh
from comparisons.margins import MarginPoint
from comparisons.verify.context import Context
from comparisons.verify.plan import VMAX
from comparisons.verify.report import CheckStatus, Column, Row, Section
from bifurcation.equilibria.hopf import hopf_points
from bifurcation.equilibria.margins import least_damped, zero_level
from reduced_model.family import MIN_SPEED

GRID_QUICK = (41, 5)        # speeds, pressures
GRID_FULL = (201, 31)
ZERO_NODES = 201            # speeds bracketing the zero level (quick: ZERO_NODES_QUICK)
ZERO_NODES_QUICK = 101
MAP_TOL = 1e-9
ZERO_RTOL = 1e-6
SIDE = 1e-4                 # relative step beside a Hopf point to read the margin's sign on either side
FIGURE = "margins.png"
COLUMNS = ("model", "case", "quantity", "damping_ratio", "speed_kmh", "pressure_bar", "frequency_hz", "mode")
LABELS = {"model": Column("model"),
          "frequency_hz": Column("frequency of the least damped mode [Hz]", dash="no value in that row"),
          "quantity": Column("what")}


def check_pressures(ctx: Context) -> list[float]:
    """bar: the planned cases with both tyres alike, and the ends and middle of the pressure window (quick: the
    planned cases alone, or the window's ends when none is planned)."""
    lo, hi = ctx.axle.pressure_range_bar
    planned = [c.pressure_right_bar for c in ctx.plan.cases if c.pressure_right_bar == c.pressure_left_bar]
    extra = [lo, hi] if not planned else []
    if not ctx.quick:
        extra = [lo, 0.5 * (lo + hi), hi]
    return sorted({round(float(p), 6) for p in planned + extra})


def zero_level_row(family, title: str, bar: float, nodes: int) -> tuple[Row, list[tuple[float, float]]]:
    """The zero level of the margin along the speed at ``bar`` (bracketed on ``nodes`` speeds) against the Hopf
    points (module docstring)."""
    q = bar * BAR
    hopf = hopf_points(family, q, 0.0, VMAX, lyapunov=False)
    zeros = zero_level(family, q, np.linspace(MIN_SPEED, VMAX, nodes))
    stray = [z for z in zeros if not any(abs(h.p - z) <= ZERO_RTOL * h.p for h in hopf)]
    crossing = [h for h in hopf
                if np.sign(least_damped(family, h.p * (1 - SIDE), q).damping_ratio)
                != np.sign(least_damped(family, h.p * (1 + SIDE), q).damping_ratio)]
    missed = [h for h in crossing if not any(abs(h.p - z) <= ZERO_RTOL * h.p for z in zeros)]
    ok = not stray and not missed
    speeds = ", ".join(f"{kmh(z):.2f}" for z in zeros) or "none"
    if ok and not hopf:
        note = "no Hopf point and no zero level: straight running is damped at every speed"
    elif ok:
        others = len(hopf) - len(crossing)
        note = (f"zero level at {speeds} km/h = the Hopf points (relative {ZERO_RTOL:g})"
                + (f"; {others} Hopf points where another mode is already unstable (the margin stays negative)"
                   if others else ""))
    else:
        note = (f"zero level at {speeds} km/h; not a Hopf point: "
                f"{', '.join(f'{kmh(z):.2f}' for z in stray) or '-'}; Hopf points missed: "
                f"{', '.join(f'{kmh(h.p):.2f}' for h in missed) or '-'} km/h")
    row = Row({"model": title, "case": f"{bar:g} bar", "quantity": "zero level of the margin = Hopf points"},
              CheckStatus.PASS if ok else CheckStatus.FAIL, note)
    return row, [(kmh(h.p), bar) for h in hopf]


def minimum_row(title: str, study) -> Row:
    low = study.minimum
    cells = {"model": title, "case": "operating window", "quantity": "minimum margin"}
    if low is None:
        return Row(cells, CheckStatus.INFO, "no oscillatory mode anywhere in the window")
    where = "shimmy: a mode grows there" if low.damping_ratio < 0 else "every mode damped in the whole window"
    return Row({**cells, "damping_ratio": low.damping_ratio, "speed_kmh": low.speed_kmh,
                "pressure_bar": low.pressure_bar, "frequency_hz": low.frequency_hz, "mode": low.mode},
               CheckStatus.INFO, where)


@dataclass(frozen=True)
class MarginMinimum:
    """One model's least damping ratio over the operating window, as the verdict states it
    (:class:`comparisons.verify.verdict.MarginFact`)."""

    model: str
    point: MarginPoint | None
    window_bar: tuple[float, float]

    def text(self) -> str:
        lo, hi = self.window_bar
        if self.point is None:
            return f"Stability margin of {self.model}: no oscillating mode anywhere in {lo:g}-{hi:g} bar."
        p = self.point
        state = "a mode grows (shimmy)" if p.damping_ratio < 0 else "every mode is damped"
        return (f"Stability margin of {self.model}: least damping ratio {p.damping_ratio:+.4f} over "
                f"{lo:g}-{hi:g} bar and {kmh(MIN_SPEED):g}-{kmh(VMAX):g} km/h, at {p.speed_kmh:.1f} km/h and "
                f"{p.pressure_bar:.2f} bar ({p.mode}, {p.frequency_hz:.2f} Hz): {state}.")

    def to_json(self) -> dict:
        p = self.point
        return {"model": self.model, "damping_ratio": None if p is None else p.damping_ratio,
                "speed_kmh": None if p is None else p.speed_kmh, "pressure_bar": None if p is None else p.pressure_bar,
                "frequency_hz": None if p is None else p.frequency_hz, "mode": None if p is None else p.mode,
                "text": self.text()}


def margins_section(ctx: Context) -> Section:
    from comparisons.api import Axle, stability_margins
    from comparisons.figures.margin_figures import plot_margin_maps
    axle = Axle(ctx.axle)
    n_speeds, n_pressures = GRID_QUICK if ctx.quick else GRID_FULL
    window = ctx.axle.pressure_range_bar
    models = {"reduced": ("reduced model", axle.reduced()),
              "mbs_reduced": ("MBS, reduced model's assumptions", axle.mbs("reduced")),
              "mbs_full": ("MBS, full geometry", axle.mbs("full"))}
    studies = {}
    for key, (title, model) in models.items():
        ctx.progress(f"Stability margins: {title}, {n_speeds} x {n_pressures} grid")
        studies[key] = stability_margins(model, window, kmh(MIN_SPEED), kmh(VMAX), n_pressures, n_speeds).study
    a, b = studies["reduced"].damping_ratio, studies["mbs_reduced"].damping_ratio
    same_nan = bool(np.array_equal(np.isnan(a), np.isnan(b)))
    diff = float(np.nanmax(np.abs(a - b))) if same_nan and np.isfinite(a).any() else np.inf
    ok = same_nan and diff <= MAP_TOL
    rows = [Row({"model": models["mbs_reduced"][0], "case": "operating window",
                 "quantity": "margin map = the reduced model's"}, CheckStatus.PASS if ok else CheckStatus.FAIL,
                f"max |difference| {diff:.2g} on {a.size} nodes (tolerance {MAP_TOL:g})" if same_nan else
                "the models oscillate at different nodes")]
    hopf = {}
    nodes = ZERO_NODES_QUICK if ctx.quick else ZERO_NODES
    for key in ("reduced", "mbs_full"):
        title, model = models[key]
        family = model.problem(model.axle.data.pressure_range_bar[0] * BAR, "pressure")
        found = []
        for bar in check_pressures(ctx):
            ctx.progress(f"Stability margins: zero level at {bar:g} bar, {title}")
            row, points = zero_level_row(family, title, bar, nodes)
            rows.append(row)
            found += points
        hopf[key] = found
    rows += [minimum_row(models[key][0], studies[key]) for key in ("reduced", "mbs_full")]
    plot_margin_maps([(studies[key], f"{models[key][0]}\nblack: zero damping; circles: Hopf points; star: minimum",
                       hopf[key]) for key in ("reduced", "mbs_full")], os.path.join(ctx.out, FIGURE),
                     title=f"Least damping ratio of straight running, axle {ctx.axle.shown_name}")
    lo, hi = window
    where = "(or the ends of the window)" if ctx.quick else "and the ends and middle of the window"
    return Section(
        key="margins", title="Stability margins: the least damping ratio of straight running", columns=COLUMNS,
        rows=tuple(rows), figures=(FIGURE,), labels=LABELS,
        verdict_facts=tuple(MarginMinimum(models[key][0], studies[key].minimum, window)
                            for key in ("reduced", "mbs_full")),
        text=(f"The least damping ratio zeta = -Re(lambda)/|lambda| over the oscillating eigenvalues of straight "
              f"running (real eigenvalues left out), on {n_speeds} speeds in {kmh(MIN_SPEED):g}-{kmh(VMAX):g} km/h x "
              f"{n_pressures} pressures in {lo:g}-{hi:g} bar (the axle's operating window, both tyres alike); "
              f"`shimmy margins` prints the map. Checks: the MBS with every assumption of the reduced model on has "
              f"the reduced model's map to {MAP_TOL:g}; the margin's zero level along the speed (Brent's method "
              f"between {nodes} speeds) is the Hopf points to {ZERO_RTOL:g} relative, at the planned cases {where}, "
              f"for the reduced model and the full geometry. Information: "
              f"each model's minimum over the window, its location to the grid's spacing."))
