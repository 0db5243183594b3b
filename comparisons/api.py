"""The package's public face for an engineer in a notebook: one entry function per job, small frozen inputs.

Interface units at the edges (km/h, bar, degrees, as the ``shimmy`` command takes them), SI inside and in every
result's fields; results show themselves in interface units (:mod:`comparisons.results`)::

    from comparisons.api import Axle, TyrePressures, hopf_points

    axle = Axle.paper()                          # or Axle.from_file("mytruck.toml")
    family = axle.reduced(effects="hcl,pt").family(TyrePressures.both(1.5))   # bar
    result = hopf_points(family, vmax_kmh=400)
    print(result)                                # a table: speed km/h, frequency Hz, l1, criticality

* inputs: :class:`Axle` (``paper``, ``from_file``, ``with_values``, ``with_set``), :class:`TyrePressures`,
  :class:`Braking` (``Braking.of_slip(0.05, 0.0)``: a steady braking, right and left; default free rolling);
* models: ``axle.reduced(effects=...)`` (:class:`ReducedModel`) and ``axle.mbs(fidelity=..., assume=...)``
  (:class:`MultibodyModel`), each with ``.family(pressures, param="pressure", braking=...)`` (:class:`ModelFamily`);
* jobs: :func:`hopf_points`, :func:`cycle_branches`, :func:`stability_margins`, :func:`simulate` (one signature
  for both models).

Bad input raises :class:`~axles.parameters.ParameterError` with a one-line message naming the range.
Reading an axle loads no Exudyn: the multibody model is imported when its family or a simulation is made.  The
``shimmy`` command builds its models through this module (:mod:`comparisons.cli.options`).
"""

from __future__ import annotations

import numbers
import os
from dataclasses import dataclass
from functools import cached_property
from typing import Callable, Iterable, Mapping, Sequence

import numpy as np

from axles import axle as axle_data
from axles.axle_file import axle_from_path_or_paper
from axles.input_file import finite_number
from axles.limits import (
    PRESSURE_RANGE_BAR,
    SPEED_RANGE_KMH,
)
from axles.input_file import check_range
from axles.braking import FREE_ROLLING, Braking
from axles.pressures import TyrePressures
from axles.units import to_si
from comparisons.windows import ShimmyWindows, pair_windows
from comparisons.results import (
    CycleBranches,
    HopfSummary,
    HopfResult,
    Simulation,
    StabilityMargins,
    cycle_branch,
)
from axles.dimensions import AxleDimensions
from mbs_shimmy.fidelity import Fidelity
from bifurcation.special_points import BranchStatus
from reduced_model.family import SpeedFamily
from reduced_model.model import STATE_NAMES, STATE_UNITS, Effects, ShimmyModel  # noqa: F401 - API names
from axles.parameters import ParameterError, ShimmyParameters
from reduced_model.trajectory import SpeedSchedule, Trajectory


def check_count(what: str, value: int, lo: int, hi: int) -> int:
    """A whole number (numpy integers too) within [lo, hi], or a :class:`ParameterError` naming ``what``."""
    if isinstance(value, bool) or not isinstance(value, numbers.Integral) or not lo <= int(value) <= hi:
        raise ParameterError(f"{what} must be a whole number within [{lo}, {hi}], got {value!r}")
    return int(value)


# --- inputs ---------------------------------------------------------------------------------------------------

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

    data: axle_data.AxleData

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
        # each value a finite number before any unit conversion (10**400 would overflow it), named with its unit
        merged = {name: finite_number(name, v, axle_data.entry(name).unit) for name, v in merged.items()}
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

    def family(self, pressures: TyrePressures, param: str = "pressure",
               braking: Braking = FREE_ROLLING) -> "ModelFamily":
        """The model over speed and ``param`` (``"pressure"``, ``"pressure_left"``, ``"pressure_right"``,
        ``"brake_slip"`` or a Table 1 entry) at these tyre pressures and this braking
        (:class:`~axles.braking.Braking`; default free rolling)."""
        return ModelFamily(self, pressures, param, braking)

    def problem(self, pressures: TyrePressures, param: str = "pressure",
                braking: Braking = FREE_ROLLING) -> SpeedFamily:
        """The toolkit's family (:func:`family_of`)."""
        return family_of(self.model, pressures, param, braking)

    def run(self, pressures: TyrePressures, schedule: SpeedSchedule, x0, duration: float,
            progress: Callable[[float], None] | None = None, poses: bool = False,
            braking: Braking = FREE_ROLLING) -> Trajectory:
        """The trajectory by scipy; ``poses`` changes nothing (a recording draws this model from its states)."""
        from reduced_model.simulation import integrate
        return integrate(self.model, pressures, schedule, duration, x0, progress=progress, braking=braking)


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

    def family(self, pressures: TyrePressures, param: str = "pressure",
               braking: Braking = FREE_ROLLING) -> "ModelFamily":
        """As :meth:`ReducedModel.family`."""
        return ModelFamily(self, pressures, param, braking)

    def problem(self, pressures: TyrePressures, param: str = "pressure", braking: Braking = FREE_ROLLING):
        """The toolkit's family (:func:`family_of`)."""
        return family_of(self.model, pressures, param, braking)

    def run(self, pressures: TyrePressures, schedule: SpeedSchedule, x0, duration: float,
            progress: Callable[[float], None] | None = None, poses: bool = False,
            braking: Braking = FREE_ROLLING) -> Trajectory:
        """The trajectory by Exudyn, with the bodies' poses when ``poses`` (for a 3D recording); ``progress(t)``
        with the simulated time every 1 % of the duration."""
        from mbs_shimmy.simulation import integrate
        return integrate(self.axle.params, self.effects, self.fidelity, pressures, schedule, x0, duration,
                         dims=self.axle.dims, poses=poses, progress=progress, braking=braking)


def family_of(model, pressures: TyrePressures, param: str = "pressure", braking: Braking = FREE_ROLLING):
    """The toolkit's family of a model over speed and ``param`` at the tyres' ``pressures`` under ``braking``: a
    :class:`~reduced_model.family.SpeedFamily` of a :class:`~reduced_model.model.ShimmyModel`, an
    :class:`~mbs_shimmy.linearisation.MbsFamily` of an :class:`~mbs_shimmy.model.MbsModel`.  The one place a family
    is constructed (``tests/test_architecture.py``); everything else asks here or through :meth:`ModelFamily.problem`."""
    if not isinstance(pressures, TyrePressures):
        raise TypeError(f"pressures must be TyrePressures, got {type(pressures).__name__}")
    if not isinstance(braking, Braking):
        raise TypeError(f"braking must be Braking, got {type(braking).__name__}")
    if isinstance(model, ShimmyModel):
        return SpeedFamily(model, param, pressures, braking)
    from mbs_shimmy.linearisation import MbsFamily
    from mbs_shimmy.model import MbsModel
    if isinstance(model, MbsModel):
        return MbsFamily(model, param, pressures, braking)
    raise TypeError(f"no family for a {type(model).__name__}")


@dataclass(frozen=True)
class ModelFamily:
    """A model over speed and one more parameter ``param`` at tyre pressures ``pressures``; ``q`` is the
    parameter's own value there (SI), which the jobs use.  ``problem`` is the toolkit's family.

    >>> family = Axle.paper().reduced().family(TyrePressures.both(2.5))
    >>> family.q
    250000.0
    """

    model: ReducedModel | MultibodyModel
    pressures: TyrePressures
    param: str = "pressure"
    braking: Braking = FREE_ROLLING

    @cached_property
    def problem(self):
        return self.model.problem(self.pressures, self.param, self.braking)

    @property
    def q(self) -> float:
        return self.problem.nominal

    def label(self) -> str:
        braking = f", {self.braking}" if self.braking.active else ""
        return f"{self.model.label()}, {self.pressures}{braking}, axle {self.model.axle.data.shown_name}"


# --- jobs -----------------------------------------------------------------------------------------------------

def speed_window(vmin_kmh: float, vmax_kmh: float) -> tuple[float, float]:
    """(vmin, vmax) m/s of a window in km/h inside :data:`~axles.limits.SPEED_RANGE_KMH`."""
    lo = check_range("vmin_kmh", vmin_kmh, *SPEED_RANGE_KMH, "km/h")
    hi = check_range("vmax_kmh", vmax_kmh, *SPEED_RANGE_KMH, "km/h")
    if not lo < hi:
        raise ParameterError(f"vmin_kmh must be below vmax_kmh, got {lo:g} and {hi:g} km/h")
    return to_si(lo, "m/s"), to_si(hi, "m/s")


def hopf_points(family: ModelFamily, vmin_kmh: float = 0.5, vmax_kmh: float = 400.0) -> HopfResult:
    """Every Hopf point of straight running (shimmy onset) in the speed window, at the family's own q, as
    ``shimmy hopf``: speed, frequency and the first Lyapunov coefficient (criticality).

    >>> family = Axle.paper().reduced().family(TyrePressures.both(2.5))
    >>> [round(p.speed_kmh, 1) for p in hopf_points(family, vmax_kmh=100).points]
    [46.1, 70.5]
    """
    from bifurcation.equilibria.hopf import find_hopf_points as find
    vmin, vmax = speed_window(vmin_kmh, vmax_kmh)
    found = find(family.problem, family.q, vmin, vmax)
    return HopfResult(family.label(), vmin, vmax, tuple(HopfSummary.of(p) for p in found))


def shimmy_windows(family: ModelFamily, hopf: HopfResult | None = None, vmin_kmh: float = 0.5,
                   vmax_kmh: float = 400.0) -> ShimmyWindows:
    """The speed windows where straight running shimmies, by mode, from the Hopf points of ``hopf`` (else found in
    the window), paired as :func:`comparisons.windows.pair_windows` says.

    >>> family = Axle.paper().reduced().family(TyrePressures.both(1.5))
    >>> [w.text() for w in shimmy_windows(family).windows]
    ['yaw from 26.630 to 97.128 km/h', 'tramp from 192.983 to 345.889 km/h']
    """
    if hopf is None:
        hopf = hopf_points(family, vmin_kmh, vmax_kmh)
    return pair_windows(family.problem, hopf)


def cycle_branches(family: ModelFamily, vmin_kmh: float = 0.5, vmax_kmh: float = 400.0) -> CycleBranches:
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
    return CycleBranches(family.label(), vmin, vmax, tuple(HopfSummary.of(h) for h in diagram.hopf), branches,
                         status, diagram)


def stability_margins(model: ReducedModel | MultibodyModel, pressure_range_bar: tuple[float, float] | None = None,
                      vmin_kmh: float = 0.5, vmax_kmh: float = 400.0, pressure_points: int = 31,
                      speed_points: int = 201, progress: Callable[[], None] | None = None,
                      braking: Braking = FREE_ROLLING) -> StabilityMargins:
    """The least damping ratio of straight running (under ``braking``: the braked steady state) on an even grid of
    speeds (km/h) and tyre pressures (bar, both tyres alike; default: the axle's operating window), with the mode it
    belongs to, as ``shimmy margins``; ``progress()`` is called after each pressure of the grid.

    >>> result = stability_margins(Axle.paper().reduced(), (2.5, 2.5), 40, 80, pressure_points=1, speed_points=41)
    >>> low = result.minimum
    >>> round(low.damping_ratio, 4), low.mode, round(low.speed_kmh)
    (-0.0038, 'yaw', 57)
    """
    from comparisons.studies.margin_study import margin_study
    lo, hi = model.axle.data.pressure_range_bar if pressure_range_bar is None else pressure_range_bar
    lo, hi = (check_range("pressure_range_bar", v, *PRESSURE_RANGE_BAR, "bar") for v in (lo, hi))
    if not lo <= hi:
        raise ParameterError(f"pressure_range_bar needs LO <= HI, got {lo:g} {hi:g}")
    vmin, vmax = speed_window(vmin_kmh, vmax_kmh)
    counts = [check_count(what, n, 1, 2001) for what, n in (("pressure_points", pressure_points),
                                                           ("speed_points", speed_points))]
    pressures = TyrePressures.both(0.5 * (lo + hi))
    problem = model.problem(pressures, "pressure", braking)
    grid_p = np.linspace(to_si(lo, "Pa"), to_si(hi, "Pa"), counts[0]) if lo < hi else np.array([to_si(lo, "Pa")])
    study = margin_study(problem, np.linspace(vmin, vmax, counts[1]), grid_p, progress)
    braked = f", {braking}" if braking.active else ""
    return StabilityMargins(f"{model.label()}{braked}, axle {model.axle.data.shown_name}", study)


# the API's simulations, defined beside it
from comparisons.simulations import check_simulation_work, initial_from_degrees, schedule_of  # noqa: E402
from comparisons.simulations import simulate  # noqa: E402

__all__ = ["Axle", "CycleBranches", "ModelFamily", "HopfSummary", "HopfResult", "MultibodyModel", "ReducedModel",
           "ShimmyWindows", "Simulation", "StabilityMargins", "TyrePressures", "check_simulation_work", "cycle_branches",
           "family_of", "fidelity_of", "hopf_points", "parse_settings", "shimmy_windows", "simulate", "stability_margins"]
