"""The values of ``--grid``, ``--random``, ``--lhs`` (``legdsl sweep``) and ``--param``
(``legdsl tune``), read into SI units, each mistake echoed with a caret under its fault.

``NAME=LO:HI:N`` (N values from LO to HI), ``NAME=A,B,C`` (a list), ``NAME=LO:HI`` (a range
to draw from, or to tune in). A number takes a unit right after it; a bare number is in the
SI unit of what it sets. One value list or range gives every number its unit, or none: a bare
number beside written ones (``tilt=-3deg:1:3``, its 1 read as 1 rad, 57 degrees, where the
user meant 1 deg: the run fell, unsaid) is refused, a caret under it (a bare 0 is 0 in every
unit). A grid runs each value once: a value given twice (``speed=1m/s,100cm/s``,
``speed=1:1:3``) ran identical runs without a word. A grid's values from LO to HI are the
nearest doubles to the exact steps between LO and HI (numpy's ``linspace`` made 0.3:0.9:3's
middle 0.6000000000000001, which a resume written ``0.3,0.6,0.9`` did not match).
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from fractions import Fraction

from legdsl.lang.errors import UsageError
from legdsl.lang.units import Dim, a_kind, named_si_unit, parse_unit, unit_for
from legdsl.pipeline.settings import NUMBER_AND_UNIT, parse_given

MAX_RUNS = 1_000_000  # a sweep's plan is laid out whole, in memory and in sweep.json
SAME = 1e-12  # relative: two values this close are one (57cm and 0.57 m are 1 ulp apart)


@dataclass(frozen=True)
class Axis:
    """One swept name and how its values are chosen."""

    name: str
    kind: str  # grid, random, lhs
    values: tuple[float, ...] = ()  # grid: the values; random and lhs: (low, high)
    written: str = ""  # the unit its values were given in (the picture shows them in it)


class PointedError(UsageError):
    """A mistake in an option's value: the sentence, then the option and its value echoed with
    a caret under the fault (``start``, ``length`` in ``value``)."""

    def __init__(self, why: str, option: str, value: str, start: int, length: int) -> None:
        self.why, self.option, self.value = why, option, value
        self.start, self.length = max(0, start), max(1, length)
        indent = " " * (len(option) + 1 + self.start)
        super().__init__(f"{option} {value!r}: {why}\n    {option} {value}\n    "
                         f"{indent}^{'~' * (self.length - 1)}")  # fmt: skip

    def moved(self, option: str, value: str, shift: int, why: str | None = None) -> PointedError:
        """The same fault in ``value`` of ``option``, where the fault is ``shift`` further on
        (``--speeds 1,1`` read as ``--grid speed=1,1``: -6)."""
        return PointedError(self.why if why is None else why, option, value,
                            self.start + shift, self.length)  # fmt: skip


def same_value(a: float, b: float) -> bool:
    """Two values of one quantity that are one (to ``SAME``, relative)."""
    return a == b or abs(a - b) <= SAME * max(abs(a), abs(b))


def bare_in_si(text: str, name: str, dim: Dim, written: str | None = None) -> str:
    """``NAME=LO:HI`` (or a grid) written without units is in SI units: for a quantity whose
    usual unit (or the unit the file ``written`` it in: ``stroke = 1.5 cm``) is not SI (an
    angle: ``stand=-50:-30`` meant in degrees is radians) say so, and how to write it in that
    unit; "" otherwise."""
    other = in_usual_unit(text, name, dim, written)
    if other is None:
        return ""
    return (
        f"; a bare number is in {named_si_unit(dim)}: to give them in {other[0]}, write {other[1]}"
    )


def in_usual_unit(
    text: str, name: str, dim: Dim, written: str | None = None
) -> tuple[str, str] | None:
    """``bare_in_si``'s unit and ``NAME=...`` rewritten in it, or None (units given, or the
    usual unit SI)."""
    spec = text.partition("=")[2]
    si, usual = named_si_unit(dim), written or unit_for(dim)
    if any(c.isalpha() for c in spec) or usual in ("", si):
        return None
    numbers = re.split(r"([:,])", spec)
    last = len(numbers) - 1 if ":" in spec and spec.count(":") == 2 else len(numbers)  # a grid's N
    rewritten = "".join(p + usual if i % 2 == 0 and i < last else p for i, p in enumerate(numbers))
    return usual, f"{name}={rewritten.replace(' ', '')}"


def _pieces(text: str, start: int, separator: str) -> list[tuple[int, str]]:
    """The parts of ``text[start:]`` between ``separator``s, each with where it starts."""
    found, at = [], start
    for part in text[start:].split(separator):
        found.append((at, part))
        at += len(part) + 1
    return found


def _where(piece: tuple[int, str]) -> tuple[int, int]:
    """(start, length) of a piece without its blanks."""
    at, part = piece
    lead = len(part) - len(part.lstrip())
    return at + lead, len(part.strip()) or 1


def parse_axis(kind: str, text: str, dims: dict[str, Dim]) -> Axis:
    """``NAME=LO:HI:N``, ``NAME=A,B,C`` (grid) or ``NAME=LO:HI`` (random, lhs, param), in SI
    units."""
    name, eq, spec = text.partition("=")
    name = name.strip()
    option = f"--{kind}"
    if not eq or not name:
        raise PointedError(f"write NAME=LO:HI{':N' if kind == 'grid' else ''}",
                           option, text, 0, len(text))  # fmt: skip
    if name not in dims:
        known = ", ".join(n for n in dims if "." not in n) or "none"
        settings = [n for n in dims if "." in n]
        also = f"; or an actuator setting, ACTUATOR.KEY ({', '.join(settings)})" if settings else ""
        what = "a parameter" if kind == "param" else "an input or parameter"  # tune: parameters
        raise UsageError(f"--{kind} {name}: not {what} of the controller ({known}){also}")
    want = dims[name]
    begin = len(text) - len(spec)
    lists = kind == "grid" and ("," in spec or ":" not in spec)
    pieces = _pieces(text, begin, "," if lists else ":")
    numbers = pieces if lists or kind != "grid" else pieces[:2]  # a grid's N is a count
    for _, number in numbers:  # a unit of the wrong kind first, the mix of bare and not next
        _number(number, want, kind, name)
    _all_or_none_written(option, text, name, numbers, want)
    axis = _parse_values(option, text, name, pieces, lists, want)
    units = [m[2] for m in map(NUMBER_AND_UNIT.fullmatch, re.split("[:,]", spec)) if m and m[2]]
    return Axis(axis.name, kind, axis.values, units[0] if units else "")


def _all_or_none_written(
    option: str, text: str, name: str, pieces: list[tuple[int, str]], want: Dim
) -> None:
    """Refuses a bare number beside numbers written with a unit (a bare 0 is 0 in any)."""
    split = [(p, NUMBER_AND_UNIT.fullmatch(p[1])) for p in pieces]
    written = [(p[1].strip(), m[2]) for p, m in split if m and m[2]]
    if not written or not named_si_unit(want):
        return
    for piece, m in split:
        if m and not m[2] and float(m[1]) != 0:
            start, length = _where(piece)
            number = piece[1].strip()
            raise PointedError(
                f"{number} has no unit, beside {written[0][0]}: a bare number is in "
                f"{named_si_unit(want)}, so one range or list gives every number its unit, or "
                f"none; write its unit ({number}{written[0][1]}, if that is what it is)",
                option, text, start, length,
            )  # fmt: skip


def _parse_values(
    option: str,
    text: str,
    name: str,
    pieces: list[tuple[int, str]],
    lists: bool,
    want: Dim,
) -> Axis:
    """``parse_axis``'s values in SI units."""
    kind = option.removeprefix("--")
    if lists:
        values = [_number(p[1], want, kind, name) for p in pieces]
        for k, v in enumerate(values):
            if any(same_value(v, u) for u in values[:k]):
                first = next(pieces[j][1].strip() for j in range(k) if same_value(values[j], v))
                raise PointedError(
                    f"{pieces[k][1].strip()} is given twice ({first} before it is the same "
                    "value, and its runs would be alike); give each value once",
                    option, text, *_where(pieces[k]),
                )  # fmt: skip
        return Axis(name, kind, tuple(values))
    end = len(text)
    if kind == "grid":
        if len(pieces) < 3:
            raise PointedError(
                f"a grid's range ends with its number of values: write {name}="
                f"{pieces[0][1].strip()}:{pieces[1][1].strip()}:N (N values from LO to HI), or "
                f"list them, {name}=A,B,C", option, text, end, 1,
            )  # fmt: skip
        if len(pieces) > 3:
            raise PointedError(f"write {name}=LO:HI:N (N values from LO to HI), or {name}=A,B,C; "
                               "this has more parts", option, text, pieces[3][0] - 1,
                               end - pieces[3][0] + 1)  # fmt: skip
        count = pieces[2][1].strip()
        if not count.isdigit() and (whole := _whole_written_otherwise(count)) is not None:
            # 1e9 is a whole number: its refusal said it was not (--samples 1e9 says it)
            digits = f"{pieces[0][1].strip()}:{pieces[1][1].strip()}:{whole}"
            why = (f"{whole:,} values, more than a sweep takes ({MAX_RUNS:,}); sweep fewer"
                   if whole > MAX_RUNS else f"write N in digits: {name}={digits}")  # fmt: skip
            raise PointedError(f"N, the number of values from LO to HI, is {count}: {why}",
                               option, text, *_where(pieces[2]))  # fmt: skip
        if not count.isdigit() or int(count) < 1:
            raise PointedError(
                f"N, the number of values from LO to HI, is a whole number, 1 or more; "
                f"{count or 'nothing'} is not", option, text, *_where(pieces[2]),
            )  # fmt: skip
        n = int(count)
        _at_most(n, f"--grid {text}")
        lo, hi = (_number(p[1], want, kind, name) for p in pieces[:2])
        if n == 1 and lo != hi:  # linspace would keep LO and drop HI unsaid
            raise UsageError(
                f"--grid {text!r}: 1 value from LO to HI is LO alone; write "
                f"{name}={pieces[0][1].strip()} for one value, or give N of 2 or more"
            )
        if n > 1 and same_value(lo, hi):  # n identical runs
            raise PointedError(
                f"{n} values from {pieces[0][1].strip()} to {pieces[1][1].strip()} are one "
                f"value {n} times (its runs would be alike); give HI other than LO, or write "
                f"{name}={pieces[0][1].strip()} for one run", option, text, *_where(pieces[1]),
            )  # fmt: skip
        if n == 1:
            return Axis(name, kind, (lo,))
        inner = steps(_exact(pieces[0][1]), _exact(pieces[1][1]), n)[1:-1]
        return Axis(name, kind, (lo, *inner, hi))  # LO and HI as --set reads them
    if len(pieces) != 2:
        raise PointedError(f"write {name}=LO:HI", option, text, pieces[0][0], end - pieces[0][0])
    lo, hi = (_number(p[1], want, kind, name) for p in pieces)
    if not lo < hi:  # said with the range that is meant, or one value's own option
        low, high = pieces[0][1].strip(), pieces[1][1].strip()
        fix = (f"write {name}={high}:{low}" if lo > hi else "give HI above LO"
               + (f", or --grid {name}={low} for one value" if kind != "param" else ""))  # fmt: skip
        start = _where(pieces[0])[0]
        raise PointedError(f"the range needs LO < HI; {fix}", option, text, start, end - start)
    return Axis(name, kind, (lo, hi))


def steps(lo: Fraction, hi: Fraction, n: int) -> tuple[float, ...]:
    """``n`` values from ``lo`` to ``hi``, each the double nearest the exact step between them
    (``0.3:0.9:3``'s middle is 0.6; numpy's ``linspace`` made it 0.6000000000000001, and
    ``0.1:0.7:7``'s 0.4 0.39999999999999997, which ``legdsl run --set`` of 0.4 does not run)."""
    if n == 1:
        return (float(lo),)
    return tuple(float((lo * (n - 1 - i) + hi * i) / (n - 1)) for i in range(n))


def _exact(text: str) -> Fraction:
    """A number as written, in SI units, exactly: its digits times its unit's factor as that
    is written (``57cm`` is 57/100 m, where 57 * 0.01 is 0.5700000000000001): the steps
    between LO and HI are the numbers meant (LO and HI themselves are as ``--set`` reads
    them, so that a row runs again as ``legdsl run --set`` of the value written)."""
    given = parse_given(text, "--grid")
    factor = parse_unit(given.unit)[0] if given.unit else 1.0
    return Fraction(given.number) * Fraction(repr(factor))


def _number(text: str, want: Dim, kind: str, name: str) -> float:
    """A value of a swept name, read as ``--set`` reads one (``2 s^-1``, ``60 N*m/rad``); a
    bare number is in the quantity's SI unit."""
    given = parse_given(text, f"--{kind} {name}")
    if given.dim is not None and given.dim != want:
        raise UsageError(
            f"--{kind} {name}: {name} is {a_kind(want)}, but {text.strip()!r} is "
            f"{a_kind(given.dim)}; {_in_which_unit(want)}"
        )
    return given.value


def _in_which_unit(want: Dim) -> str:
    """How to write a value of ``want``: its SI unit, and the usual one where that differs."""
    si, usual = named_si_unit(want), unit_for(want)
    if not si:
        return "write it without a unit"
    return f"give it in {si}" + ("" if usual in ("", si) else f" or {usual}")


def refuse_swept_twice(given: list[tuple[str, str]]) -> None:
    """Each name swept by one option (``given``: each --grid, --random and --lhs as (kind,
    text)): the second named, a caret under it ('sweep: each name is swept once' said
    neither)."""
    seen: dict[str, str] = {}
    for kind, text in given:
        written = text.partition("=")[0]
        name = written.strip()
        if name in seen:
            raise PointedError(
                f"{name} is swept twice ({seen[name]} sweeps it already); sweep each name "
                "once, all its values in one option", f"--{kind}", text,
                len(written) - len(written.lstrip()), len(name),
            )  # fmt: skip
        seen[name] = f"--{kind} {text}"


def _whole_written_otherwise(count: str) -> int | None:
    """A grid's N written other than in digits (``1e9``, ``3.0``) that is a whole number, 1 or
    more; else None."""
    try:
        value = float(count)
    except ValueError:
        return None
    return int(value) if math.isfinite(value) and value >= 1 and value == int(value) else None


def _at_most(runs: int, what: str) -> None:
    if runs > MAX_RUNS:
        raise UsageError(
            f"{what}: {runs:,} runs, more than a sweep takes ({MAX_RUNS:,}); sweep fewer "
            "values, or split it into sweeps of their own --out"
        )
