"""Messages keep the values they name (``bifurcation.messages``); the interface shows them in its units without
reading numbers back out of text (issue 28)."""

import pytest

from axles.axle import interface_text
from axles.units import from_kmh
from bifurcation.messages import Message, Quantity, message_of
from bifurcation.problem import ProblemError


def test_a_location_reads_in_si_and_in_interface_units():
    where = Message.of("ends on the window boundary at ", Quantity("speed", from_kmh(147.707)), ", ",
                       Quantity("pressure", 50000.0))
    assert str(where) == "ends on the window boundary at speed = 41.02972, pressure = 50000"
    assert interface_text(where) == "ends on the window boundary at 147.707 km/h, pressure = 0.5 bar"
    assert [q.name for q in where.quantities] == ["speed", "pressure"]


def test_each_name_gets_its_own_unit():
    assert interface_text(Message.of(Quantity("t0", 0.08194))) == "t0 = 0.08194 m"
    assert interface_text(Message.of(Quantity("pressure_left", 128521.0))) == "pressure_left = 1.28521 bar"
    # no unit known: as the toolkit wrote it (a state, a test oscillator's parameter)
    assert interface_text(Message.of(Quantity("mu", 0.25))) == "mu = 0.25"
    # an entry without a unit
    assert interface_text(Message.of(Quantity("p_dy1", 1.2))) == "p_dy1 = 1.2"


def test_text_that_merely_looks_like_a_value_is_left_alone():
    """The regex this replaced turned any "pressure = N" in any text into bar; plain text now stays text."""
    assert interface_text("a file says pressure = 50000") == "a file says pressure = 50000"


def test_an_exception_carries_its_message():
    exc = ProblemError(Message.of("no cycle at ", Quantity("speed", 50.0)))
    assert str(exc) == "no cycle at speed = 50"
    assert message_of(exc).quantities == (Quantity("speed", 50.0),)
    assert interface_text(exc) == "no cycle at 180 km/h"
    with pytest.raises(ProblemError, match="speed = 50"):
        raise exc


def test_messages_compose():
    m = "a" + Message.of(Quantity("speed", 10.0)) + " b"
    assert isinstance(m, Message) and str(m) == "aspeed = 10 b"
    assert not Message() and Message.of("x")


def test_the_interface_converts_the_value_the_si_text_shows():
    """The last digit of the interface text agrees with the SI text's (the value is rounded once, in SI)."""
    q = Quantity("speed", 41.666666666, digits=7)
    assert q.si_text == "41.66667" and interface_text(Message.of(q)) == "150 km/h"


def test_a_value_given_with_its_unit_is_shown_as_written():
    """A range error prints the value beside its range in one unit: converting the value alone would mix units."""
    m = Message.of(Quantity("I1", 3.0, 6, "kg m^2"), " is smaller than ...")
    assert str(m) == interface_text(m) == "I1 = 3 kg m^2 is smaller than ..."


def test_a_contradiction_in_an_axle_file_names_its_entry_from_the_message_values(tmp_path):
    """The consistency error's quantities say which entries are involved: the file's line is found by name."""
    from axles.axle_file import AxleFileError, read_axle
    path = tmp_path / "light.toml"
    path.write_text('name = "light"\nbase = "YANG2024"\n[table1]\nI1 = 1.0\n')
    with pytest.raises(AxleFileError) as info:
        read_axle(str(path))
    text = str(info.value)
    assert "light.toml:4" in text and "I1 = 1 kg m^2 is smaller" in text
