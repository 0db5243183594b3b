"""Text from files and users shown on one line (standard library only: the command imports it before the model
packages, to report signals and errors)."""

from __future__ import annotations


def printable(text: str) -> str:
    """``text`` with control characters and line breaks escaped (``\\n``, ``\\x1b``): one line whatever a file or
    an option holds.  Undecodable bytes of a file name (``surrogateescape``) are kept, to be printed as they are."""
    if text.isprintable():
        return text
    return "".join(c if c.isprintable() or 0xDC80 <= ord(c) <= 0xDCFF else repr(c)[1:-1] for c in text)
