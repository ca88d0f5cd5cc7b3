"""The value a ``--set`` (or another option's) error suggests writing instead, in the unit
the user wrote where that is plain: the advice keeps their number and their unit's prefix."""

from __future__ import annotations

import math
import re
from typing import Any, Protocol

from legdsl.lang.turning import ANGULAR_VELOCITY, FREQUENCY, turning_rate
from legdsl.lang.units import DIMENSIONLESS, Dim, UnitError, parse_unit, si_unit

_PREFIXES = {"k": "kilo", "c": "centi", "m": "milli", "u": "micro", "n": "nano", "M": "mega"}


class Given(Protocol):
    """A value as given (``legdsl.pipeline.settings.Given``, read only)."""

    @property
    def number(self) -> str: ...  # the digits as written

    @property
    def unit(self) -> str: ...  # the unit as written, empty for a bare number

    @property
    def value(self) -> float: ...  # in SI units

    @property
    def dim(self) -> Dim | None: ...  # None for a bare number

    @property
    def text(self) -> str: ...


def written(given: Given, want: Dim, unit: str, write: str = "{}") -> str:
    """The value an error suggests in ``unit``, in ``write`` (``{}`` for the value, e.g.
    ``--switch {}=gallop``: each value suggested is written whole, where "1s, or 1ms if the m
    meant milli" was put in its place): the user's number, or, for a quantity whose
    dimension is the wanted one's inverse (a frequency for a time), its reciprocal: 500Hz
    for a time is 0.002s, never 500s; a frequency for a turning rate is turns a second: 1Hz
    for deg/s is 360deg/s, never 1deg/s; and an angular velocity for a frequency is its turns a
    second: 3600rev/min for Hz is 60Hz, never 3600Hz."""
    inverse = given.dim is not None and all(a == -b for a, b in zip(given.dim, want, strict=True))
    if inverse and given.value != 0 and want != DIMENSIONLESS:
        value = f"{1 / given.value / parse_unit(unit)[0]:g}{unit}"
        return f"{write.format(value)} (1/{given.text})"
    if given.dim == FREQUENCY and want == ANGULAR_VELOCITY:  # 1Hz for deg/s: 360deg/s, not 1
        turned = turning_rate(given.value, parse_unit(unit)[0])
        turns = f"{given.value:g} turn" + ("" if given.value == 1 else "s")
        return f"{write.format(f'{turned:g}{unit}')} ({given.text} is {turns} a second)"
    if given.dim == ANGULAR_VELOCITY and want == FREQUENCY:  # 3600rev/min for Hz: 60Hz
        turns_a_second = given.value / (2.0 * math.pi)
        turns = f"{turns_a_second:.6g} turn" + ("" if turns_a_second == 1 else "s")
        hz = f"{turns_a_second / parse_unit(unit)[0]:.6g}{unit}"
        return f"{write.format(hz)} ({given.text} is {turns} a second)"
    kept = _kept(given.unit, want)
    prefix = _PREFIXES.get(given.unit, "")
    if prefix and given.dim and kept == given.unit + si_unit(want) and kept != unit:
        # 5m for a time: 5ms reads the metre as milli, 1000 times off if seconds were meant
        return (f"{write.format(given.number + unit)}, or {write.format(given.number + kept)} "
                f"if the {given.unit} meant {prefix}")  # fmt: skip
    return write.format(given.number + (kept or unit))


def _kept(written: str, want: Dim) -> str | None:
    """The unit the user wrote, made the wanted kind, where that is plain: its first factor
    (0.03m/s for a length: 0.03m, not 0.03cm, 100 times less), or its prefix before the wanted
    kind's SI unit (20m for a time: 20ms). None where neither is ``want``."""
    head = re.split(r"[*/]", written)[0]
    plain = si_unit(want).isalpha()  # one unit (s, N): a prefix before it is plain
    prefixed = (
        written + si_unit(want) if plain and len(written) == 1 and written in "kcmunMG" else ""
    )
    for unit in (head if head != written else "", prefixed):
        try:
            if unit and parse_unit(unit)[1] == want:
                return unit
        except UnitError:
            pass
    return None


def setting_unit(model: Any, controller: str | None, name: str) -> str | None:
    """The unit to give ``name``'s values in (``run_copies``' ``vary=`` advice): the file's own
    for an input or parameter of ``controller`` ('' for a dimensionless one), the kind's for an
    actuator setting (``hip.kp``: 'N*m/rad'); None for a name neither is."""
    from legdsl.ir.model import setting_kind
    from legdsl.lang.units import KINDS, unit_for

    actuator, dot, key = name.partition(".")
    if dot:
        found = [a for a in model.actuators if a.name == actuator]
        try:
            return unit_for(KINDS[setting_kind(key, found[0].rotary)][0]) if found else None
        except KeyError:
            return None
    if controller is None:
        return None
    ctl = model.controller(controller)
    own = [c for c in [*ctl.inputs, *ctl.params] if c.name == name]
    return (own[0].unit or unit_for(own[0].dim)) if own else None
