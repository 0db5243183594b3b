"""Input files (axle files, and tyre files): read so that no file can hang the reader, exhaust its memory or
escape as a traceback.

Every input file goes through :func:`read_text` and :func:`parse_toml`, and every number in it through
:func:`finite_number`; every failure is an :class:`InputFileError`, one line naming the file and, where known,
the line and the entry (``mytruck.toml:12: [table1] I1 ...``).  In order:

* before reading: only a regular file is opened (a device such as ``/dev/zero``, a FIFO without a writer or a
  socket is refused at once: the file is opened non-blocking and checked with ``fstat``), and at most
  :data:`MAX_BYTES` are read;
* before parsing: a scan of the text refuses nesting deeper than :data:`MAX_DEPTH` (the standard library's TOML
  parser recurses once per level and would end in a ``RecursionError``) and number literals longer than
  :data:`MAX_DIGITS` digits (Python refuses to convert integers of more than 4300 digits, and one of 400 digits
  overflows a float); the scan also records the line of each ``key =`` so that later errors can name it;
* after parsing: :func:`finite_number` refuses booleans, non-numbers, NaN, infinities and integers beyond
  :data:`MAX_MAGNITUDE` before any conversion to float.

The command line reports an :class:`InputFileError` as one line and exit code 2 (it is a
:class:`~axles.parameters.ParameterError`), the pytest plugin as one ``ERROR:`` line and exit code 4, and the
Python API raises it (a ``ValueError``) naming the file.
"""

from __future__ import annotations

import hashlib
import math
import numbers
import os
import re
import stat
import tomllib

from axles.parameters import ParameterError
from axles.text import printable

MAX_BYTES = 1 << 20          # 1 MiB: a complete axle file is about 10 kB
MAX_DEPTH = 16               # arrays and inline tables inside each other: axle files need 1
MAX_DIGITS = 100             # digits in one number literal: 1e100 is far beyond every physical range
MAX_MAGNITUDE = 1e300        # |n| of an integer: beyond it a float conversion (or a unit factor) overflows

_KEY = re.compile(r"[ \t]*([A-Za-z0-9_-]+)[ \t]*=")
_TABLE = re.compile(r"[ \t]*\[[ \t]*([A-Za-z0-9_.-]+)[ \t]*\]")


class InputFileError(ParameterError):
    """A bad input file, one line: ``FILE[:LINE]: message``.  ``file``, ``line`` (or None) and ``entry`` (or None)
    are kept for callers that show them differently."""

    def __init__(self, file: str, message: str, line: int | None = None, entry: str | None = None):
        where = f"{file}:{line}" if line is not None else f"{file}"
        super().__init__(printable(f"{where}: {message}"))
        self.file, self.line, self.entry = file, line, entry


def read_text(path: str, what: str = "input file", max_bytes: int = MAX_BYTES,
              error: type[InputFileError] = InputFileError) -> tuple[str, str]:
    """(UTF-8 text, sha256 hex) of the regular file ``path``, at most ``max_bytes`` long; ``error`` otherwise."""
    try:
        # Non-blocking: opening a FIFO without a writer returns at once instead of waiting for one.
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0))
    except OSError as exc:
        raise error(path, f"cannot read the {what} ({exc.strerror or exc})") from None
    except (ValueError, TypeError) as exc:      # a NUL character in the name, a name that is not text
        raise error(str(path), f"cannot read the {what} ({exc})") from None
    try:
        st = os.fstat(fd)
        if stat.S_ISDIR(st.st_mode):
            raise error(path, f"is a directory, not {_a(what)}")
        if not stat.S_ISREG(st.st_mode):
            raise error(path, f"not a regular file (a device, a FIFO or a socket): give {_a(what)}")
        if st.st_size > max_bytes:
            raise error(path, f"{st.st_size} bytes, more than the {max_bytes} {_a(what)} may have")
        chunks, size = [], 0
        while size <= max_bytes:
            chunk = os.read(fd, max_bytes + 1 - size)
            if not chunk:
                break
            chunks.append(chunk)
            size += len(chunk)
    except OSError as exc:
        raise error(path, f"cannot read the {what} ({exc.strerror or exc})") from None
    finally:
        os.close(fd)
    data = b"".join(chunks)
    if len(data) > max_bytes:     # it grew while being read
        raise error(path, f"more than the {max_bytes} bytes {_a(what)} may have")
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = data[:exc.start].count(b"\n") + 1
        raise error(path, "not a text file (TOML must be UTF-8)", line=line) from None
    return text, hashlib.sha256(data).hexdigest()


class TomlDocument:
    """A parsed TOML file: ``data`` (the standard library's dict) and the line of each ``key =``."""

    def __init__(self, data: dict, lines: dict[tuple[str, str], int], source: str,
                 error: type[InputFileError]):
        self.data, self.lines, self.source, self.error = data, lines, source, error

    def line(self, section: str, key: str) -> int | None:
        """The line of ``key`` in ``[section]`` (``""``: top level), None when the file does not give it."""
        return self.lines.get((section, key))

    def fail(self, message: str, section: str = "", key: str | None = None) -> InputFileError:
        """The error to raise: ``FILE:LINE: message`` with the line of ``key`` in ``[section]`` when it is known."""
        line = self.line(section, key) if key is not None else None
        entry = None if key is None else (f"[{section}] {key}" if section else key)
        return self.error(self.source, message, line=line, entry=entry)


def _scan(text: str, source: str, error: type[InputFileError]) -> dict[tuple[str, str], int]:
    """Refuse deep nesting and over-long numbers before the parser sees them; return each key's line.

    A small lexer: strings (basic, literal, multi-line) and comments are skipped, brackets and braces counted,
    runs of digits measured.  It does not validate TOML (the parser does); it only bounds what the parser gets.
    """
    lines: dict[tuple[str, str], int] = {}
    section, key, depth, digits = "", None, 0, 0
    line, i, n = 1, 0, len(text)
    at_line_start = True
    while i < n:
        c = text[i]
        if at_line_start and depth == 0:
            at_line_start = False
            m = _TABLE.match(text, i)
            if m:
                section = m.group(1)
            else:
                m = _KEY.match(text, i)
                if m:
                    key = m.group(1)
                    lines.setdefault((section, key), line)
        if c.isdigit() or (c == "_" and digits):
            digits += c != "_"
            if digits > MAX_DIGITS:
                raise error(source, f"a number of more than {MAX_DIGITS} digits"
                                    + (f" in '{key}'" if key else ""), line=line, entry=key)
            i += 1
            continue
        digits = 0
        if c == "\n":
            line, at_line_start = line + 1, True
        elif c == "#":
            while i < n and text[i] != "\n":
                i += 1
            continue
        elif c in "\"'":
            quote = text[i:i + 3] if text[i:i + 3] in ('"""', "'''") else c
            i += len(quote)
            while i < n and not text.startswith(quote, i):
                if text[i] == "\\" and quote[0] == '"':
                    i += 1
                elif text[i] == "\n":
                    if len(quote) == 1:
                        break            # an unterminated string: the parser reports it
                    line += 1
                i += 1
            i += len(quote)
            continue
        elif c in "[{":
            depth += 1
            if depth > MAX_DEPTH:
                raise error(source, f"nested more than {MAX_DEPTH} levels deep" + (f" in '{key}'" if key else ""),
                            line=line, entry=key)
        elif c in "]}":
            depth = max(depth - 1, 0)
        i += 1
    return lines


def parse_toml(text: str, source: str, error: type[InputFileError] = InputFileError) -> TomlDocument:
    """The parsed TOML ``text`` of the file ``source``, depth and digits bounded (see the module docstring)."""
    lines = _scan(text, source, error)
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        line = getattr(exc, "lineno", None)       # Python 3.14; before, only in the message
        if line is None:
            found = re.search(r"\(at line (\d+),", str(exc))
            line = int(found.group(1)) if found else None
        raise error(source, f"TOML syntax error: {exc}", line=line) from None
    except (ValueError, RecursionError, MemoryError) as exc:   # kept out by the scan; one line if it ever is not
        raise error(source, f"cannot parse the file ({type(exc).__name__}: {exc})") from None
    return TomlDocument(data, lines, source, error)


def finite_number(what: str, value, unit: str = "") -> float:
    """``value`` as a float when it is a finite real number, an integer of magnitude at most :data:`MAX_MAGNITUDE`
    (numpy scalars too, booleans not); else a :class:`ParameterError` naming ``what`` (and ``unit``), without ever
    converting an out-of-range value (``float(10**400)`` raises OverflowError)."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise ParameterError(f"{what} must be a number, got {type(value).__name__} {_short(value)}")
    if isinstance(value, numbers.Integral):
        value = int(value)
        if abs(value) > MAX_MAGNITUDE:
            digits = int(value.bit_length() * math.log10(2)) + 1   # str() refuses beyond 4300 digits
            raise ParameterError(f"{what} is too large (an integer of about {digits} digits"
                                 f"{', in ' + unit if unit else ''})")
        return float(value)
    try:
        value = float(value)
    except OverflowError:                        # a Fraction or Decimal beyond any float
        raise ParameterError(f"{what} is too large{' (in ' + unit + ')' if unit else ''}") from None
    if not math.isfinite(value):
        raise ParameterError(f"{what} must be a finite number, got {value!r}")
    return value    # a finite float that is too large is left to the range check, whose message names the range


def _short(value) -> str:
    text = repr(value)
    return printable(text if len(text) <= 60 else text[:57] + "...")


__all__ = ["InputFileError", "MAX_BYTES", "MAX_DEPTH", "MAX_DIGITS", "MAX_MAGNITUDE", "TomlDocument",
           "finite_number", "parse_toml", "read_text"]


def check_range(what: str, value, lo: float, hi: float, unit: str) -> float:
    """``value`` as a float, or a :class:`ParameterError` naming ``what`` and the range [lo, hi] (interface
    units): the check of an input at the interface (API arguments, pressures in bar).  numpy scalars are numbers;
    an integer too large for a float (``10**400``) is refused by name."""
    real = isinstance(value, numbers.Real) and not isinstance(value, (bool, numbers.Integral))
    if real and _nonfinite(value):
        value = float(value)    # NaN and infinities are outside every range: the message names the range
    else:
        value = finite_number(what, value, unit)
    if not lo <= value <= hi:
        raise ParameterError(f"{what} must be within [{lo:g}, {hi:g}] {unit}, got {value:g}")
    return value


def _nonfinite(value) -> bool:
    try:
        return not math.isfinite(float(value))
    except OverflowError:
        return False


def _a(what: str) -> str:
    """'an axle file', 'a tyre file'."""
    return f"{'an' if what[:1] in 'aeiou' else 'a'} {what}"
