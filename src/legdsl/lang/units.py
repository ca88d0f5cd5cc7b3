"""Units: parsing unit strings, dimensions, and conversion to SI.

A dimension is a tuple of exponents over (mass, length, time, angle). Angle is
kept as its own dimension so that a linear spring (N/m) on a revolute joint,
or a length where an angle belongs, is caught; ``rad`` is its SI unit and
``deg`` converts to it.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

Dim = tuple[int, int, int, int]  # exponents of kg, m, s, rad

DIMENSIONLESS: Dim = (0, 0, 0, 0)

# symbol -> (factor to SI, dimension)
UNITS: dict[str, tuple[float, Dim]] = {
    "kg": (1.0, (1, 0, 0, 0)),
    "g": (1e-3, (1, 0, 0, 0)),
    "m": (1.0, (0, 1, 0, 0)),
    "cm": (1e-2, (0, 1, 0, 0)),
    "mm": (1e-3, (0, 1, 0, 0)),
    "km": (1e3, (0, 1, 0, 0)),
    "s": (1.0, (0, 0, 1, 0)),
    "ms": (1e-3, (0, 0, 1, 0)),
    "min": (60.0, (0, 0, 1, 0)),
    "Hz": (1.0, (0, 0, -1, 0)),
    "kHz": (1e3, (0, 0, -1, 0)),
    "N": (1.0, (1, 1, -2, 0)),
    "kN": (1e3, (1, 1, -2, 0)),
    "J": (1.0, (1, 2, -2, 0)),
    "W": (1.0, (1, 2, -3, 0)),
    "rad": (1.0, (0, 0, 0, 1)),
    "deg": (math.pi / 180.0, (0, 0, 0, 1)),
    "rev": (2.0 * math.pi, (0, 0, 0, 1)),
}

# Names for the dimensions a property may ask for, with an example unit for messages.
KINDS: dict[str, tuple[Dim, str]] = {
    "dimensionless": (DIMENSIONLESS, "no unit"),
    "mass": ((1, 0, 0, 0), "kg"),
    "length": ((0, 1, 0, 0), "m"),
    "time": ((0, 0, 1, 0), "s"),
    "angle": ((0, 0, 0, 1), "deg"),
    "velocity": ((0, 1, -1, 0), "m/s"),
    "angular velocity": ((0, 0, -1, 1), "rad/s"),
    "acceleration": ((0, 1, -2, 0), "m/s^2"),
    "force": ((1, 1, -2, 0), "N"),
    "torque": ((1, 2, -2, 0), "N*m"),
    "moment of inertia": ((1, 2, 0, 0), "kg*m^2"),
    "linear stiffness": ((1, 0, -2, 0), "N/m"),
    "linear damping": ((1, 0, -1, 0), "N*s/m"),
    "angular stiffness": ((1, 2, -2, -1), "N*m/rad"),
    "angular damping": ((1, 2, -1, -1), "N*m*s/rad"),
    "frequency": ((0, 0, -1, 0), "Hz"),
}

_ATOM = re.compile(r"([A-Za-z]+)(?:\^(-?\d+))?")


class UnitError(ValueError):
    """A unit string that names no known unit; it reads as the sentence a file's unknown
    unit gets ('hz' is not a unit legdsl knows: ...; did you mean 'Hz'?), so that the
    command line's values (``--dt 0.4MS``, ``--set speed=1m/sec``) are told the same."""

    def __init__(self, text: str) -> None:
        super().__init__(text)
        self.text = text

    def __str__(self) -> str:
        from legdsl.lang.unit_words import unknown_unit  # it reads this module's table

        return unknown_unit(self.text)


def parse_unit(text: str) -> tuple[float, Dim]:
    """Parse ``N*m*s/rad`` into (factor to SI, dimension); ``/`` divides the next atom only."""
    factor = 1.0
    dim = [0, 0, 0, 0]
    sign = 1
    pos = 0
    while True:
        match = _ATOM.match(text, pos)
        if not match or match.group(1) not in UNITS:
            raise UnitError(text)
        scale, base = UNITS[match.group(1)]
        power = sign * int(match.group(2) or 1)
        try:
            factor *= scale**power
        except OverflowError:  # '1 km^200': past a double, so the number reads as too large
            factor = math.inf
        for i in range(4):
            dim[i] += base[i] * power
        pos = match.end()
        if pos == len(text):
            return factor, (dim[0], dim[1], dim[2], dim[3])
        if text[pos] not in "*/":
            raise UnitError(text)
        sign = 1 if text[pos] == "*" else -1
        pos += 1


_MANTISSA = re.compile(r"\s*[-+]?(\d*\.?\d*)")


def out_of_range(written: str, value: float) -> str | None:
    """Why a number, as written, has no double to hold it: too large (it would be infinite),
    or too small (not zero, yet it would read as 0); None for a number that reads."""
    if not math.isfinite(value):
        return f"'{written}' is too large a number"
    mantissa = _MANTISSA.match(written)
    if value == 0 and mantissa is not None and re.search("[1-9]", mantissa.group(1)):
        return (
            f"'{written}' is too small a number: nearer 0 than a double holds (5e-324), it "
            "would read as 0; write 0 if you mean zero"
        )
    return None


def unit_pattern() -> str:
    """A regular expression for a unit string made of the known unit symbols."""
    names = "|".join(sorted(UNITS, key=len, reverse=True))
    atom = rf"(?:{names})(?:\^-?\d+)?(?![A-Za-z0-9_])"
    return rf"{atom}(?:[*/]{atom})*"


def describe(dim: Dim) -> str:
    """A human name for a dimension, e.g. 'linear stiffness (N/m)'."""
    for name, (kind_dim, example) in KINDS.items():
        if kind_dim == dim:
            return name if name == "dimensionless" else f"{name} ({example})"
    parts = []
    for symbol, exp in zip(("kg", "m", "s", "rad"), dim, strict=True):
        if exp:
            parts.append(symbol if exp == 1 else f"{symbol}^{exp}")
    return "*".join(parts) or "dimensionless"


@dataclass(frozen=True)
class Quantity:
    """A number converted to SI, with its dimension; ``unitless`` when written without a unit."""

    value: float
    dim: Dim
    unitless: bool = False
