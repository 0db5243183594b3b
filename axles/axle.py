"""One truck front axle: the paper's Table 1 entries, the multibody dimensions, plausible ranges, pressure window.

An :class:`AxleData` holds an axle's entries, as an axle file or ``--set`` gives them (the API's
:class:`comparisons.api.Axle` wraps it with the models made from it).  The paper's axle is :func:`paper_axle`; others come
from an axle file (:mod:`axles.axle_file`) and ``--set NAME=VALUE`` on top.  Values are SI inside; the
interface shows them in the units of :mod:`axles.units` (degrees, bar).  Entry names are one namespace over
:class:`~axles.parameters.ShimmyParameters` ("table1") and :class:`~axles.dimensions.AxleDimensions`
("multibody"), so both are read, written, overridden and swept the same way.
"""

from __future__ import annotations

import dataclasses
import difflib
import math
from dataclasses import dataclass, field
from functools import lru_cache
from typing import Mapping

from axles.limits import PRESSURE_RANGE_BAR
from axles.units import BAR, interface_of, to_interface, to_si
from bifurcation.messages import Message, Quantity, message_of
from axles.dimensions import DEFAULT_DIMENSIONS, AxleDimensions
from axles.braking import BRAKE_PARAMS
from axles.pressures import PRESSURE_PARAMS
from axles.text import printable
from axles.parameters import YANG2024, ParameterError, ShimmyParameters

PAPER_NAME = "YANG2024"
DEFAULT_PRESSURE_RANGE_BAR = (0.5, 3.5)
CHOSEN = "chosen for the multibody model (not in the paper)"


@dataclass(frozen=True)
class Entry:
    """One entry of an axle: where it lives, its units and documentation."""

    name: str
    section: str            # "table1" or "multibody"
    si_unit: str
    description: str
    source: str
    range_si: tuple[float, float]
    plausible_si: tuple[float, float] | None
    printed: str = ""       # the symbol as Table 1 prints it, where the OCR garbled it
    neutral_si: float | None = None   # a dimension's value at which its element has no effect (None: no such value)

    @property
    def unit(self) -> str:
        """The unit shown at the interface."""
        return interface_of(self.si_unit)[0]

    def to_interface(self, value: float) -> float:
        return to_interface(value, self.si_unit)

    def to_si(self, value: float) -> float:
        return to_si(value, self.si_unit)

    @property
    def range(self) -> tuple[float, float]:
        return tuple(self.to_interface(v) for v in self.range_si)

    @property
    def neutral(self) -> float | None:
        """The neutral value in interface units (None: the entry has none)."""
        return None if self.neutral_si is None else self.to_interface(self.neutral_si)

    def check(self, value_si: float, where: str = "") -> None:
        """Raise :class:`ParameterError` naming the range in interface units."""
        lo, hi = self.range_si
        shown = self.to_interface(value_si) if math.isfinite(value_si) else value_si
        if not math.isfinite(value_si) or not lo <= value_si <= hi:
            a, b = self.range
            raise ParameterError(Message.of(where, Quantity(self.name, shown, 6, self.unit),
                                            f" is outside its physical range [{a:g}, {b:g}] {self.unit}"))


@lru_cache(maxsize=None)
def entries() -> dict[str, Entry]:
    """Every entry of an axle by name, Table 1 first (in the paper's order), then the multibody dimensions."""
    out: dict[str, Entry] = {}
    for f_ in dataclasses.fields(ShimmyParameters):
        m = f_.metadata
        out[f_.name] = Entry(f_.name, "table1", m["unit"], m["description"], m["source"], tuple(m["range"]), None,
                             m["printed"])
    for f_ in dataclasses.fields(AxleDimensions):
        m = f_.metadata
        if f_.name in out:
            raise RuntimeError(f"entry name {f_.name} is both a Table 1 entry and a dimension")
        out[f_.name] = Entry(f_.name, "multibody", m["unit"], m["reason"], m.get("source", CHOSEN),
                             tuple(m["range"]), tuple(m["plausible"]), neutral_si=m.get("neutral"))
    return out


def entry(name: str, what: str = "entry") -> Entry:
    """The entry of that name, or a :class:`ParameterError` naming the closest known one."""
    found = entries().get(name)
    if found is None:
        close = difflib.get_close_matches(name, list(entries()), n=1)
        hint = f" (did you mean '{close[0]}'?)" if close else " (see 'shimmy params')"
        raise ParameterError(f"unknown {what} '{name}'{hint}")
    return found


@dataclass(frozen=True)
class AxleData:
    """The entries of a truck front axle (SI inside).  ``plausible``: (name, (lo, hi)) in SI for the dimensions nobody measured."""

    name: str = PAPER_NAME
    params: ShimmyParameters = YANG2024
    dims: AxleDimensions = DEFAULT_DIMENSIONS
    pressure_range_bar: tuple[float, float] = DEFAULT_PRESSURE_RANGE_BAR
    plausible: tuple[tuple[str, tuple[float, float]], ...] = ()
    file: str | None = None
    sha256: str | None = None
    inherited: tuple[str, ...] = ()
    overrides: tuple[tuple[str, float], ...] = field(default=())   # --set, interface units, in order
    tyre_file: str | None = None     # the .tir file the tyre entries were read from (--tyre, an axle's tyre_file)

    def value(self, name: str) -> float:
        """SI value of an entry."""
        e = entry(name)
        return getattr(self.params if e.section == "table1" else self.dims, name)

    def interface_value(self, name: str) -> float:
        return entry(name).to_interface(self.value(name))

    def plausible_range(self, name: str) -> tuple[float, float] | None:
        """SI plausible range of a dimension (from the file, else the dimension's default)."""
        for n, r in self.plausible:
            if n == name:
                return r
        return entry(name).plausible_si

    def with_values(self, values_si: Mapping[str, float]) -> "AxleData":
        """A copy with entries replaced (SI), each checked against its physical range."""
        table1, multibody = {}, {}
        for name, value in values_si.items():
            e = entry(name)
            e.check(float(value))
            (table1 if e.section == "table1" else multibody)[name] = float(value)
        return dataclasses.replace(self, params=self.params.replace(**table1) if table1 else self.params,
                                   dims=self.dims.replace(**multibody) if multibody else self.dims)

    def with_overrides(self, items: Mapping[str, float]) -> "AxleData":
        """``--set NAME=VALUE`` in interface units, applied on top of this axle."""
        si = {name: entry(name).to_si(v) for name, v in items.items()}
        out = self.with_values(si)
        return dataclasses.replace(out, overrides=self.overrides + tuple((k, float(v)) for k, v in items.items()))

    @property
    def shown_name(self) -> str:
        """The name for text: line breaks and escape characters escaped, so that a header stays one line."""
        return printable(self.name)

    def check_consistent(self) -> None:
        """Raise :class:`ParameterError` when entries contradict each other, although each lies in its range: an
        I1 below the wheel's own inertia about the kingpin, an I2 above twice the wheel's diametral inertia
        (:meth:`AxleDimensions.check`).  Checked when an axle file is read and before ``verify`` plans its work;
        the reduced model alone does not need it, so ``--set`` and sweeps of the reduced model are not refused."""
        self.dims.check(self.params)

    @property
    def is_paper(self) -> bool:
        """Same Table 1 as the paper: the paper's printed numbers apply (the chosen dimensions do not enter them)."""
        return self.params == YANG2024

    def differences(self) -> list[dict]:
        """Entries that differ from the paper's axle, in interface units."""
        out = []
        paper = AxleData()
        for name, e in entries().items():
            mine, ref = self.value(name), paper.value(name)
            if mine != ref:
                out.append({"name": name, "value": e.to_interface(mine), "paper": e.to_interface(ref),
                            "unit": e.unit})
        return out

    def describe(self) -> dict:
        """The ``"axle"`` object of every JSON output and report."""
        out = {"name": self.name, "file": self.file, "sha256": self.sha256,
               "differs_from_paper": self.differences(), "inherited": list(self.inherited),
               "overrides": {k: v for k, v in self.overrides}}
        if self.tyre_file is not None:
            out["tyre_file"] = self.tyre_file
        return out

    def label(self) -> str:
        """One line for text headers."""
        diff = self.differences()
        # a name or file name holding a line break or an escape character is shown escaped, on one line
        where = f" ({printable(self.file)})" if self.file else ""
        name = self.shown_name
        if self.tyre_file:
            where += f" with the tyre {printable(self.tyre_file)}"
        if not diff:
            return f"axle {name}{where}: the paper's values"
        shown = ", ".join(f"{d['name']} = {d['value']:g} {d['unit']}".replace(" -", "") for d in diff[:6])
        more = f", and {len(diff) - 6} more" if len(diff) > 6 else ""
        return f"axle {name}{where}: differs from the paper in {shown}{more}"


def paper_axle() -> AxleData:
    """Yang, Knowles & Mavros' truck (Table 1) with the chosen multibody dimensions."""
    return AxleData()


def check_pressure_range(lo: float, hi: float, where: str = "") -> tuple[float, float]:
    low, high = PRESSURE_RANGE_BAR
    if not (math.isfinite(lo) and math.isfinite(hi) and low <= lo < hi <= high):
        raise ParameterError(f"{where}pressure range must satisfy {low:g} <= LO < HI <= {high:g} bar, "
                             f"got [{lo:g}, {hi:g}]")
    return float(lo), float(hi)


def interface_unit(name: str) -> tuple[str, float]:
    """(unit label, SI per interface unit) of an axle entry, a pressure or a brake slip at the command line."""
    if name in PRESSURE_PARAMS:
        return "bar", BAR
    if name in BRAKE_PARAMS:
        return "-", 1.0
    from axles.axle import entry
    return interface_of(entry(name).si_unit)


def interface_quantity(quantity: Quantity) -> str:
    """One value of a message in interface units: a speed as "150 km/h" (its unit says which parameter it is), a
    pressure or an axle entry as "pressure = 1.5 bar", "t0 = 0.25 m"; a name the interface has no unit for
    (a state, a test oscillator's parameter) as the toolkit wrote it, and so is a value its message gave a unit."""
    if quantity.unit:
        return str(quantity)
    if quantity.name == "speed":
        unit, factor = interface_of("m/s")
        return f"{quantity.shown_value / factor:.6g} {unit}"
    if quantity.name not in PRESSURE_PARAMS and quantity.name not in entries():
        return str(quantity)
    unit, factor = interface_unit(quantity.name)
    if factor == 1.0 and unit in ("", "-"):
        return str(quantity)
    return f"{quantity.name} = {quantity.shown_value / factor:.6g} {unit}"


def interface_text(message: Message | BaseException | str) -> str:
    """A message of the toolkit or a model (or the exception that carries one) in interface units, so that
    speed = 41.66667 m/s and pressure = 150000 Pa read "150 km/h, pressure = 1.5 bar"."""
    return message_of(message).show(interface_quantity)
