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
    ANGLE_RANGE_DEG,
    DURATION_RANGE_S,
    MAX_CYCLES,
    MBS_MAX_DURATION,
    PRESSURE_RANGE_BAR,
    RAMP_TIME_RANGE_S,
    RATE_RANGE_DEG_S,
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
from reduced_model.model import STATE_NAMES, STATE_UNITS, Effects, ShimmyModel
from axles.parameters import ParameterError, ShimmyParameters
from reduced_model.simulation import initial_state
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
            progress: Callable[[float], None] | None = None, poses: bool = False) -> Trajectory:
        """The trajectory by scipy; ``poses`` changes nothing (a recording draws this model from its states)."""
        from reduced_model.simulation import integrate
        return integrate(self.model, pressures, schedule, duration, x0, progress=progress)


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
            progress: Callable[[float], None] | None = None, poses: bool = False) -> Trajectory:
        """The trajectory by Exudyn, with the bodies' poses when ``poses`` (for a 3D recording); ``progress(t)``
        with the simulated time every 1 % of the duration."""
        from mbs_shimmy.simulation import integrate
        return integrate(self.axle.params, self.effects, self.fidelity, pressures, schedule, x0, duration,
                         dims=self.axle.dims, poses=poses, progress=progress)


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
                      speed_points: int = 201, progress: Callable[[], None] | None = None) -> StabilityMargins:
    """The least damping ratio of straight running on an even grid of speeds (km/h) and tyre pressures (bar, both
    tyres alike; default: the axle's operating window), with the mode it belongs to, as ``shimmy margins``;
    ``progress()`` is called after each pressure of the grid.

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
    problem = model.problem(pressures, "pressure")
    grid_p = np.linspace(to_si(lo, "Pa"), to_si(hi, "Pa"), counts[0]) if lo < hi else np.array([to_si(lo, "Pa")])
    study = margin_study(problem, np.linspace(vmin, vmax, counts[1]), grid_p, progress)
    return StabilityMargins(f"{model.label()}, axle {model.axle.data.shown_name}", study)


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


def check_simulation_work(model: ReducedModel | MultibodyModel, pressures: TyrePressures, schedule: SpeedSchedule,
                          duration: float, what: str = "duration_s") -> None:
    """Refuse (:class:`ParameterError`, naming ``what``) a simulation that would run on for many minutes: an MBS
    run longer than :data:`~axles.limits.MBS_MAX_DURATION`, or one whose fastest oscillation needs more than
    :data:`~axles.limits.MAX_CYCLES` periods resolved.

    Within the physical ranges an axle can still combine a stiff tie rod with a light wheel (k1 = 1e8 N m/rad,
    I1 = 0.1 kg m^2 oscillate at 7 kHz): both integrators must follow every period of such a mode, and 20 s take
    hours.  The fastest frequency is read from the linearisation of the model that runs, at both ends of the
    speed range: the MBS's own, whose full geometry adds modes (steering gear, lateral travel) the reduced model
    does not have.
    """
    mbs = isinstance(model, MultibodyModel)
    if mbs and duration > MBS_MAX_DURATION:
        option = f"{what} with --model mbs" if what.startswith("--") else f"{what} of the multibody model"
        raise ParameterError(f"{option} must be at most {MBS_MAX_DURATION:g} s (about 2 s of computing per "
                             f"simulated second), got {duration:g}")
    speeds = {schedule.start} | ({schedule.end} if schedule.end is not None else set())
    family = model.problem(pressures, "pressure")
    fastest = max(float(np.max(np.abs(np.linalg.eigvals(family.linear_matrix(v, family.nominal)).imag)))
                  for v in speeds) / (2 * np.pi)
    cycles = fastest * duration
    if cycles > MAX_CYCLES:
        which = "the MBS's" if mbs else "the axle's"
        raise ParameterError(f"{which} fastest oscillation, {fastest:.4g} Hz, would need {cycles:.3g} periods "
                             f"resolved in {duration:g} s (limit {MAX_CYCLES:g}): shorten {what} or check the "
                             f"stiffnesses and inertias (k1, k2, I1, ...)")


def simulate(model: ReducedModel | MultibodyModel, pressures: TyrePressures, *, speed_kmh: float | None = None,
             ramp_kmh: tuple[float, float, float] | None = None, duration_s: float,
             initial_deg: Mapping[str, float] | None = None, progress: Callable[[float], None] | None = None,
             poses: bool = False, allow_long: bool = False) -> Simulation:
    """A time simulation of either model, the same call for both: at a constant ``speed_kmh`` or along
    ``ramp_kmh=(FROM, TO, SECONDS)`` (then held), for ``duration_s`` s from ``initial_deg`` (degrees, deg/s for
    the rates; default theta1 = 0.573 deg).  The reduced model runs on scipy, the MBS on Exudyn (about 2 s of
    computing per simulated second).  ``progress(t)`` is called with the simulated time every 1 % of the duration
    (reduced model; the MBS reports none); ``poses`` keeps the MBS bodies' poses in the trajectory, for a 3D
    recording (:func:`comparisons.recordings.writer.write_recording`).  As the command, a run that would take many
    minutes is refused (:func:`check_simulation_work`: the MBS beyond 100 s, or more than 50000 periods of the
    fastest oscillation); ``allow_long=True`` runs it anyway.

    >>> run = simulate(Axle.paper().reduced(), TyrePressures.both(2.5), speed_kmh=60, duration_s=2)
    >>> run.status.value
    'complete'
    """
    schedule = schedule_of(speed_kmh, ramp_kmh)
    duration = check_range("duration_s", duration_s, *DURATION_RANGE_S, "s")
    x0 = initial_from_degrees(initial_deg)
    if not allow_long:
        check_simulation_work(model, pressures, schedule, duration)
    trajectory = model.run(pressures, schedule, x0, duration, progress=progress, poses=poses)
    return Simulation(f"{model.label()}, {pressures}, axle {model.axle.data.shown_name}", trajectory)


__all__ = ["Axle", "CycleBranches", "ModelFamily", "HopfSummary", "HopfResult", "MultibodyModel", "ReducedModel",
           "ShimmyWindows", "Simulation", "StabilityMargins", "TyrePressures", "check_simulation_work", "cycle_branches",
           "family_of", "fidelity_of", "hopf_points", "parse_settings", "shimmy_windows", "simulate", "stability_margins"]
