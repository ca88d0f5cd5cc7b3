"""Long lines and long words are read in time linear in their length: no regular expression of
legdsl.lang backtracks over every way of splitting a run of blanks, digits or letters.

An outside user's file with 100 000 spaces after 'inertia 0.01 kg*m^2' took minutes to check
(the loose-unit pattern of spellings.py tried each split of the blanks between two '[ \\t]*').
Each case here took seconds to minutes before; the bound is generous, so the test is not
timing-flaky, and a quadratic or exponential pattern still fails it.
"""

from __future__ import annotations

import time

import pytest

from legdsl.lang.errors import LegError
from legdsl.lang.parser import parse
from legdsl.lang.units import looks_like_unit, unknown_unit

CREATURE = """creature c {
  planar
  body trunk free { mass 1 kg  inertia 0.1 kg*m^2 }
  body arm on trunk via revolute j at (0 m, 0 m) {
    length 0.3 m  mass 0.1 kg  inertia 0.01 kg*m^2
  }
}
"""
LINE = "    length 0.3 m  mass 0.1 kg  inertia 0.01 kg*m^2"
N = 100_000
BOUND = 10.0  # seconds; each case takes well under one


def _parse(text: str) -> str:
    start = time.perf_counter()
    try:
        parse(text, "long.leg", recover=True)
        told = ""
    except LegError as err:
        told = str(err)
    took = time.perf_counter() - start
    assert took < BOUND, f"took {took:.1f} s"
    return told


@pytest.mark.parametrize(
    "tail",
    [
        " " * N,  # the user's file: spaces after the line's last unit
        "\t" * N,
        "* " + " " * N,  # a unit's '*' and blanks
        "1" * N,  # digits run into the unit's power: 'm^2111...'
        "a" * N,  # a long word after the unit
        "1e" * (N // 2),
    ],
    ids=["spaces", "tabs", "star-spaces", "digits", "letters", "1e1e"],
)
def test_a_long_tail_on_a_property_line_is_read_in_linear_time(tail: str) -> None:
    told = _parse(CREATURE.replace(LINE, LINE + tail))
    assert "internal error" not in told and "Traceback" not in told


@pytest.mark.parametrize(
    "tail", ["1" * N, "a" * N, "1e" * (N // 2)], ids=["digits", "letters", "1e1e"]
)
def test_a_long_word_where_a_keyword_goes_is_read_in_linear_time(tail: str) -> None:
    told = _parse(CREATURE.replace("  planar", "  planar" + tail))
    assert told.startswith("long.leg:") and "internal error" not in told


def test_a_unit_power_of_many_digits_is_told_not_a_traceback() -> None:
    told = _parse(CREATURE.replace("0.01 kg*m^2", "0.01 kg*m^" + "2" * 20_000))
    assert "has a power past any unit's" in told
    told = _parse(CREATURE.replace("0.01 kg*m^2", "0.01 kg*m^1e300"))
    assert "'kg*m^1e300' has a power past any unit's: a unit's powers are small whole" in told


def test_symbols_run_together_are_read_in_linear_time() -> None:
    # '(?:kg|m|mm|...)+' tried every way of reading a run of 'm's: exponential in its length
    start = time.perf_counter()
    for word in ("m" * 40 + "x", "m" * 40 + "2", "mmmmmmmmmmmmmmmmmmmmmmmmmmmmmmx2"):
        unknown_unit(word)
        looks_like_unit(word)
    assert time.perf_counter() - start < BOUND
    assert "did you mean 'kg*m^2'" in unknown_unit("kgm2")
