"""Which measured values are round-off of a zero, by the size of the creature that ran.

A run's sums and differences in doubles leave about 1e-16 of the numbers they combine: a
quadruped trotting in place had a stride length of 1.61e-16 m and a running speed of
-3.63e-17 m/s, a bound a roll magnitude of 1.8e-14 deg, and its hips' roll work 7e-29 J,
printed as if measured. Each value is weighed against the natural size of its unit for the
creature (its size L, its mass M and gravity g: L, √(L/g), √(gL), M g L, ...; 1 rad for an
angle, 1 for a ratio), and one under ``ROUND_OFF`` of that is printed as 0: a millimetre
creature's small values are its own size's and stay, a metre creature's 1e-16 m goes.
"""

from __future__ import annotations

import math
import re

import numpy as np

from legdsl.lang.units import UnitError, parse_unit
from legdsl.sim.trajectory import Trajectory

ROUND_OFF = 1e-9  # of a value's natural size: far above a double's 1e-16, far below a measure
_UNIT = re.compile(r"\(([^()]*)\)\s*$")  # a row label's unit: 'stride length (m)'
_RATIOS = {"-": 1.0, "g": 1.0, "": 1.0}  # a pure number, an acceleration in g


def creature_size(tr: Trajectory) -> float | None:
    """The creature's length scale (m): its longest leg, hip to foot, else the mean height of
    its centre of mass; None when the run says neither."""
    for series in (tr.leg_length, tr.com[:, 2:3]):
        values = np.abs(np.asarray(series, dtype=float))
        values = values[np.isfinite(values)]
        if values.size:
            size = float(values.max() if series is tr.leg_length else values.mean())
            if size > 0.0:
                return size
    return None


def natural_sizes(tr: Trajectory) -> dict[str, float]:
    """The natural size of a value in each SI base (kg, m, s, rad) for the run's creature:
    what ``natural`` combines; empty when its size is not known."""
    size = creature_size(tr)
    g = tr.gravity if tr.gravity > 0 else 9.81
    mass = tr.total_mass if tr.total_mass > 0 else 1.0
    if size is None:
        return {}
    return {"kg": mass, "m": size, "s": math.sqrt(size / g), "rad": 1.0}


def natural(unit: str, sizes: dict[str, float]) -> float | None:
    """The natural size of a value in ``unit`` ('m/s', 'deg', 'J/m', '-', 'g') by ``sizes``;
    None for a unit legdsl does not read or sizes not known."""
    if not sizes:
        return None
    if unit in _RATIOS:
        return _RATIOS[unit]
    try:
        factor, dim = parse_unit(unit)
    except UnitError:
        return None
    si = math.prod(sizes[b] ** p for b, p in zip(("kg", "m", "s", "rad"), dim, strict=True))
    return si / factor if factor > 0 else None


def label_unit(label: str) -> str | None:
    """The unit a row's label ends with, in brackets; None without one."""
    found = _UNIT.search(label)
    return found.group(1).strip() if found else None


def resolved(x: float, scale: float | None) -> float:
    """``x``, or 0.0 where it is under ``ROUND_OFF`` of ``scale`` (its unit's natural size)."""
    if scale is None or not math.isfinite(x) or abs(x) >= ROUND_OFF * scale:
        return x
    return 0.0
