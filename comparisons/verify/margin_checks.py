"""The ``shimmy verify`` section "Stability margins": how far straight running is from shimmy, for both models.

The least damping ratio of straight running (:mod:`bifurcation.equilibria.margins`, the mode named
as ``shimmy modes`` names it) is mapped over the axle's operating window: its pressures (axle file ``[operating]``,
both tyres alike) and the plan's speeds (0.5-400 km/h), for the reduced model (section 3) and the MBS with the full
geometry.  Checks, each of which can fail:

* the MBS with every assumption of the reduced model on has the reduced model's map (:data:`MAP_TOL`, absolute, on
  every node);
* along the speed at the planned cases and at the ends and middle of the pressure window, the margin's sign
  against the Hopf points of ``find_hopf_points`` (the truth, from continuation of the eigenvalues): read on both sides of
  every Hopf point, at the middle of every interval between neighbouring ones, however narrow, and at the map's
  speeds (no root is searched between grid nodes, which missed a stable window narrower than the grid's step), no
  oscillating pair crosses the imaginary axis inside an interval and one does across each Hopf point; for the
  reduced model and the full geometry.  A growing pair that meets the real axis (a divergence) changes the margin's
  sign without a Hopf point: the row says so, it is no failure.

Information: each model's minimum margin over the window with its speed, pressure, frequency and mode.
"""

from __future__ import annotations

import os
from dataclasses import dataclass

import numpy as np

from axles.pressures import TyrePressures
from axles.units import BAR, kmh
from comparisons.studies.margin_study import MarginPoint
from comparisons.verify.context import Context
from comparisons.verify.plan import VMAX
from comparisons.verify.report import CheckStatus, Column, Row, Section
from bifurcation.equilibria.hopf import find_hopf_points
from bifurcation.equilibria.margins import IMAG_RTOL, least_damped
from reduced_model.family import MIN_SPEED

GRID_QUICK = (41, 5)        # speeds, pressures
GRID_FULL = (201, 31)
MAP_TOL = 1e-9
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


def _side(hopf: list[float], i: int) -> float:
    """How far beside the i-th Hopf point (m/s) its two sides are read: SIDE relative, but never past a quarter of
    the gap to a neighbour, so that the sides of two Hopf points however close lie between them."""
    gaps = [hopf[i] - hopf[i - 1] if i > 0 else hopf[i] - MIN_SPEED,
            hopf[i + 1] - hopf[i] if i + 1 < len(hopf) else VMAX - hopf[i]]
    return min([SIDE * hopf[i]] + [0.25 * g for g in gaps if g > 0.0])


def margin_samples(hopf: list[float], grid=()) -> list[list[float]]:
    """The speeds (m/s) where the margin's sign is read, one list per interval between neighbouring Hopf points
    (and the ends of the speed window): just after the Hopf point that opens it, its middle, just before the one
    that closes it, however narrow the interval, and the ``grid`` speeds inside it (a sign read there, never a root
    searched between them)."""
    edges = [MIN_SPEED] + hopf + [VMAX]
    out = []
    for k, (a, b) in enumerate(zip(edges[:-1], edges[1:])):
        first = a + _side(hopf, k - 1) if k > 0 else a
        last = b - _side(hopf, k) if k < len(hopf) else b
        inside = sorted({first, 0.5 * (a + b), last} | {float(v) for v in grid if first < v < last})
        out.append(inside)
    return out


@dataclass(frozen=True)
class Sample:
    """The margin's sign at one speed, how many oscillating pairs of straight running grow there and how many
    eigenvalues in all (real ones too) lie in the right half-plane."""

    speed: float            # m/s
    damping_ratio: float    # NaN: nothing oscillates (counted as damped)
    growing_pairs: int
    growing: int            # eigenvalues with Re > 0, a pair counting two

    @property
    def negative(self) -> bool:
        return self.damping_ratio < 0.0


def sample(family, speed: float, q: float) -> Sample:
    A = family.linear_matrix(speed, q)
    margin = least_damped(family, speed, q, A=A, vector=False)
    lam = np.linalg.eigvals(A)
    radius = float(np.max(np.abs(lam))) if lam.size else 0.0
    pairs = int(np.sum((lam.imag > IMAG_RTOL * radius) & (lam.real > 0.0)))
    return Sample(speed, margin.damping_ratio, pairs, int(np.sum(lam.real > 0.0)))


def crossed(a: Sample, b: Sample) -> bool:
    """Between two samples an oscillating pair crossed the imaginary axis: the growing pairs and the growing
    eigenvalues change together, two eigenvalues a pair.  (A growing pair that meets the real axis and splits into
    two real eigenvalues, or a real eigenvalue through zero, changes the margin's sign or the pair count without a
    Hopf point: the margin leaves real eigenvalues out.)"""
    return a.growing_pairs != b.growing_pairs and b.growing - a.growing == 2 * (b.growing_pairs - a.growing_pairs)


def hopf_sign_row(family, title: str, bar: float, grid=()) -> tuple[Row, list[tuple[float, float]]]:
    """The margin's sign against the Hopf points at ``bar`` (module docstring): the Hopf points of ``find_hopf_points``
    are the truth; in no interval between them does an oscillating pair cross the imaginary axis, and across every
    Hopf point one does (the growing pairs change by one, the growing eigenvalues by two)."""
    q = bar * BAR
    points = find_hopf_points(family, q, 0.0, VMAX, lyapunov=False)
    hopf = sorted(h.p for h in points)
    intervals = [[sample(family, v, q) for v in speeds] for speeds in margin_samples(hopf, grid)]
    missed = [(a.speed, b.speed) for iv in intervals for a, b in zip(iv[:-1], iv[1:]) if crossed(a, b)]
    split = [(a.speed, b.speed) for iv in intervals for a, b in zip(iv[:-1], iv[1:])
             if a.negative != b.negative and not crossed(a, b)]
    unchanged = [h for h, before, after in zip(hopf, intervals[:-1], intervals[1:])
                 if not (abs(before[-1].growing_pairs - after[0].growing_pairs) == 1 and crossed(before[-1], after[0]))]
    ok = not missed and not unchanged
    edges = [MIN_SPEED] + hopf + [VMAX]
    calm = [(a, b) for a, b, iv in zip(edges[:-1], edges[1:], intervals) if not any(s.negative for s in iv)]
    where = ", ".join(f"{kmh(a):.2f}-{kmh(b):.2f}" for a, b in calm)
    calm_text = f"no oscillation grows at {where} km/h" if calm else "an oscillation grows at every speed"
    also = "".join(f"; the margin changes sign within {kmh(a):.2f}-{kmh(b):.2f} km/h where a growing pair meets the "
                   f"real axis (a divergence, not a Hopf point)" for a, b in split)
    if ok and not hopf:
        note = ("no Hopf point, and no oscillating pair crosses the imaginary axis from the lowest to the highest "
                "speed: " + ("straight running is damped at every speed" if not any(s.growing for s in intervals[0])
                             else calm_text))
    elif ok:
        note = (f"the margin read on both sides of each of the {len(hopf)} Hopf points and in the middle of each "
                f"interval between them agrees with them: {calm_text}")
    else:
        note = "; ".join(
            [f"an oscillating pair crosses the imaginary axis within {kmh(a):.2f}-{kmh(b):.2f} km/h, between Hopf "
             f"points (a Hopf point the continuation did not find)" for a, b in missed] +
            [f"no pair of eigenvalues crosses at the Hopf point {kmh(h):.2f} km/h" for h in unchanged])
    row = Row({"model": title, "case": f"{bar:g} bar", "quantity": "sign of the margin = Hopf points"},
              CheckStatus.PASS if ok else CheckStatus.FAIL, note + also)
    return row, [(kmh(h), bar) for h in hopf]


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
    for key in ("reduced", "mbs_full"):
        title, model = models[key]
        family = model.problem(TyrePressures.uniform(model.axle.data.pressure_range_bar[0] * BAR), "pressure")
        found = []
        for bar in check_pressures(ctx):
            ctx.progress(f"Stability margins: sign against the Hopf points at {bar:g} bar, {title}")
            row, points = hopf_sign_row(family, title, bar, np.linspace(MIN_SPEED, VMAX, n_speeds))
            rows.append(row)
            found += points
        hopf[key] = found
    rows += [minimum_row(models[key][0], studies[key]) for key in ("reduced", "mbs_full")]
    plot_margin_maps([(studies[key], f"{models[key][0]}\nblack: zero damping; circles: Hopf points",
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
              f"the reduced model's map to {MAP_TOL:g}; the margin's sign against the Hopf points of straight running "
              f"(the truth, from continuation), at the planned cases {where}, for the reduced model and the full "
              f"geometry: read on both sides of every Hopf point ({SIDE:g} relative, at most a quarter of the gap to "
              f"the next), in the middle of every interval between them, however narrow, and at the map's speeds: "
              f"no oscillating pair crosses the imaginary axis inside an interval (the growing pairs and the growing "
              f"eigenvalues change together), one does across each Hopf point; a growing pair meeting the real axis "
              f"(a divergence) changes the margin's sign without a Hopf point and is named in the note. "
              f"Information: "
              f"each model's minimum over the window, its location to the grid's spacing."))
