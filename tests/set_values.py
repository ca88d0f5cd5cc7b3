"""Values written as ``legdsl run --set`` takes them, for the tests that draw settings of the
shipped and outside creatures (random run options, random sweeps, random API calls)."""

from __future__ import annotations

import functools
from pathlib import Path

from legdsl.check.source import check_file
from legdsl.ir.model import Model
from legdsl.lang.units import Dim, parse_unit, unit_for


@functools.cache
def models(source: Path) -> tuple[Model, ...]:
    """The creatures of ``source``, checked once a session."""
    return tuple(check_file(source))


def number(x: float) -> str:
    """``x`` to four significant digits, as a person writes it."""
    return f"{x:.4g}"


def in_unit(value: float, dim: Dim, space: str = "") -> str:
    """``value`` (SI) written in the unit ``--set`` suggests for its dimension (``space``
    between the number and the unit)."""
    unit = unit_for(dim)
    if not unit:
        return number(value)
    scale, _ = parse_unit(unit)
    return f"{number(value / scale)}{space}{unit}"
