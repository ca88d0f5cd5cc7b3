"""A generated Python power of a base that can be negative, to a fractional power, raised
nothing: ``**`` gave a complex number (hopper12's ``((com.vx - 1 m/s) / (1 m/s)) ^ ex``,
``ex = 1.5``, called on its own at com.vx = 0, returned ``(-1.1e-15-6j)``) where C's
``leg_pow`` flags. It prints as ``math.pow``, which raises there and is the same ``pow``
elsewhere; a base that is never negative (``x*x + z*z``) and a whole power keep ``**``
(the kangaroo's inverse square roots: the goldens are unchanged)."""

from __future__ import annotations

import math

import pytest
from sympy import Float, Pow, Symbol

from legdsl.codegen.python.printer import LegPrinter

x, z, p = Symbol("x"), Symbol("z"), Symbol("p")


def _run(text: str, **values: float) -> float:
    return float(eval(text, {"math": math}, values))


@pytest.mark.parametrize("power", [Pow(x - 1, p), Pow(x - 1, Float(1.5)), Pow(x - 1, Float(-0.25))])
def test_a_fractional_power_of_a_base_that_can_be_negative_raises(power: Pow) -> None:
    text = LegPrinter().print(power)
    assert text.startswith("math.pow(")
    with pytest.raises(ValueError):
        _run(text, x=0.0, p=1.5)
    assert _run(text, x=3.0, p=1.5) == 2.0 ** float(power.exp.subs(p, 1.5))


def test_a_base_never_negative_or_a_whole_power_keeps_its_print() -> None:
    printer = LegPrinter()
    assert "**(-0.5)" in printer.print(Pow(x * x + z * z, Float(-0.5)))
    assert "math.pow" not in printer.print(Pow(x * x + z * z, Float(-0.5)))
    assert "math.pow" not in printer.print(Pow(x - 1, Float(3.0)))
