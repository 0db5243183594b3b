"""What the notebook API (:mod:`comparisons.api`) returns: frozen results with a status, SI in the fields.

Each result shows itself in the interface units (km/h, bar, degrees, every column labelled): ``print(result)``
gives a text table, a notebook renders ``_repr_html_``, and ``result.table()`` is the :class:`Table` behind both.
The fields stay SI, as everywhere inside the code; the conversions go through :mod:`axles.units`.

>>> from comparisons.results import Table
>>> print(Table(("speed km/h", "frequency Hz"), (("16.106", "4.662"),)))
speed km/h  frequency Hz
----------  ------------
    16.106         4.662
"""

from __future__ import annotations

import html
import math
from dataclasses import dataclass, field

import numpy as np

from axles.axle import interface_text
from axles.units import BAR, kmh, to_interface
from comparisons.studies.margin_study import MarginPoint, MarginStudy
from bifurcation.cycles.problem import CycleBranch as ToolkitCycleBranch
from bifurcation.cycles.problem import CycleDiagram
from bifurcation.equilibria.hopf import HopfPoint as ToolkitHopfPoint
from bifurcation.messages import Message
from bifurcation.special_points import BranchStatus, Criticality, PointKind
from reduced_model.model import STATE_NAMES, STATE_UNITS
from reduced_model.trajectory import SimulationStatus, Trajectory

# The seconds at the end of a run over which a simulation's table reports each angle's peak (the shimmy amplitude
# once the transient has died out).
LAST_SECONDS = 1.0


def degrees(value: float, si_unit: str = "rad") -> float:
    """deg (or deg/s) of an angle in rad (or a rate in rad/s)."""
    return to_interface(value, si_unit)


def aligned(cell: str, width: int) -> str:
    """Numbers right-aligned (their digits line up), words left-aligned."""
    try:
        float(cell.split()[0])
    except (ValueError, IndexError):
        return cell.ljust(width)
    return cell.rjust(width)


@dataclass(frozen=True)
class Table:
    """Labelled columns (units in the labels) and formatted rows: text through ``str``, HTML for notebooks."""

    columns: tuple[str, ...]
    rows: tuple[tuple[str, ...], ...]
    title: str = ""

    def __str__(self) -> str:
        widths = [max([len(c)] + [len(r[i]) for r in self.rows]) for i, c in enumerate(self.columns)]
        lines = [self.title] if self.title else []
        lines.append("  ".join(c.ljust(w) for c, w in zip(self.columns, widths)).rstrip())
        lines.append("  ".join("-" * w for w in widths))
        lines += ["  ".join(aligned(cell, w) for cell, w in zip(r, widths)).rstrip() for r in self.rows]
        if not self.rows:
            lines.append("(none)")
        return "\n".join(lines)

    def _repr_html_(self) -> str:
        head = "".join(f"<th>{html.escape(c)}</th>" for c in self.columns)
        body = "".join("<tr>" + "".join(f"<td>{html.escape(x)}</td>" for x in r) + "</tr>" for r in self.rows)
        caption = f"<caption>{html.escape(self.title)}</caption>" if self.title else ""
        return f"<table>{caption}<thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>"


class Shown:
    """Display of a result through its :meth:`table` (text and HTML alike)."""

    def table(self) -> Table:
        raise NotImplementedError

    def __str__(self) -> str:
        return str(self.table())

    def _repr_html_(self) -> str:
        return self.table()._repr_html_()


# --- Hopf points ----------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class HopfSummary:
    """A Hopf point of straight running as the API shows it (the toolkit's :class:`~bifurcation.equilibria.hopf.HopfPoint`
    is ``point``): where shimmy sets in (SI).  ``first_lyapunov`` is NaN and
    ``criticality`` None where l1 could not be computed.  ``kink`` is the quadratic amplitude coefficient where the
    right-hand side has a kink at straight running (the full geometry's camber force), NaN elsewhere, and
    ``kink_criticality`` its reading at vanishing amplitude.  ``point`` is the toolkit's, for further analysis."""

    speed: float                      # m/s
    omega: float                      # rad/s
    first_lyapunov: float
    criticality: Criticality | None
    point: ToolkitHopfPoint = field(compare=False, repr=False)
    kink: float = float("nan")        # 1/s per unit of the state's norm (the eigenvector of norm 1)

    @classmethod
    def of(cls, point: ToolkitHopfPoint) -> "HopfSummary":
        return cls(point.p, point.omega, point.first_lyapunov, point.criticality, point, point.kink)

    @property
    def kink_criticality(self) -> Criticality | None:
        return self.point.kink_criticality

    @property
    def speed_kmh(self) -> float:
        return kmh(self.speed)

    @property
    def frequency_hz(self) -> float:
        return self.omega / (2.0 * math.pi)


@dataclass(frozen=True)
class HopfResult(Shown):
    """Every Hopf point in the speed window [vmin, vmax] (m/s), by speed.  The search seeds every candidate
    speed exactly (:mod:`bifurcation.equilibria.hopf`), so a returned result is complete; a point
    that does not converge raises instead."""

    title: str
    vmin: float                       # m/s
    vmax: float                       # m/s
    points: tuple[HopfSummary, ...]
    status: BranchStatus = BranchStatus.COMPLETE

    def table(self) -> Table:
        kinked = any(p.kink_criticality is not None for p in self.points)
        rows = tuple((f"{p.speed_kmh:.4f}", f"{p.frequency_hz:.3f}",
                      "-" if p.criticality is None else f"{p.first_lyapunov:+.4e}",
                      "-" if p.criticality is None else p.criticality.value)
                     + ((f"{p.kink:+.4e}" if p.kink_criticality else "-",
                         p.kink_criticality.value if p.kink_criticality else "-") if kinked else ())
                     for p in self.points)
        return Table(("speed km/h", "frequency Hz", "l1", "criticality")
                     + (("kink a", "criticality at the kink") if kinked else ()), rows,
                     f"Hopf points, {self.title}, {kmh(self.vmin):g}-{kmh(self.vmax):g} km/h "
                     f"({self.status.value})")


# --- cycle branches -------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class CyclePointOnBranch:
    """A detected point on a cycle branch (cycle fold, torus, period doubling): kind, speed (m/s) and the
    amplitude max|theta1| (rad) of the cycle there."""

    kind: PointKind
    speed: float
    theta1: float

    @property
    def speed_kmh(self) -> float:
        return kmh(self.speed)


@dataclass(frozen=True)
class BranchSummary:
    """One branch of limit cycles as the API shows it (the toolkit's
    :class:`~bifurcation.cycles.problem.CycleBranch` is ``branch``): limit cycles (shimmy oscillations) born at a Hopf point, SI: where it runs, its largest
    max|theta1| and the speed of that cycle, its frequencies and its special points.  ``status`` says how the
    continuation ended (``message``, the toolkit's, with its values by name; :meth:`CycleBranches.messages`
    shows it in interface units); ``branch`` is the toolkit's."""

    start: HopfSummary
    end: HopfSummary | None
    status: BranchStatus
    message: Message
    speeds: tuple[float, float]               # m/s, lowest and highest speed of a computed cycle
    peak_theta1: float                        # rad
    peak_speed: float                         # m/s
    frequencies: tuple[float, float]          # Hz
    stable: int                               # how many of the computed cycles are stable
    special_points: tuple[CyclePointOnBranch, ...]
    branch: ToolkitCycleBranch = field(compare=False, repr=False)

    @property
    def complete(self) -> bool:
        return self.status.is_complete

    @property
    def cycles(self) -> int:
        return len(self.branch.points)


@dataclass(frozen=True)
class CycleBranches(Shown):
    """The cycle branches born at the Hopf points in [vmin, vmax] (m/s).  ``status`` is the first incomplete
    branch's, or complete; ``diagram`` is the toolkit's (for plots)."""

    title: str
    vmin: float
    vmax: float
    hopf: tuple[HopfSummary, ...]
    branches: tuple[BranchSummary, ...]
    status: BranchStatus
    diagram: CycleDiagram = field(compare=False, repr=False)

    def table(self) -> Table:
        rows = []
        for b in self.branches:
            points = ", ".join(f"{p.kind.value} {p.speed_kmh:.2f}" for p in b.special_points) or "-"
            rows.append((f"{b.start.speed_kmh:.3f}", "-" if b.end is None else f"{b.end.speed_kmh:.3f}",
                         f"{kmh(b.speeds[0]):.2f}-{kmh(b.speeds[1]):.2f}", f"{degrees(b.peak_theta1):.4f}",
                         f"{kmh(b.peak_speed):.2f}", f"{b.frequencies[0]:.3f}-{b.frequencies[1]:.3f}",
                         f"{b.stable}/{b.cycles}", points, b.status.value))
        return Table(("from HB km/h", "to HB km/h", "speeds km/h", "peak max|theta1| deg", "at km/h",
                      "frequency Hz", "stable", "special points km/h", "status"), tuple(rows),
                     f"Limit-cycle branches, {self.title}, {kmh(self.vmin):g}-{kmh(self.vmax):g} km/h "
                     f"({self.status.value})")

    def messages(self) -> tuple[str, ...]:
        """How each branch ended, in interface units."""
        return tuple(interface_text(b.message) for b in self.branches)


def cycle_branch(branch: ToolkitCycleBranch, peak) -> BranchSummary:
    """The summary of a toolkit branch; ``peak`` is its cycle of largest max|theta1|
    (:func:`bifurcation.cycles.branches.branch_peak`)."""
    speeds = [p.p for p in branch.points]
    special = tuple(CyclePointOnBranch(s.kind, s.p, float(s.data["amplitude"][0]))
                    for s in sorted(branch.special_points, key=lambda s: s.bracket[0]))
    return BranchSummary(start=HopfSummary.of(branch.start), end=None if branch.end is None else HopfSummary.of(branch.end),
                       status=branch.status, message=branch.message, speeds=(min(speeds), max(speeds)),
                       peak_theta1=peak.max_abs("theta1"), peak_speed=peak.p,
                       frequencies=branch.frequency_range, stable=sum(p.stable for p in branch.points),
                       special_points=special, branch=branch)


# --- stability margins ----------------------------------------------------------------------------------------

@dataclass(frozen=True)
class StabilityMargins(Shown):
    """The least damping ratio of straight running over speed and tyre pressure (both tyres alike), with the mode
    it belongs to (:class:`comparisons.studies.margin_study.MarginStudy`, SI in its fields); ``minimum`` over the map's window.
    Negative: that mode grows (shimmy)."""

    title: str
    study: MarginStudy = field(repr=False)

    @property
    def minimum(self) -> MarginPoint | None:
        return self.study.minimum

    def table(self) -> Table:
        rows = []
        for p, m in zip(self.study.pressures, self.study.least_per_pressure()):
            rows.append((f"{p / BAR:.3f}",) + (("-", "-", "-", "none oscillates") if m is None else
                                                (f"{m.damping_ratio:+.4f}", f"{m.speed_kmh:.1f}",
                                                 f"{m.frequency_hz:.3f}", m.mode)))
        low = self.minimum
        where = ("no oscillatory mode" if low is None else
                 f"minimum {low.damping_ratio:+.4f} ({low.mode}, {low.frequency_hz:.3f} Hz) at {low.speed_kmh:.1f} "
                 f"km/h, {low.pressure_bar:.3f} bar")
        speeds = self.study.speeds
        return Table(("pressure bar", "least damping ratio", "at km/h", "frequency Hz", "mode"), tuple(rows),
                     f"Stability margins, {self.title}, {kmh(speeds[0]):g}-{kmh(speeds[-1]):g} km/h "
                     f"({len(speeds)} speeds): {where}")


# --- simulations ----------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class Simulation(Shown):
    """A time simulation of either model: ``status`` complete, or where it stopped (``message``).  The states
    are the reduced model's, SI, in ``trajectory`` (time s, states, speed m/s)."""

    title: str
    trajectory: Trajectory = field(repr=False)

    @property
    def status(self) -> SimulationStatus:
        return self.trajectory.status

    @property
    def message(self) -> Message:
        return self.trajectory.message

    @property
    def duration(self) -> float:
        """Simulated time, s (shorter than asked when the run stopped early)."""
        return float(self.trajectory.t[-1])

    def amplitude(self, name: str) -> float:
        """max |x_name| over the last :data:`LAST_SECONDS` s (SI), about the steady state under braking: the shimmy
        amplitude once settled."""
        t = self.trajectory.t
        return float(np.max(np.abs(self.trajectory.deviation(name)[t >= t[-1] - LAST_SECONDS])))

    def table(self) -> Table:
        rows = []
        for name, unit in zip(STATE_NAMES, STATE_UNITS):
            shown = "deg/s" if unit == "rad/s" else "deg"
            rows.append((name, f"{degrees(self.trajectory.state(name)[-1], unit):+.5f} {shown}",
                         f"{degrees(self.amplitude(name), unit):.5f} {shown}"))
        speed = self.trajectory.speed
        return Table(("state", "final", f"max |x|, last {LAST_SECONDS:g} s"), tuple(rows),
                     f"Simulation, {self.title}: {self.duration:g} s, {kmh(speed[0]):g} to {kmh(speed[-1]):g} km/h "
                     f"({self.status.value}{': ' + interface_text(self.message) if self.message else ''})")
