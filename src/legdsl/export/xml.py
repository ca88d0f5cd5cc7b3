"""Small helpers shared by the MJCF and URDF exporters: numbers, colours, names, XML text.

Every number is printed as the shortest decimal that reads back as the same
double (Python's ``repr``), so an exported file carries the model exactly and
the same model always gives the same bytes.
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from collections.abc import Iterable

from legdsl.ir.model import Vec3
from legdsl.lang.errors import InternalError


def num(x: float) -> str:
    """``x`` as the shortest round-tripping decimal: 0.5, 1, -0.11, 1e-05 (never ``-0``)."""
    x = float(x)
    if not math.isfinite(x):
        raise InternalError(f"cannot export the non-finite number {x!r}")
    if x == 0.0:
        return "0"
    text = repr(x)
    return text[:-2] if text.endswith(".0") else text


def nums(values: Iterable[float]) -> str:
    return " ".join(num(v) for v in values)


def rgba(color: str | None, default: str = "#a0a0a0") -> str:
    """A "#rrggbb" colour as the four numbers "r g b 1" in [0, 1], to four decimals."""
    c = color or default
    return nums((*(round(int(c[i : i + 2], 16) / 255.0, 4) for i in (1, 3, 5)), 1.0))


def fresh(name: str, taken: set[str]) -> str:
    """``name``, or ``name_``, ``name__``... whichever is not taken yet; the result is taken."""
    while name in taken:
        name += "_"
    taken.add(name)
    return name


def rpy_z_to(d: Vec3) -> Vec3:
    """Roll, pitch, yaw (URDF's fixed-axis x-y-z) of a rotation taking +z onto unit ``d``."""
    return (0.0, math.atan2(math.hypot(d[0], d[1]), d[2]), math.atan2(d[1], d[0]))


def to_text(root: ET.Element) -> str:
    """Indented XML text with a trailing newline; attributes stay in insertion order."""
    ET.indent(root, space="  ")
    return ET.tostring(root, encoding="unicode") + "\n"
