"""The package's public face for an engineer in a notebook: one entry function per job, small frozen inputs.

Interface units at the edges (km/h, bar, degrees, as the ``shimmy`` command takes them), SI inside and in every
result's fields; results show themselves in interface units (:mod:`comparisons.results`)::

    from comparisons.api import Axle, TyrePressures, hopf_points

    axle = Axle.paper()                          # or Axle.from_file("mytruck.toml")
    family = axle.reduced(effects="hcl,pt").family(TyrePressures.both(1.5))   # bar
    result = hopf_points(family, vmax_kmh=400)
    print(result)                                # a table: speed km/h, frequency Hz, l1, criticality

* inputs: :class:`Axle` (``paper``, ``from_file``, ``with_values``, ``with_set``), :class:`TyrePressures`;
* models: ``axle.reduced(effects=...)`` (:class:`ReducedModel`) and ``axle.mbs(fidelity=..., assume=...)``
  (:class:`MultibodyModel`), each with ``.family(pressures, param="pressure")`` (:class:`Family`);
* jobs: :func:`hopf_points`, :func:`cycle_branches`, :func:`stability_margins`, :func:`simulate` (one signature
  for both models).

Bad input raises :class:`~axles.parameters.ParameterError` with a one-line message naming the range.
Reading an axle loads no Exudyn: the multibody model is imported when its family or a simulation is made.  The
``shimmy`` command builds its models through this module (:mod:`comparisons.cli.options`).
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass
from functools import cached_property
from typing import Callable, Iterable, Mapping, Sequence

import numpy as np

from axles import axle as axle_data
from axles.axle_file import axle_from_path_or_paper
from axles.limits import (
    ANGLE_RANGE_DEG,
    DURATION_RANGE_S,
    PRESSURE_RANGE_BAR,
    RAMP_TIME_RANGE_S,
    RATE_RANGE_DEG_S,
    SPEED_RANGE_KMH,
)
from axles.units import to_si
from comparisons.results import CycleBranches, HopfPoint, HopfResult, Simulation, StabilityMargins, cycle_branch
from axles.dimensions import AxleDimensions
from mbs_shimmy.fidelity import Fidelity
from bifurcation.special_points import BranchStatus
from reduced_model.family import SpeedFamily
from reduced_model.model import STATE_NAMES, STATE_UNITS, Effects, ShimmyModel
from axles.parameters import ParameterError, ShimmyParameters
from reduced_model.simulation import initial_state
from reduced_model.trajectory import SpeedSchedule, Trajectory


def check_range(what: str, value: float, lo: float, hi: float, unit: str) -> float:
    """``value`` as a float, or a :class:`ParameterError` naming the range [lo, hi] (interface units)."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise ParameterError(f"{what} must be a number, got {value!r}")
    if not (math.isfinite(value) and lo <= value <= hi):
        raise ParameterError(f"{what} must be within [{lo:g}, {hi:g}] {unit}, got {value:g}")
    return float(value)


# --- inputs ---------------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class TyrePressures:
    """Inflation pressures of the two front tyres, bar (wheel 1, theta1, is the right wheel).

    >>> TyrePressures.both(1.5).si
    150000.0
    >>> TyrePressures(right_bar=1.5, left_bar=1.2).si
    (150000.0, 120000.0)
    """

    right_bar: float
    left_bar: float

    def __post_init__(self) -> None:
        # Stored as plain floats, so that 2 and 2.0 bar are the same pressures (and the same family).
        object.__setattr__(self, "right_bar", check_range("right tyre pressure", self.right_bar, *PRESSURE_RANGE_BAR,
                                                          "bar"))
        object.__setattr__(self, "left_bar", check_range("left tyre pressure", self.left_bar, *PRESSURE_RANGE_BAR,
                                                         "bar"))

    @classmethod
    def both(cls, bar: float) -> "TyrePressures":
        """Both tyres at ``bar``."""
        return cls(bar, bar)

    @property
    def alike(self) -> bool:
        return self.right_bar == self.left_bar

    @property
    def si(self) -> float | tuple[float, float]:
        """The models' pressure argument, Pa: one value when the tyres are alike, else (right, left).  The one
        place where the pressures in bar become Pa."""
        right, left = to_si(self.right_bar, "Pa"), to_si(self.left_bar, "Pa")
        return right if self.alike else (right, left)

    def __str__(self) -> str:
        if self.alike:
            return f"{self.right_bar:g} bar"
        return f"right {self.right_bar:g} / left {self.left_bar:g} bar"


def name_and_text(item: str, option: str) -> tuple[str, str]:
    """(NAME, VALUE text) of a ``NAME=VALUE`` item, or a :class:`ParameterError` naming the option."""
    name, sep, text = item.partition("=")
    name = name.strip()
    if not sep or not name or not text.strip():
        raise ParameterError(f"{option} expects NAME=VALUE, got '{item}'")
    return name, text


def parse_settings(items: Iterable[str]) -> dict[str, float]:
    """``NAME=VALUE`` strings (``shimmy --set`` style, interface units) to ``{name: value}``.

    >>> parse_settings(["t0=0.25", "gamma=3"])
    {'t0': 0.25, 'gamma': 3.0}
    """
    values: dict[str, float] = {}
    for item in items:
        name, text = name_and_text(item, "--set")
        if name not in axle_data.entries():
            try:
                axle_data.entry(name, "parameter")
            except ParameterError as exc:
                raise ParameterError(f"{exc} in --set") from None
        try:
            values[name] = float(text)
        except ValueError:
            raise ParameterError(f"--set {name}: '{text}' is not a number") from None
    return values


@dataclass(frozen=True)
class Axle:
    """A truck front axle: Table 1 and the multibody dimensions (``data``, SI; see ``shimmy params``).

    >>> axle = Axle.paper().with_values(t0=0.25)       # interface units: degrees, bar, otherwise SI
    >>> axle.value("t0"), axle.params.t0
    (0.25, 0.25)
    >>> Axle.paper().with_set("gamma=3").value("gamma")  # degrees, as 'shimmy --set gamma=3'
    3.0
    """

    data: axle_data.Axle

    @classmethod
    def paper(cls) -> "Axle":
        """Yang, Knowles & Mavros' truck (Table 1) with the chosen multibody dimensions."""
        return cls(axle_data.paper_axle())

    @classmethod
    def from_file(cls, path: str | os.PathLike) -> "Axle":
        """An axle file (``shimmy params --write FILE.toml`` writes one); a bad file raises
        :class:`~axles.axle_file.AxleFileError` naming the file and the entry."""
        return cls(axle_from_path_or_paper(os.fspath(path)))

    def with_tyre(self, path: str | os.PathLike) -> "Axle":
        """A copy with the tyre entries of a Magic Formula 6.1/6.2 property file (``.tir``); a bad file raises
        :class:`~axles.tyre_file.TyreFileError` naming the file, the line and the key."""
        from axles.tyre_file import apply_tyre, read_tir
        return Axle(apply_tyre(self.data, read_tir(os.fspath(path))))

    def with_values(self, values: Mapping[str, float] | None = None, **named: float) -> "Axle":
        """A copy with entries replaced, in interface units (degrees, bar, otherwise SI), each checked against
        its physical range: ``axle.with_values(t0=0.25)`` or ``axle.with_values({"t0": 0.25})``."""
        merged = {**(values or {}), **named}
        return Axle(self.data.with_overrides(merged)) if merged else self

    def with_set(self, *items: str) -> "Axle":
        """``with_values`` from ``NAME=VALUE`` strings, as the command's ``--set``: ``axle.with_set("t0=0.25")``."""
        return self.with_values(parse_settings(items))

    @property
    def name(self) -> str:
        return self.data.name

    @property
    def params(self) -> ShimmyParameters:
        """Table 1 (:class:`~axles.parameters.ShimmyParameters`, SI)."""
        return self.data.params

    @property
    def dims(self) -> AxleDimensions:
        """The multibody dimensions (:class:`~axles.dimensions.AxleDimensions`, SI)."""
        return self.data.dims

    def value(self, name: str) -> float:
        """An entry in interface units, as :meth:`with_values` takes it."""
        return self.data.interface_value(name)

    def __str__(self) -> str:
        return self.data.label()

    def reduced(self, effects: str | Effects = "") -> "ReducedModel":
        """The paper's reduced model of this axle; ``effects``: pressure effects beyond the lateral force,
        ``"hcl,pt,rl,vs"``, ``"all"`` or ``""`` (the section 3 model).

        >>> Axle.paper().reduced(effects="hcl,pt").effects.names
        ('hcl', 'pt')
        """
        return ReducedModel(self, effects_of(effects))

    def mbs(self, fidelity: str | Fidelity | None = None, assume: str | Sequence[str] | None = None,
            effects: str | Effects = "") -> "MultibodyModel":
        """The Exudyn multibody model of this axle: ``fidelity="reduced"`` (every assumption of the reduced model
        on, the default) or ``"full"`` (all off), or ``assume=("small_angles", ...)`` (exactly these on; see
        ``shimmy assumptions``).

        >>> Axle.paper().mbs(fidelity="full").fidelity.label
        'full'
        """
        return MultibodyModel(self, effects_of(effects), fidelity_of(fidelity, assume))


def effects_of(effects: str | Effects) -> Effects:
    return effects if isinstance(effects, Effects) else Effects.parse(effects)


def fidelity_of(fidelity: str | Fidelity | None = None, assume: str | Sequence[str] | None = None) -> Fidelity:
    """The MBS fidelity from ``fidelity`` ("reduced", "full" or a :class:`Fidelity`) or ``assume`` (names)."""
    if fidelity is not None and assume is not None:
        raise ParameterError("give either fidelity or assume, not both")
    if assume is not None:
        return Fidelity.parse(assume)
    if isinstance(fidelity, Fidelity):
        return fidelity
    if fidelity not in (None, "reduced", "full"):
        raise ParameterError(f"fidelity must be 'reduced' or 'full' (or give assume=NAMES), got {fidelity!r}")
    return Fidelity.parse(fidelity or "reduced")


# --- models and families --------------------------------------------------------------------------------------

@dataclass(frozen=True)
class ReducedModel:
    """The paper's 3-DOF model of an axle with the chosen pressure effects."""

    axle: Axle
    effects: Effects

    @cached_property
    def model(self) -> ShimmyModel:
        return ShimmyModel(params=self.axle.params, effects=self.effects)

    def label(self) -> str:
        return f"reduced model, pressure effects {','.join(self.effects.names) or 'none'}"

    def family(self, pressures: TyrePressures, param: str = "pressure") -> "Family":
        """The model over speed and ``param`` (``"pressure"``, ``"pressure_left"``, ``"pressure_right"`` or a
        Table 1 entry) at these tyre pressures."""
        return Family(self, pressures, param)

    def problem(self, pressure: float | tuple[float, float], param: str) -> SpeedFamily:
        """The toolkit's family (pressures in Pa)."""
        return SpeedFamily(self.model, param, pressure=pressure)

    def run(self, pressure, schedule: SpeedSchedule, x0, duration: float,
            progress: Callable[[float], None] | None = None, poses: bool = False) -> Trajectory:
        """The trajectory by scipy; ``poses`` changes nothing (a recording draws this model from its states)."""
        from reduced_model.simulation import simulate as simulate_reduced
        return simulate_reduced(self.model, pressure, schedule, duration, x0, progress=progress)


@dataclass(frozen=True)
class MultibodyModel:
    """The Exudyn multibody model of an axle at a fidelity, with the chosen pressure effects.  Exudyn is loaded
    when a family or a simulation of it is made, not before."""

    axle: Axle
    effects: Effects
    fidelity: Fidelity

    @cached_property
    def model(self):
        """:class:`mbs_shimmy.model.MbsModel`."""
        from mbs_shimmy.model import MbsModel
        return MbsModel(self.axle.params, self.effects, self.fidelity, self.axle.dims)

    def label(self) -> str:
        return f"MBS, fidelity {self.fidelity.label}, pressure effects {','.join(self.effects.names) or 'none'}"

    def family(self, pressures: TyrePressures, param: str = "pressure") -> "Family":
        """As :meth:`ReducedModel.family`."""
        return Family(self, pressures, param)

    def problem(self, pressure: float | tuple[float, float], param: str):
        """The toolkit's family, :class:`mbs_shimmy.linearisation.MbsFamily` (pressures in Pa)."""
        from mbs_shimmy.linearisation import MbsFamily
        return MbsFamily(self.model, param, pressure)

    def run(self, pressure, schedule: SpeedSchedule, x0, duration: float,
            progress: Callable[[float], None] | None = None, poses: bool = False) -> Trajectory:
        """The trajectory by Exudyn, with the bodies' poses when ``poses`` (for a 3D recording); it reports no
        ``progress``."""
        from mbs_shimmy.simulation import simulate as simulate_mbs
        return simulate_mbs(self.axle.params, self.effects, self.fidelity, pressure, schedule, x0, duration,
                            dims=self.axle.dims, poses=poses)


@dataclass(frozen=True)
class Family:
    """A model over speed and one more parameter ``param`` at tyre pressures ``pressures``; ``q`` is the
    parameter's own value there (SI), which the jobs use.  ``problem`` is the toolkit's family.

    >>> family = Axle.paper().reduced().family(TyrePressures.both(2.5))
    >>> family.q
    250000.0
    """

    model: ReducedModel | MultibodyModel
    pressures: TyrePressures
    param: str = "pressure"

    @cached_property
    def problem(self):
        return self.model.problem(self.pressures.si, self.param)

    @property
    def q(self) -> float:
        return self.problem.nominal

    def label(self) -> str:
        return f"{self.model.label()}, {self.pressures}, axle {self.model.axle.name}"


# --- jobs -----------------------------------------------------------------------------------------------------

def speed_window(vmin_kmh: float, vmax_kmh: float) -> tuple[float, float]:
    """(vmin, vmax) m/s of a window in km/h inside :data:`~axles.limits.SPEED_RANGE_KMH`."""
    lo = check_range("vmin_kmh", vmin_kmh, *SPEED_RANGE_KMH, "km/h")
    hi = check_range("vmax_kmh", vmax_kmh, *SPEED_RANGE_KMH, "km/h")
    if not lo < hi:
        raise ParameterError(f"vmin_kmh must be below vmax_kmh, got {lo:g} and {hi:g} km/h")
    return to_si(lo, "m/s"), to_si(hi, "m/s")


def hopf_points(family: Family, vmin_kmh: float = 0.5, vmax_kmh: float = 400.0) -> HopfResult:
    """Every Hopf point of straight running (shimmy onset) in the speed window, at the family's own q, as
    ``shimmy hopf``: speed, frequency and the first Lyapunov coefficient (criticality).

    >>> family = Axle.paper().reduced().family(TyrePressures.both(2.5))
    >>> [round(p.speed_kmh, 1) for p in hopf_points(family, vmax_kmh=100).points]
    [46.1, 70.5]
    """
    from bifurcation.equilibria.hopf import hopf_points as find
    vmin, vmax = speed_window(vmin_kmh, vmax_kmh)
    found = find(family.problem, family.q, vmin, vmax)
    return HopfResult(family.label(), vmin, vmax, tuple(HopfPoint.of(p) for p in found))


def cycle_branches(family: Family, vmin_kmh: float = 0.5, vmax_kmh: float = 400.0) -> CycleBranches:
    """Every branch of limit cycles born at a Hopf point in the window, continued in speed (as ``shimmy
    cycles``, for either model): stability, amplitude, cycle folds, torus and period-doubling points.

    >>> family = Axle.paper().reduced(effects="hcl,pt").family(TyrePressures.both(1.5))
    >>> result = cycle_branches(family, vmin_kmh=5, vmax_kmh=60)
    >>> [round(b.start.speed_kmh, 2) for b in result.branches], result.status.value
    ([16.11], 'complete')
    """
    from bifurcation.cycles.branches import branch_peak, cycle_diagram
    vmin, vmax = speed_window(vmin_kmh, vmax_kmh)
    diagram = cycle_diagram(family.problem, family.q, vmin, vmax)
    branches = tuple(cycle_branch(b, branch_peak(family.problem, b, "theta1")) for b in diagram.branches
                     if b.points)
    status = next((b.status for b in diagram.branches if not b.complete), BranchStatus.COMPLETE)
    return CycleBranches(family.label(), vmin, vmax, tuple(HopfPoint.of(h) for h in diagram.hopf), branches,
                         status, diagram)


def stability_margins(model: ReducedModel | MultibodyModel, pressure_range_bar: tuple[float, float] | None = None,
                      vmin_kmh: float = 0.5, vmax_kmh: float = 400.0, pressure_points: int = 31,
                      speed_points: int = 201) -> StabilityMargins:
    """The least damping ratio of straight running on an even grid of speeds (km/h) and tyre pressures (bar, both
    tyres alike; default: the axle's operating window), with the mode it belongs to, as ``shimmy margins``.

    >>> result = stability_margins(Axle.paper().reduced(), (2.5, 2.5), 40, 80, pressure_points=1, speed_points=41)
    >>> low = result.minimum
    >>> round(low.damping_ratio, 4), low.mode, round(low.speed_kmh)
    (-0.0038, 'yaw', 57)
    """
    from comparisons.margins import margin_study
    lo, hi = model.axle.data.pressure_range_bar if pressure_range_bar is None else pressure_range_bar
    lo, hi = (check_range("pressure_range_bar", v, *PRESSURE_RANGE_BAR, "bar") for v in (lo, hi))
    if not lo <= hi:
        raise ParameterError(f"pressure_range_bar needs LO <= HI, got {lo:g} {hi:g}")
    vmin, vmax = speed_window(vmin_kmh, vmax_kmh)
    counts = []
    for what, n in (("pressure_points", pressure_points), ("speed_points", speed_points)):
        if isinstance(n, bool) or not isinstance(n, int) or not 1 <= n <= 2001:
            raise ParameterError(f"{what} must be a whole number within [1, 2001], got {n!r}")
        counts.append(n)
    pressures = TyrePressures.both(0.5 * (lo + hi))
    problem = model.problem(pressures.si, "pressure")
    grid_p = np.linspace(to_si(lo, "Pa"), to_si(hi, "Pa"), counts[0]) if lo < hi else np.array([to_si(lo, "Pa")])
    study = margin_study(problem, np.linspace(vmin, vmax, counts[1]), grid_p)
    return StabilityMargins(f"{model.label()}, axle {model.axle.name}", study)


def initial_from_degrees(initial_deg: Mapping[str, float] | None) -> np.ndarray:
    """The SI initial state of ``{state: degrees}`` (deg/s for the rates); None: theta1 = 0.573 deg (0.01 rad)."""
    if initial_deg is None:
        return initial_state()
    values = {}
    for name, value in initial_deg.items():
        if name not in STATE_NAMES:
            raise ParameterError(f"unknown state '{name}' in initial_deg (names: {' '.join(STATE_NAMES)})")
        unit = STATE_UNITS[STATE_NAMES.index(name)]
        rate = unit == "rad/s"
        value = check_range(f"initial {name}", value, *(RATE_RANGE_DEG_S if rate else ANGLE_RANGE_DEG),
                            "deg/s" if rate else "deg")
        values[name] = to_si(value, unit)
    return initial_state(values)


def schedule_of(speed_kmh: float | None, ramp_kmh: tuple[float, float, float] | None) -> SpeedSchedule:
    """The speed schedule of a constant speed (km/h) or a ramp (from km/h, to km/h, seconds)."""
    if (speed_kmh is None) == (ramp_kmh is None):
        raise ParameterError("give either speed_kmh or ramp_kmh=(FROM, TO, SECONDS)")
    if speed_kmh is not None:
        return SpeedSchedule.constant(to_si(check_range("speed_kmh", speed_kmh, *SPEED_RANGE_KMH, "km/h"), "m/s"))
    if len(ramp_kmh) != 3:
        raise ParameterError(f"ramp_kmh must be (FROM, TO, SECONDS), got {ramp_kmh!r}")
    start, end = (to_si(check_range(f"ramp_kmh {what}", v, *SPEED_RANGE_KMH, "km/h"), "m/s")
                  for what, v in zip(("FROM", "TO"), ramp_kmh[:2]))
    return SpeedSchedule.ramp(start, end, check_range("ramp_kmh SECONDS", ramp_kmh[2], *RAMP_TIME_RANGE_S, "s"))


def simulate(model: ReducedModel | MultibodyModel, pressures: TyrePressures, *, speed_kmh: float | None = None,
             ramp_kmh: tuple[float, float, float] | None = None, duration_s: float,
             initial_deg: Mapping[str, float] | None = None, progress: Callable[[float], None] | None = None,
             poses: bool = False) -> Simulation:
    """A time simulation of either model, the same call for both: at a constant ``speed_kmh`` or along
    ``ramp_kmh=(FROM, TO, SECONDS)`` (then held), for ``duration_s`` s from ``initial_deg`` (degrees, deg/s for
    the rates; default theta1 = 0.573 deg).  The reduced model runs on scipy, the MBS on Exudyn (about 2 s of
    computing per simulated second).  ``progress(t)`` is called with the simulated time every 1 % of the duration
    (reduced model; the MBS reports none); ``poses`` keeps the MBS bodies' poses in the trajectory, for a 3D
    recording (:func:`comparisons.recordings.writer.write_recording`).

    >>> run = simulate(Axle.paper().reduced(), TyrePressures.both(2.5), speed_kmh=60, duration_s=2)
    >>> run.status.value
    'complete'
    """
    schedule = schedule_of(speed_kmh, ramp_kmh)
    duration = check_range("duration_s", duration_s, *DURATION_RANGE_S, "s")
    x0 = initial_from_degrees(initial_deg)
    trajectory = model.run(pressures.si, schedule, x0, duration, progress=progress, poses=poses)
    return Simulation(f"{model.label()}, {pressures}, axle {model.axle.name}", trajectory)


__all__ = ["Axle", "CycleBranches", "Family", "HopfPoint", "HopfResult", "MultibodyModel", "ReducedModel",
           "Simulation", "StabilityMargins", "TyrePressures", "cycle_branches", "fidelity_of", "hopf_points",
           "parse_settings", "simulate", "stability_margins"]
