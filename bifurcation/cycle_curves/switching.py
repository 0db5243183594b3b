"""Switching from codimension-two points of the equilibrium onto the curves of cycle bifurcations born there:
from a Hopf-Hopf point onto its torus curves, from a generalized Hopf (Bautin) point onto its cycle-fold curve.

At a Hopf-Hopf point (frequencies omega_1, omega_2) the cycles born at each of the two Hopf curves are, close to
the point, of small amplitude and undergo a Neimark-Sacker bifurcation when the other mode crosses: the torus
curves emanate from the Hopf-Hopf point (Kuznetsov, Elements of Applied Bifurcation Theory, 3rd ed. 2004, section
8.6).  Switching therefore goes: on each side of the point, at q = q_HH +- delta, the Hopf point with frequency
omega_i; its cycle branch in a small window of p around p_HH; the torus point on it (located on its test
function); the torus curve through it (:func:`bifurcation.cycle_curves.result.cycle_bifurcation_curve`), kept when
its zero-amplitude end is this Hopf-Hopf point (located on the Hopf curve to 1e-6).  This is the construction of
the unfolding, computed rather than assumed: a side where no torus point appears yields no curve.  A generalized
Hopf point is handled the same way with its one frequency, the cycle fold in place of the torus point (Kuznetsov
2004, section 8.3: the fold curve of cycles emanates from the Bautin point on the subcritical side).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

import numpy as np

from bifurcation.cycle_curves.curve import cycle_bifurcation_curve
from bifurcation.cycle_curves.result import CycleCurve
from bifurcation.cycles.branches import branch_from_hopf
from bifurcation.cycles.problem import CycleSettings
from bifurcation.equilibria.hopf import find_hopf_points
from bifurcation.problem import ProblemError
from bifurcation.special_points import ConvergenceError, PointKind, PointStatus, SpecialPoint

BORN_AT = {PointKind.HOPF_HOPF: PointKind.TORUS, PointKind.GENERALIZED_HOPF: PointKind.CYCLE_FOLD}


@dataclass(frozen=True)
class Switched:
    """The curves switched onto at one codimension-two point: none where no side's branch gives one that ends
    there, and ``error`` where a curve's start failed to converge."""

    origin: SpecialPoint
    curves: tuple[CycleCurve, ...]
    error: ConvergenceError | None = None


# MatCont's letters for the curves of cycle bifurcations: torus (Neimark-Sacker) and cycle fold (its LPC)
LETTERS = {PointKind.TORUS: "T", PointKind.CYCLE_FOLD: "S"}


def named_curves(found: Sequence[Switched]) -> tuple[tuple[str, Switched, CycleCurve | None], ...]:
    """Every curve of ``found`` with its name (T1, T2, ... and S1, S2, ..., numbered per letter in the order of
    ``found`` and, at one origin, by decreasing primary parameter where the curve's second parameter is lowest);
    an origin whose start failed takes one name, with no curve."""
    named, count = [], {}
    for s in found:
        letter = LETTERS[BORN_AT[s.origin.kind]]
        curves = (None,) if s.error is not None else sorted(s.curves, key=lambda c: -c.ps[int(np.argmin(c.qs))])
        for curve in curves:
            count[letter] = count.get(letter, 0) + 1
            named.append((f"{letter}{count[letter]}", s, curve))
    return tuple(named)


def switched_curves(family, points, lo: float, hi: float, p_min: float, p_max: float,
                    settings: CycleSettings = CycleSettings(), progress=None) -> tuple[Switched, ...]:
    """:func:`curves_from_codimension_two` at each of ``points`` (Hopf-Hopf and generalized Hopf points of a Hopf
    diagram), in order; ``progress(point)`` after each."""
    out = []
    for point in points:
        try:
            out.append(Switched(point, curves_from_codimension_two(family, point, lo, hi, p_min, p_max,
                                                                   settings=settings)))
        except ConvergenceError as exc:
            out.append(Switched(point, (), exc))
        if progress is not None:
            progress(point)
    return tuple(out)


def curves_from_codimension_two(family, hh: SpecialPoint, lo: float, hi: float, p_min: float, p_max: float,
                                offset: float | None = None, half_width: float | None = None,
                                settings: CycleSettings = CycleSettings()) -> tuple[CycleCurve, ...]:
    """The torus curves that end at the Hopf-Hopf point ``hh``, or the cycle-fold curve that ends at the
    generalized Hopf point ``hh`` (from :func:`bifurcation.equilibria.hopf_curves.hopf_diagram`), within [p_min, p_max] x
    [lo, hi].  ``offset``: distance in q from the point at which the cycles are started (default 1 % of the
    window); ``half_width``: half width of the window of p of those branches (default 3 % of the point's p)."""
    if hh.kind not in BORN_AT:
        raise ValueError("switching needs a Hopf-Hopf or generalized Hopf point")
    born = BORN_AT[hh.kind]
    delta = 0.01 * (hi - lo) if offset is None else offset
    half = 0.03 * hh.p if half_width is None else half_width
    omegas = (hh.data["omega"], hh.data["omega2"]) if hh.kind is PointKind.HOPF_HOPF else (hh.data["omega"],)
    curves: list[CycleCurve] = []
    for q in (hh.q - delta, hh.q + delta):
        if not lo <= q <= hi:
            continue
        try:
            candidates = find_hopf_points(family, q, hh.p - half, hh.p + half)
        except (ProblemError, ConvergenceError):
            continue
        for omega in omegas:
            if not candidates:
                break
            h = min(candidates, key=lambda h: abs(h.omega - omega))
            if abs(h.omega - omega) > 0.1 * omega:
                continue
            branch = branch_from_hopf(family, h, hh.p - half, hh.p + half,
                                      others=tuple(c for c in candidates if c is not h), settings=settings)
            for torus in branch.points_of(born):
                if torus.status is not PointStatus.LOCATED:
                    continue
                try:
                    curve = cycle_bifurcation_curve(family, torus, lo, hi, p_min, p_max, settings)
                except ConvergenceError:
                    continue
                if not any(e is not None and _same(e, hh, hi - lo) for e in curve.end_points):
                    continue
                if not any(_same_curve(curve, c, hi - lo) for c in curves):
                    curves.append(curve)
    return tuple(curves)


def torus_curves_from_hopf_hopf(family, hh: SpecialPoint, lo: float, hi: float, p_min: float, p_max: float,
                                **options) -> tuple[CycleCurve, ...]:
    """The torus curves born at the Hopf-Hopf point ``hh`` (:func:`curves_from_codimension_two`)."""
    if hh.kind is not PointKind.HOPF_HOPF:
        raise ValueError("switching onto torus curves needs a Hopf-Hopf point")
    return curves_from_codimension_two(family, hh, lo, hi, p_min, p_max, **options)


def _same(p: SpecialPoint, hh: SpecialPoint, q_range: float) -> bool:
    return (p.kind is hh.kind and abs(p.p - hh.p) < 1e-6 * max(1.0, abs(hh.p))
            and abs(p.q - hh.q) < 1e-6 * q_range)


def _same_curve(a: CycleCurve, b: CycleCurve, q_range: float) -> bool:
    """Two computations of one curve: every point of a lies on b's polyline (to 1e-6 of the window)."""
    k = len(a.ps) // 2
    q = a.qs[k]
    if not b.qs.min() <= q <= b.qs.max():
        return False
    order = np.argsort(b.qs)
    p = np.interp(q, b.qs[order], b.ps[order])
    return abs(p - a.ps[k]) < 1e-3 * max(1.0, abs(p)) and abs(
        np.interp(q, b.qs[order], b.periods[order]) - a.periods[k]) < 1e-3 * a.periods[k]
