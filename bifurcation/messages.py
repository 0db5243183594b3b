"""Messages of the toolkit: text with the parameter values it names kept as values, by name, in SI.

A status alone says what happened (``BranchStatus``, an exception's class); its message says where. diffrax gives
every result a status and a message; here the message keeps its numbers as :class:`Quantity` parts, so that an
interface shows each named value in its own units (a parameter in Pa as bar, say) without reading numbers back
out of text.  ``str(message)`` is the SI text, ``name = value``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Union


@dataclass(frozen=True)
class Quantity:
    """One named value, shown with ``digits`` significant digits.  Without a ``unit`` the value is SI and the
    interface shows it in its own unit; with one, the message's author chose the unit (to match a range or a limit
    printed beside it) and the value is shown as written."""

    name: str
    value: float
    digits: int = 7
    unit: str = ""

    @property
    def si_text(self) -> str:
        return f"{self.value:.{self.digits}g}"

    @property
    def shown_value(self) -> float:
        """The value as the SI text shows it: an interface converts this one, so that its text and the SI text
        never disagree in the last digit."""
        return float(self.si_text)

    def __str__(self) -> str:
        return f"{self.name} = {self.si_text}" + (f" {self.unit}" if self.unit else "")


Part = Union[str, Quantity]


@dataclass(frozen=True)
class Message:
    """Text and quantities in order; :meth:`show` renders each quantity as the caller's units want it."""

    parts: tuple[Part, ...] = ()

    @staticmethod
    def of(*pieces: "str | Quantity | Message | None") -> "Message":
        """The pieces in order; messages are spliced in, None is skipped."""
        parts: list[Part] = []
        for piece in pieces:
            if piece is None:
                continue
            if isinstance(piece, Message):
                parts.extend(piece.parts)
            elif isinstance(piece, Quantity):
                parts.append(piece)
            else:
                parts.append(str(piece))
        return Message(tuple(p for p in parts if p != ""))

    def show(self, quantity: Callable[[Quantity], str] = str) -> str:
        return "".join(p if isinstance(p, str) else quantity(p) for p in self.parts)

    @property
    def quantities(self) -> tuple[Quantity, ...]:
        return tuple(p for p in self.parts if isinstance(p, Quantity))

    def __str__(self) -> str:
        return self.show()

    def __bool__(self) -> bool:
        return bool(self.parts)

    def __add__(self, other: "str | Quantity | Message") -> "Message":
        return Message.of(self, other)

    def __radd__(self, other: "str | Quantity | Message") -> "Message":
        return Message.of(other, self)


NO_MESSAGE = Message()


def message_of(source: "Message | BaseException | str") -> Message:
    """The message of a result or an exception: an exception raised with a :class:`Message` keeps it; any other
    text (from a library the toolkit calls) is plain text without quantities."""
    if isinstance(source, Message):
        return source
    if isinstance(source, BaseException):
        if len(source.args) == 1 and isinstance(source.args[0], Message):
            return source.args[0]
        return Message.of(str(source))
    return Message.of(source)
