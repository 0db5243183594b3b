"""Stability margins of straight running for either model: the toolkit's least damping ratio
(:mod:`bifurcation.equilibria.margins`) on a grid of speed and tyre pressure (both tyres alike), each
least-damped mode named as ``shimmy modes`` names it (:mod:`reduced_model.mode_shapes`: yaw, tramp, lateral, gear
by its share of the kinetic energy).

The reduced model's Jacobian costs about 0.5 ms per (speed, pressure); the MBS's is affine in the speed and kept
per pressure (:class:`mbs_shimmy.linearisation.MbsFamily`), so a map of the MBS costs two Exudyn linearisations per
pressure (about 0.02 s with every assumption on, 0.1 s with the full geometry) and one eigenvalue problem per node.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from axles.units import BAR, kmh
from bifurcation.equilibria.margins import Margin, MarginMap, MarginStatus, margin_map
from reduced_model.family import SpeedFamily
from reduced_model.mode_shapes import mode_shape, reduced_inertias


def mode_inertias(problem) -> dict[str, float]:
    """The mass matrix's diagonal by mechanical coordinate at straight running (what :func:`mode_shape` weighs
    the rates by): I1 and I3 for the reduced model, the MBS's own mass matrix for the multibody model (with the
    full geometry the axle's lateral travel and the steering gear carry energy too)."""
    if isinstance(problem, SpeedFamily):
        return reduced_inertias(problem.model.params.I1, problem.model.params.I3)
    M = problem.mass_matrix(problem.nominal)
    return {name: float(M[k, k]) for k, name in enumerate(problem.layout.coordinates)}


@dataclass(frozen=True)
class MarginPoint:
    """The least damped mode of straight running at one speed (m/s) and pressure (Pa), named."""

    speed: float
    pressure: float
    damping_ratio: float          # negative: the mode grows (shimmy); NaN: nothing oscillates
    frequency_hz: float
    mode: str                     # yaw, tramp, lateral, gear ("-" when nothing oscillates)
    status: MarginStatus

    @property
    def speed_kmh(self) -> float:
        return kmh(self.speed)

    @property
    def pressure_bar(self) -> float:
        return self.pressure / BAR

    def to_json(self) -> dict:
        ok = self.status is MarginStatus.OSCILLATORY
        return {"speed_kmh": self.speed_kmh, "pressure_bar": self.pressure_bar,
                "damping_ratio": self.damping_ratio if ok else None,
                "frequency_hz": self.frequency_hz if ok else None, "mode": self.mode if ok else None,
                "status": self.status.value}


def named(margin: Margin, inertias: dict[str, float], names: tuple[str, ...]) -> MarginPoint:
    if margin.status is not MarginStatus.OSCILLATORY:
        return MarginPoint(margin.p, margin.q, math.nan, math.nan, "-", margin.status)
    shape = mode_shape(margin.eigenvalue, margin.eigenvector, inertias, names)
    return MarginPoint(margin.p, margin.q, margin.damping_ratio, margin.frequency_hz, shape.character, margin.status)


@dataclass(frozen=True)
class MarginStudy:
    """The least damping ratio of straight running on the grid ``speeds`` (m/s) x ``pressures`` (Pa);
    ``points[j][i]`` at (speeds[i], pressures[j]); ``minimum`` over the whole grid (None if nothing
    oscillates anywhere); ``map`` is the toolkit's."""

    speeds: np.ndarray = field(compare=False)
    pressures: np.ndarray = field(compare=False)
    points: tuple[tuple[MarginPoint, ...], ...]
    minimum: MarginPoint | None
    map: MarginMap = field(compare=False, repr=False)

    @property
    def damping_ratio(self) -> np.ndarray:
        """shape (len(pressures), len(speeds))"""
        return self.map.damping_ratio

    def least_per_pressure(self) -> tuple[MarginPoint | None, ...]:
        """The least margin over the speeds at each pressure."""
        out = []
        for row in self.points:
            found = [m for m in row if m.status is MarginStatus.OSCILLATORY]
            out.append(min(found, key=lambda m: m.damping_ratio) if found else None)
        return tuple(out)

    def to_json(self) -> dict:
        """The map as ``shimmy margins --json`` prints it (docs/json.md)."""
        rows = [[m.to_json() for m in row] for row in self.points]
        return {"speeds_kmh": [kmh(float(v)) for v in self.speeds],
                "pressures_bar": [float(p) / BAR for p in self.pressures],
                "damping_ratio": [[r["damping_ratio"] for r in row] for row in rows],
                "frequency_hz": [[r["frequency_hz"] for r in row] for row in rows],
                "mode": [[r["mode"] for r in row] for row in rows],
                "minimum": None if self.minimum is None else self.minimum.to_json()}


def margin_study(problem, speeds: np.ndarray, pressures: np.ndarray,
                 progress: Callable[[], None] | None = None) -> MarginStudy:
    """The named margin map of a model's family over "pressure" (:meth:`comparisons.api.ReducedModel.problem`)
    on the grid speeds (m/s) x pressures (Pa), and its minimum over the grid."""
    mmap = margin_map(problem, speeds, pressures, progress)
    inertias, names = mode_inertias(problem), tuple(problem.state_names)
    points = tuple(tuple(named(m, inertias, names) for m in row) for row in mmap.margins)
    low = mmap.minimum()
    minimum = None if low is None else named(low, inertias, names)
    return MarginStudy(mmap.p, mmap.q, points, minimum, mmap)
