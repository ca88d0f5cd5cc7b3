"""The controller IR: a controller's declarations and state table with every name resolved.

Quantities carry their dimension (``legdsl.lang.units.Dim``) from the checker on, so that a
value given later (``legdsl run --set speed=2m/s``) is checked against what the file declared.
"""

from __future__ import annotations

from dataclasses import dataclass

from legdsl.lang.errors import Span
from legdsl.lang.units import Dim


@dataclass(frozen=True)
class Constant:
    """An input or parameter: its default value in SI units and its dimension."""

    name: str
    value: float
    dim: Dim
    span: Span
