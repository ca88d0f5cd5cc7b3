"""``legdsl.api.Quantity``: a value in SI units with its dimension, as ``load`` gives a
controller's inputs and parameters, and as ``set=``, ``time=``, the options and ``metrics()``'
windows take one.

Made by hand it is ``Quantity(1.5, "m/s")`` (a number and its unit, any unit legdsl knows:
``Quantity(90, "km/h")`` holds 25 m/s), ``Quantity("1.5 m/s")`` (a text as ``set=`` takes it)
or ``Quantity(1.5, (0, 1, -1, 0))`` (the SI number and its dimension, the exponents of kg, m,
s and rad, as ``q.dim`` gives them back). Anything else is a ``UsageError`` saying so: a unit
given as text used to be kept as it was, and the run it went into failed on it with Python's
``not enough values to unpack``.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from typing import Any

import numpy as np

from legdsl.lang.errors import UsageError
from legdsl.lang.units import DIMENSIONLESS, Dim, UnitError, named_si_unit, parse_unit

_TEXT = re.compile(r"\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*(.*?)\s*$")
_HOW = "give Quantity(1.5, 'm/s'), Quantity('1.5 m/s') or Quantity(1.5, (0, 1, -1, 0))"


@dataclass(frozen=True, init=False)
class Quantity:
    """A value in SI units with its dimension; prints with its unit (``0.03 s``, and
    ``f"{q:.2f}"`` as ``0.03 s``). ``Quantity(1.5, "m/s")``, ``Quantity("1.5 m/s")`` or
    ``Quantity(1.5, (0, 1, -1, 0))`` (the exponents of kg, m, s, rad)."""

    value: float
    dim: Dim

    def __init__(self, value: Any, dim: Any = None) -> None:
        if dim is None:
            number, dim = _from_text(value)
        elif isinstance(dim, str):
            factor, unit = _unit(dim)
            number = _number(value) * factor
            if not math.isfinite(number):
                raise UsageError(f"Quantity(): {value!r} {dim} is too large for a double")
            dim = unit
        else:
            number, dim = _number(value), _dimension(dim)
        object.__setattr__(self, "value", number)
        object.__setattr__(self, "dim", dim)

    @property
    def unit(self) -> str:
        return named_si_unit(self.dim)

    def __str__(self) -> str:
        return f"{self.value:g} {self.unit}".rstrip()

    def __format__(self, spec: str) -> str:
        """``f"{q:.2f}"``: the number formatted so, then its unit; a whole number's ``d``
        (``f"{q:d}"``, ``2 m``) too, which was float's ValueError from in here."""
        if not spec:
            return str(self)
        number: float | int = self.value
        whole = spec[-1:] in "bcdoxX"  # formats of a whole number ('n' takes a float too)
        if whole and self.value.is_integer():
            number = int(self.value)
        try:
            return f"{format(number, spec)} {self.unit}".rstrip()
        except ValueError as e:
            why = (f"formats whole numbers, and {self.value:g} is not one" if whole
                   and not self.value.is_integer() else f"is no format for a number ({e})")  # fmt: skip
            raise UsageError(f"Quantity {self}: {spec!r} {why}; give one such as f'{{q:.3g}}' "
                             "or f'{q:.2f}'") from None  # fmt: skip

    def __float__(self) -> float:
        return self.value


def _number(value: Any) -> float:
    if isinstance(value, np.ndarray) and value.ndim == 0 and value.dtype.kind in "iuf":
        value = value[()]  # np.array(1.5), as numpy's reductions give and run options take
    if isinstance(value, bool) or not isinstance(value, int | float | np.integer | np.floating):
        raise UsageError(f"Quantity(): the value is a number, not {value!r}; {_HOW}")
    try:
        number = float(value)
    except OverflowError:
        raise UsageError(f"Quantity(): {value} is too large for a double") from None
    if not math.isfinite(number):  # no run takes one: set= told it as '--set speed=nanm/s'
        raise UsageError(f"Quantity(): the value is a finite number, not {value!r}")
    return number


def _unit(text: str) -> tuple[float, Dim]:
    unit = re.sub(r"\s*([*/^])\s*", r"\1", text.strip())  # 'N * m', not 'm s' as 'ms'
    if not unit:
        return 1.0, DIMENSIONLESS
    try:
        return parse_unit(unit)
    except UnitError as e:
        raise UsageError(f"Quantity(): {e}") from None


def _from_text(text: Any) -> tuple[float, Dim]:
    if not isinstance(text, str):
        raise UsageError(f"Quantity(): give the value's unit too, not {text!r} alone; {_HOW}")
    match = _TEXT.fullmatch(text)
    if match is None:
        raise UsageError(f"Quantity(): {text!r} is not a number with its unit; {_HOW}")
    factor, dim = _unit(match.group(2))
    number = float(match.group(1)) * factor
    if not math.isfinite(number):
        raise UsageError(f"Quantity(): {text!r} is too large for a double")
    return number, dim


def _dimension(dim: Any) -> Dim:
    whole = isinstance(dim, tuple | list) and len(dim) == 4
    if not whole or any(isinstance(e, bool) or not isinstance(e, int | np.integer) for e in dim):
        raise UsageError(f"Quantity(): the dimension is a unit ('m/s') or the four whole "
                         f"exponents of kg, m, s and rad, (0, 1, -1, 0), not {dim!r}")  # fmt: skip
    return (int(dim[0]), int(dim[1]), int(dim[2]), int(dim[3]))
