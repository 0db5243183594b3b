"""Magic Formula 6.1/6.2 tyre property files (.tir, TYDEX format) in and out.

``shimmy params --tyre FILE.tir`` (and an axle file's ``tyre_file = "..."``) reads one onto an axle; ``shimmy
params --write-tir FILE.tir`` writes an axle's tyre.  Which key is which axle entry, with its sign, scaling, unit
and what is taken when a file has none: the one table :data:`axles.tyre_mapping.TYRE_KEYS`.

A file is a list of ``[SECTION]`` headers and ``KEY = VALUE`` lines; ``$`` starts a comment (also after a value),
``!`` a comment line; strings are in single quotes.  Anything wrong is one :class:`TyreFileError` line naming the
file, the line and the key: a missing section or key, a value that is not a number, an unknown FITTYP, a unit it
cannot convert, a coefficient outside the axle entry's physical range, a key given twice.  Keys the models do not
use are kept in :attr:`TyreFile.unused` and listed by ``shimmy params``, never dropped silently.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

from axles.axle import AxleData, entry
from axles.input_file import InputFileError
from axles.input_file import read_text as read_input
from axles.parameters import ParameterError
from axles.tyre_mapping import (
    EXTENSIONS,
    FITTYPS,
    REQUIRED,
    REQUIRED_SECTIONS,
    REQUIRED_UNITS,
    SCALES_MUST_BE,
    TIR_UNIT_KEYS,
    TYRE_KEYS,
    ZERO,
    scale_keys,
)
from axles.units import TIR_UNITS, tir_unit_factor

MAX_BYTES = 1_000_000   # a .tir file is some 20 kB; anything past 1 MB is not one


class TyreFileError(ParameterError):
    """A bad tyre property file: one line naming the file, the line and the key; exit 2 at the command line."""


@dataclass(frozen=True)
class Line:
    number: int
    section: str
    key: str
    raw: str          # the value as written (quotes removed for strings)
    quoted: bool


@dataclass(frozen=True)
class TyreFile:
    """What a .tir file gives an axle (SI) and what it holds that the models do not use."""

    source: str
    fittyp: int
    values: tuple[tuple[str, float], ...]       # (axle entry, SI value) read from the file, scalings folded in
    zeros: tuple[str, ...]                      # entries the file lacks that are 0 (the term is absent)
    kept: tuple[str, ...]                       # entries the file lacks that stay the axle's
    unused: tuple[str, ...]                     # "[SECTION] KEY" the file has and neither model uses
    absent_sections: tuple[str, ...]            # optional sections the file does not have

    def entries(self) -> dict[str, float]:
        """Every entry the tyre sets (SI): the file's values and the absent terms' zeros."""
        return {**dict(self.values), **{name: 0.0 for name in self.zeros}}


class TyreReadError(InputFileError, TyreFileError):
    """A tyre file that cannot be read as text (:func:`axles.input_file.read_text`)."""


def read_text(path: str) -> str:
    """The text of a tyre file, through the one reader of every input file (:func:`axles.input_file.read_text`: a
    regular file, devices and FIFOs refused at once, at most :data:`MAX_BYTES`, UTF-8)."""
    return read_input(path, "tyre file", max_bytes=MAX_BYTES, error=TyreReadError)[0]


def _strip_comment(text: str) -> str:
    """The part of a line before a ``$`` comment that is not inside single quotes."""
    quoted = False
    for i, c in enumerate(text):
        if c == "'":
            quoted = not quoted
        elif c == "$" and not quoted:
            return text[:i]
    return text


def _lines(text: str, source: str) -> tuple[dict[str, dict[str, Line]], dict[str, int], list[str]]:
    """(section -> key -> line, section -> its header's line number, table lines of sections) of a file."""
    sections: dict[str, dict[str, Line]] = {}
    headers: dict[str, int] = {}
    tables: list[str] = []
    section = ""
    for number, full in enumerate(text.splitlines(), start=1):
        line = _strip_comment(full).strip()
        if not line or line.startswith("!"):
            continue
        if line.startswith("[") and line.endswith("]"):
            section = line[1:-1].strip().upper()
            if section in headers:
                raise TyreFileError(f"{source}:{number}: section [{section}] given twice (first on line "
                                    f"{headers[section]})")
            headers[section] = number
            sections[section] = {}
            continue
        if "=" not in line:
            tables.append(f"[{section}] line {number}")
            continue
        key, _, value = line.partition("=")
        key, value = key.strip().upper(), value.strip()
        quoted = len(value) >= 2 and value.startswith("'") and value.endswith("'")
        here = sections.setdefault(section, {})
        if key in here:
            raise TyreFileError(f"{source}:{number}: [{section}] {key} given twice (first on line "
                                f"{here[key].number})")
        here[key] = Line(number, section, key, value[1:-1].strip() if quoted else value, quoted)
    return sections, headers, tables


def _number(line: Line, source: str) -> float:
    where = f"{source}:{line.number}: [{line.section}] {line.key}"
    if line.quoted:
        raise TyreFileError(f"{where} = '{line.raw}' is not a number")
    try:
        value = float(line.raw.replace("D", "E").replace("d", "e"))   # Fortran exponents, 1.0D+00
    except ValueError:
        raise TyreFileError(f"{where} = {line.raw!r} is not a number") from None
    if not math.isfinite(value):
        raise TyreFileError(f"{where} = {line.raw} is not a finite number")
    return value


def _unit_factors(units: dict[str, Line], source: str) -> dict[str, float]:
    """SI per file unit of each quantity the table's keys have."""
    factors = {}
    for name in TIR_UNIT_KEYS:
        line = units.get(name)
        if line is None:
            if name in REQUIRED_UNITS:
                raise TyreFileError(f"{source}: missing key [UNITS] {name}")
            continue
        factor = tir_unit_factor(name, line.raw)
        if factor is None:
            known = ", ".join(f"'{u}'" for u in TIR_UNITS[name])
            raise TyreFileError(f"{source}:{line.number}: [UNITS] {name} = '{line.raw}': a unit it cannot convert "
                                f"(known: {known})")
        factors[name] = factor
    length, force = factors["LENGTH"], factors["FORCE"]
    return {"length": length, "force": force, "stiffness": force / length,
            "pressure": factors.get("PRESSURE", force / length ** 2)}


def _find(sections, row) -> Line | None:
    for name in (row.section,) + row.also_in:
        line = sections.get(name, {}).get(row.key)
        if line is not None:
            return line
    return None


def parse_tir(text: str, source: str = "<tyre>") -> TyreFile:
    """The tyre a .tir file's text describes; :class:`TyreFileError` for anything wrong."""
    sections, headers, tables = _lines(text, source)
    for name in REQUIRED_SECTIONS:
        if name not in sections:
            raise TyreFileError(f"{source}: missing section [{name}]")
    model = sections["MODEL"]
    if "FITTYP" not in model:
        raise TyreFileError(f"{source}: missing key [MODEL] FITTYP (61 for MF 6.1, 62 for MF 6.2)")
    fit_line = model["FITTYP"]
    fittyp = _number(fit_line, source)
    if fittyp not in FITTYPS:
        raise TyreFileError(f"{source}:{fit_line.number}: [MODEL] FITTYP = {fit_line.raw}: unknown FITTYP (this "
                            f"reader takes {', '.join(f'{k} ({v})' for k, v in FITTYPS.items())})")
    factors = _unit_factors(sections["UNITS"], source)

    scaling = sections.get("SCALING_COEFFICIENTS", {})
    scales = {}
    for name in scale_keys():
        line = scaling.get(name)
        scales[name] = SCALES_MUST_BE.get(name, 1.0) if line is None else _number(line, source)
        if line is not None and name in SCALES_MUST_BE and scales[name] != SCALES_MUST_BE[name]:
            raise TyreFileError(f"{source}:{line.number}: [SCALING_COEFFICIENTS] {name} = {line.raw}: only "
                                f"{SCALES_MUST_BE[name]:g} is supported (it acts on a term the models use in a way "
                                f"that cannot be folded into their coefficients)")

    values: list[tuple[str, float]] = []
    zeros, kept, used = [], [], set()
    for row in TYRE_KEYS:
        line = _find(sections, row)
        if line is None:
            if row.missing == REQUIRED:
                raise TyreFileError(f"{source}: missing key [{row.section}] {row.key} (the axle's {row.entry})")
            (zeros if row.missing == ZERO else kept).append(row.entry)
            continue
        used.add((line.section, line.key))
        value = _number(line, source) * row.sign
        for s in row.scales:
            value *= scales[s]
        if row.quantity is not None:
            value *= factors[row.quantity]
        try:
            entry(row.entry).check(value)
        except ParameterError as exc:
            raise TyreFileError(f"{source}:{line.number}: [{line.section}] {row.key} = {line.raw} gives {exc}"
                                + (" (MF 6.1 writes PKY1 negative)" if row.key == "PKY1" else "")) from None
        values.append((row.entry, value))

    used |= {("MODEL", "FITTYP")} | {("UNITS", k) for k in TIR_UNIT_KEYS}
    used |= {("SCALING_COEFFICIENTS", k) for k in scale_keys()}
    unused = [f"[{section}] {key}" for section, keys in sections.items() for key in keys
              if (section, key) not in used and section != "MDI_HEADER"]
    unused += tables
    absent = tuple(s for s in ("STRUCTURAL", "LONGITUDINAL_COEFFICIENTS", "SCALING_COEFFICIENTS", EXTENSIONS)
                   if s not in headers)
    return TyreFile(source=source, fittyp=int(fittyp), values=tuple(values), zeros=tuple(zeros), kept=tuple(kept),
                    unused=tuple(unused), absent_sections=absent)


def read_tir(path: str) -> TyreFile:
    return parse_tir(read_text(path), source=path)


def apply_tyre(axle: AxleData, tyre: TyreFile) -> AxleData:
    """The axle with the tyre's entries (the rest, and the entries the file lacks that stay the axle's, kept)."""
    try:
        out = axle.with_values(tyre.entries())
    except ParameterError as exc:   # a combination the models cannot take (a wheel too light for I1, ...)
        raise TyreFileError(f"{tyre.source}: {exc}") from None
    return dataclasses.replace(out, tyre_file=tyre.source)


def _value(x: float) -> str:
    """A float written so that reading it back gives the same float."""
    return repr(float(x))


def format_tir(axle: AxleData) -> str:
    """An MF 6.1 property file of the axle's tyre: every coefficient the models use, SI units, all scalings 1."""
    lines = [
        "[MDI_HEADER]",
        "FILE_TYPE                = 'tir'",
        "FILE_VERSION             = 3.0",
        "FILE_FORMAT              = 'ASCII'",
        f"! : COMMENT : the tyre of axle '{axle.name}', written by 'shimmy params --write-tir'",
        "! : COMMENT : the coefficients the shimmy models use (docs/axle-files.md lists which is which); the",
        f"! : COMMENT : paper's extensions beyond MF 6.1 are in [{EXTENSIONS}], which other MF tools ignore",
        "$----------------------------------------------------------------units",
        "[UNITS]",
        "LENGTH                   = 'meter'",
        "FORCE                    = 'newton'",
        "ANGLE                    = 'radians'",
        "MASS                     = 'kg'",
        "TIME                     = 'second'",
        "$----------------------------------------------------------------model",
        "[MODEL]",
        "FITTYP                   = 61                    $Magic Formula version number (MF 6.1)",
    ]
    pi0 = axle.value("pi0")
    order = ("DIMENSION", "OPERATING_CONDITIONS", "VERTICAL", "STRUCTURAL", "SCALING_COEFFICIENTS",
             "LONGITUDINAL_COEFFICIENTS", "LATERAL_COEFFICIENTS", "ALIGNING_COEFFICIENTS", EXTENSIONS)
    for section in order:
        lines += [f"${'-' * 64}{section.lower()}", f"[{section}]"]
        if section == "OPERATING_CONDITIONS":
            lines.append(f"{'INFLPRES':24s} = {_value(pi0):21s} $Tyre inflation pressure (not used: --pressure)")
        if section == "SCALING_COEFFICIENTS":
            for name in scale_keys():
                lines.append(f"{name:24s} = {_value(SCALES_MUST_BE.get(name, 1.0)):21s} $scaling factor")
        for row in TYRE_KEYS:
            if row.section != section:
                continue
            e = entry(row.entry)
            value = axle.value(row.entry) / row.sign   # SI, as the [UNITS] above say
            lines.append(f"{row.key:24s} = {_value(value):21s} ${row.symbol}: {' '.join(e.description.split())}")
    return "\n".join(lines) + "\n"


__all__ = ["TyreFile", "TyreFileError", "apply_tyre", "format_tir", "parse_tir", "read_text", "read_tir"]
