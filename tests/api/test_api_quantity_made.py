"""A ``Quantity`` made by hand, as docs/api.md shows one: ``Quantity(1.0, 'm/s')`` was accepted
with the text kept as its dimension, and the run it went into (``set=``, ``time=``) failed
with Python's ``ValueError: not enough values to unpack (expected 4, got 3)``;
``Quantity('1 m/s')`` was a ``TypeError``. Each now holds the SI value and its dimension,
formats as a number does (``f"{q:.2f}"``), and a value it cannot be is a ``UsageError``."""

from __future__ import annotations

from pathlib import Path

import pytest
from conftest import ROOT

import legdsl
from legdsl.api import Quantity
from legdsl.lang.errors import UsageError

VELOCITY, TIME = (0, 1, -1, 0), (0, 0, 1, 0)


@pytest.mark.parametrize(
    ("made", "value", "dim"),
    [
        (lambda: Quantity(1.5, "m/s"), 1.5, VELOCITY),
        (lambda: Quantity("1.5 m/s"), 1.5, VELOCITY),
        (lambda: Quantity(1.5, VELOCITY), 1.5, VELOCITY),
        (lambda: Quantity(1.5, "km/min"), 25.0, VELOCITY),
        (lambda: Quantity("200 ms"), 0.2, TIME),
        (lambda: Quantity(60, "N * m / rad"), 60.0, (1, 2, -2, -1)),
        (lambda: Quantity("0.5"), 0.5, (0, 0, 0, 0)),
    ],
)
def test_a_quantity_is_made_from_a_unit_a_text_or_a_dimension(made, value, dim) -> None:
    q = made()
    assert q.value == pytest.approx(value) and q.dim == dim


def test_a_quantity_formats_with_its_unit() -> None:
    q = Quantity(1.23456, "m/s")
    assert f"{q:.2f}" == "1.23 m/s" and f"{q}" == str(q) == "1.23456 m/s"
    assert f"{Quantity('3 kg'):>6.1f}" == "   3.0 kg"


@pytest.mark.parametrize(
    ("args", "told"),
    [
        (("abc", VELOCITY), "the value is a number, not 'abc'"),
        ((1.0, "furlong"), "'furlong' is not a unit legdsl knows"),
        ((1.0, (1, 2)), "the dimension is a unit ('m/s') or the four whole exponents"),
        ((1.0,), "give the value's unit too, not 1.0 alone"),
        (("1 m s",), "'m s' is not a unit legdsl knows"),
        ((float("nan"), "m/s"), "the value is a finite number, not nan"),
        (("1e999 m",), "'1e999 m' is too large for a double"),
    ],
)
def test_what_is_no_quantity_is_refused_when_made(args, told) -> None:
    with pytest.raises(UsageError, match=r"^Quantity\(\): ") as caught:
        Quantity(*args)
    assert told in str(caught.value)


def test_a_quantity_made_by_hand_goes_into_a_run(generated: Path) -> None:
    hopper = legdsl.load(ROOT / "creatures" / "hopper.leg", generated=generated)
    run = hopper.run(controller="hop", set={"speed": Quantity(0.5, "m/s")}, time=Quantity("60 ms"))
    assert run.info["settings"]["inputs"]["speed"] == 0.5
    assert run.trajectory.t[-1] <= 0.06
