"""A frequency given where an angular velocity is asked for, or the other way round: '1 Hz'
for a turning rate in deg/s is most likely one turn a second, 360 deg/s, and the plain
'write e.g. 1 deg/s' would be off by 360. ``as_turning`` says what the value is as the
other kind, in the unit the message suggests, and in turns a second ('rev/s')."""

from __future__ import annotations

import math

from legdsl.lang.units import KINDS, Dim, parse_unit

FREQUENCY = KINDS["frequency"][0]
ANGULAR_VELOCITY = KINDS["angular velocity"][0]


def turning_rate(turns: float, factor: float) -> float:
    """``turns`` a second (a frequency, SI) as an angular velocity in a unit ``factor`` rad/s
    large: 1 Hz is 360 deg/s."""
    return turns * 2.0 * math.pi / factor


def _number(value: float) -> str:
    return f"{value:.6g}"


def as_turning(written: str, value: float, given: Dim, want: Dim, unit: str) -> str | None:
    """The sentence for ``written`` (SI ``value``, of dimension ``given``) where ``want`` is
    asked for, when one is a frequency and the other an angular velocity, with ``unit`` (of
    ``want``) for the value to write: "1 Hz is one turn a second: write 360 deg/s (or
    1 rev/s)"; None for any other pair of dimensions."""
    try:
        factor, dim = parse_unit(unit)
    except ValueError:
        return None
    if dim != want:
        return None
    if given == FREQUENCY and want == ANGULAR_VELOCITY:
        turns = value  # a turn a second for each Hz
        as_unit = turning_rate(value, factor)
        also = f" (or {_number(turns)} rev/s)" if unit != "rev/s" else ""
    elif given == ANGULAR_VELOCITY and want == FREQUENCY:
        turns = value / (2.0 * math.pi)
        as_unit = turns / factor
        also = ""
    else:
        return None
    count = "one turn" if turns == 1 else f"{_number(turns)} turns"
    return f"{written} is {count} a second: write {_number(as_unit)} {unit}{also}"
