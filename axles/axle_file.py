"""Axle files: one TOML file describes one axle (``shimmy params --write FILE.toml``, ``--axle FILE.toml``).

Layout (values in the interface units that ``shimmy params`` prints: degrees, bar, otherwise SI)::

    name = "my-truck"
    base = "YANG2024"          # optional: missing entries come from the paper's axle, listed as inherited
    tyre_file = "my.tir"       # optional: the tyre entries from an MF 6.1/6.2 file (path relative to this file)

    [operating]
    pressure_range_bar = [0.5, 3.5]

    [table1]                   # every Table 1 entry of the reduced model
    I1 = 6.0                   # kg m^2 | description | source
    ...
    [multibody]                # every dimension of the multibody axle that the paper does not give
    wheel_mass = 40.0
    ...
    [plausible]                # where each invented dimension plausibly lies, for robustness studies
    wheel_mass = [30.0, 60.0]

Reading goes through :mod:`axles.input_file` (size, file type, nesting and numbers bounded before
parsing with the standard library's :mod:`tomllib`).  Writing is plain text because TOML writers (tomli-w) cannot
put the unit, description and source beside each value as a comment; every written file is read back by the tests.
Without ``base`` every entry must be given: nothing is ever filled in silently.
"""

from __future__ import annotations

import os

from axles.axle import DEFAULT_PRESSURE_RANGE_BAR, PAPER_NAME, AxleData, check_pressure_range, entries, entry
from axles.input_file import InputFileError, TomlDocument, finite_number, parse_toml, read_text
from axles.parameters import ParameterError
from axles.tyre_file import apply_tyre, read_tir
from bifurcation.messages import message_of

SECTIONS = ("operating", "table1", "multibody", "plausible")
TOP_KEYS = ("name", "base", "tyre_file") + SECTIONS
BASES = (PAPER_NAME,)


class AxleFileError(InputFileError):
    """A bad axle file: one line naming the file and, where known, the line and the entry; exit code 2."""


def did_you_mean(name: str, known) -> str:
    """" (did you mean 'x'?)" for the closest of ``known`` to a misspelt ``name``, else ""."""
    import difflib
    close = difflib.get_close_matches(name, list(known), n=1)
    return f" (did you mean '{close[0]}'?)" if close else ""


def _number(doc: TomlDocument, section: str, key: str, value) -> float:
    try:
        return finite_number(f"[{section}] {key}", value)
    except ParameterError as exc:
        raise doc.fail(str(exc), section, key) from None


def _pair(doc: TomlDocument, section: str, key: str, value) -> tuple[float, float]:
    if not isinstance(value, list) or len(value) != 2:
        raise doc.fail(f"[{section}] {key} must be a list of two numbers [LO, HI], got {_shown(value)}", section,
                       key)
    lo, hi = (_number(doc, section, key, v) for v in value)
    if not lo <= hi:
        raise doc.fail(f"[{section}] {key} needs LO <= HI, got [{lo:g}, {hi:g}]", section, key)
    return lo, hi


def _shown(value) -> str:
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


def parse_axle(text: str, source: str = "<axle>", sha256: str | None = None) -> AxleData:
    """The axle a file's text describes; :class:`AxleFileError` (one line, naming the file, the line and the
    entry) for anything wrong, including entries that contradict each other (:meth:`AxleData.check_consistent`)."""
    doc = parse_toml(text, source, AxleFileError)
    data = doc.data
    for key in data:
        if key not in TOP_KEYS:
            e = entries().get(key)
            hint = f" (it belongs in [{e.section}])" if e is not None else did_you_mean(key, TOP_KEYS)
            raise doc.fail(f"unknown key '{key}'{hint}", "", key)
    for key in SECTIONS:
        if key in data and not isinstance(data[key], dict):
            raise doc.fail(f"'{key}' must be a table [{key}]", "", key)
    name = data.get("name")
    if not isinstance(name, str) or not name.strip():
        raise doc.fail(f"'name' must be a non-empty string, got {_shown(name)}", "", "name")
    base = data.get("base")
    if base is not None and base not in BASES:
        raise doc.fail(f"base must be one of {', '.join(repr(b) for b in BASES)}, got {_shown(base)}", "", "base")

    tyre = _tyre_of(data, source)
    from_tyre = tyre.entries() if tyre is not None else {}
    values: dict[str, float] = {}
    inherited: list[str] = []
    for section in ("table1", "multibody"):
        given = data.get(section, {})
        for key in given:
            if key in from_tyre:
                raise doc.fail(f"[{section}] {key} is also given by tyre_file {tyre.source}: give it in one place",
                               section, key)
        for key, raw in given.items():
            e = entries().get(key)
            if e is None or e.section != section:
                other = f" (it belongs in [{e.section}])" if e is not None else did_you_mean(key, [
                    n for n, x in entries().items() if x.section == section])
                raise doc.fail(f"unknown entry '{key}' in [{section}]{other}", section, key)
            v = e.to_si(_number(doc, section, key, raw))
            try:
                e.check(v)
            except ParameterError as exc:
                raise doc.fail(f"[{section}] {exc}", section, key) from None
            values[key] = v
        for key, e in entries().items():
            if e.section == section and key not in given and key not in from_tyre:
                if base is None:
                    raise doc.fail(f"missing entry '{key}' in [{section}] ({e.unit}, {e.description}; give it, or "
                                   f"write base = \"{PAPER_NAME}\" to inherit the paper's values)")
                inherited.append(key)

    plausible: list[tuple[str, tuple[float, float]]] = []
    given = data.get("plausible", {})
    for key, raw in given.items():
        e = entries().get(key)
        if e is None or e.section != "multibody":
            raise doc.fail(f"unknown entry '{key}' in [plausible]"
                           + did_you_mean(key, [n for n, x in entries().items() if x.section == "multibody"]),
                           "plausible", key)
        lo, hi = _pair(doc, "plausible", key, raw)
        lo_si, hi_si = e.to_si(lo), e.to_si(hi)
        for v in (lo_si, hi_si):
            try:
                e.check(v, where="plausible ")
            except ParameterError as exc:
                raise doc.fail(f"[plausible] {exc}", "plausible", key) from None
        plausible.append((key, (lo_si, hi_si)))
    for key, e in entries().items():
        if e.section == "multibody" and key not in given:
            if base is None:
                raise doc.fail(f"missing entry '{key}' in [plausible] (a range [LO, HI] in {e.unit}; or write "
                               f"base = \"{PAPER_NAME}\")")
            inherited.append(f"plausible.{key}")

    operating = data.get("operating", {})
    for key in operating:
        if key != "pressure_range_bar":
            raise doc.fail(f"unknown key '{key}' in [operating]" + did_you_mean(key, ["pressure_range_bar"]),
                           "operating", key)
    if "pressure_range_bar" in operating:
        lo, hi = _pair(doc, "operating", "pressure_range_bar", operating["pressure_range_bar"])
        try:
            pressure_range = check_pressure_range(lo, hi, "[operating] ")
        except ParameterError as exc:
            raise doc.fail(str(exc), "operating", "pressure_range_bar") from None
    elif base is None:
        raise doc.fail(f"missing entry 'pressure_range_bar' in [operating] ([LO, HI] in bar; or write "
                       f"base = \"{PAPER_NAME}\")")
    else:
        pressure_range = DEFAULT_PRESSURE_RANGE_BAR
        inherited.append("operating.pressure_range_bar")

    axle = AxleData(name=name.strip(), pressure_range_bar=pressure_range, plausible=tuple(plausible),
                file=source, sha256=sha256, inherited=tuple(inherited))
    try:
        axle = axle.with_values(values)
        if tyre is not None:
            axle = apply_tyre(axle, tyre)
        axle.check_consistent()
    except ParameterError as exc:   # a combination the models cannot take: named at the first entry involved
        involved = [q.name for q in message_of(exc).quantities if q.name in values]
        section = entries()[involved[0]].section if involved else ""
        raise doc.fail(str(exc), section, involved[0] if involved else None) from None
    return axle


def _tyre_of(doc: dict, source: str):
    """The tyre file an axle file names (``tyre_file``, relative to the axle file), read; None if it names none."""
    path = doc.get("tyre_file")
    if path is None:
        return None
    if not isinstance(path, str) or not path.strip():
        raise AxleFileError(f"{source}: tyre_file must be a non-empty string (a .tir file), got {path!r}")
    if not os.path.isabs(path) and not source.startswith("<"):
        path = os.path.join(os.path.dirname(source), path)
    return read_tir(path)




def read_axle(path: str) -> AxleData:
    """Read an axle file (:func:`axles.input_file.read_text`: a regular file of at most 1 MiB); unreadable files
    and bad contents raise :class:`AxleFileError`."""
    text, sha256 = read_text(path, "axle file", error=AxleFileError)
    return parse_axle(text, source=path, sha256=sha256)


def _toml_string(s: str) -> str:
    return '"' + s.replace("\\", "\\\\").replace('"', '\\"') + '"'


def _toml_float(x: float) -> str:
    text = repr(float(x))
    return text if ("." in text or "e" in text or "inf" in text or "nan" in text) else text + ".0"


def _comment(text: str) -> str:
    return " ".join(text.split())


def format_axle(axle: AxleData, name: str | None = None) -> str:
    """The axle file text of an axle: every entry, its unit, description and source beside it; ``name`` (default
    the axle's own) is the file's ``name``."""
    lines = [
        "# shimmy axle file: one truck front axle (written by 'shimmy params --write').",
        "# Values in the units shown: angles in degrees, pressures in bar, everything else SI.",
        "# Each value carries its unit | description | source as a comment. Every entry must be given, unless",
        f"# base = \"{PAPER_NAME}\" is set: then missing entries come from the paper's axle and are reported as",
        "# inherited. Read with: shimmy COMMAND --axle THIS_FILE",
        "",
        f"name = {_toml_string(axle.name if name is None else name)}",
        "",
        "[operating]",
        f"pressure_range_bar = [{_toml_float(axle.pressure_range_bar[0])}, "
        f"{_toml_float(axle.pressure_range_bar[1])}]   # bar | pressures that 'shimmy verify --axle' scans",
    ]
    titles = {"table1": "Table 1 of the reduced model (Yang, Knowles & Mavros); physical range in brackets",
              "multibody": "dimensions of the multibody axle that the paper does not give"}
    for section in ("table1", "multibody"):
        lines += ["", f"[{section}]   # {titles[section]}"]
        for name, e in entries().items():
            if e.section != section:
                continue
            lo, hi = e.range
            value = _toml_float(e.to_interface(axle.value(name)))
            neutral = "" if e.neutral is None else f" | neutral {e.neutral:g}"
            lines.append(f"{name} = {value}".ljust(34) + f" # {e.unit} | {_comment(e.description)} | "
                         f"{_comment(e.source)} | range [{lo:g}, {hi:g}]{neutral}")
    lines += ["", "[plausible]   # where each chosen dimension plausibly lies on a real truck beam axle ([LO, HI])"]
    for name, e in entries().items():
        if e.section != "multibody":
            continue
        lo, hi = (e.to_interface(v) for v in axle.plausible_range(name))
        lines.append(f"{name} = [{_toml_float(lo)}, {_toml_float(hi)}]".ljust(44) + f" # {e.unit}")
    return "\n".join(lines) + "\n"


def axle_from_path_or_paper(path: str | None) -> AxleData:
    if path is None:
        from axles.axle import paper_axle
        return paper_axle()
    return read_axle(path)


__all__ = ["AxleFileError", "axle_from_path_or_paper", "format_axle", "parse_axle", "read_axle",
           "entry"]
