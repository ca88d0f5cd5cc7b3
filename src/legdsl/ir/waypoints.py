"""A file of waypoints (``legdsl run --path route.csv``): one ``x,y`` point per line.

Coordinates are metres, or lengths with their unit (``50 cm, 2 km``). The file's first line
with text may be a header of words (``x,y``); a header may give each column's unit as the
project's own ``trajectory.csv`` does (``x [cm],y [cm]``, or ``x (cm)``), and a bare number
in that column is then in that unit (a field with its own unit keeps it). A header's unit
must be a unit of length, on both columns. Fields are separated by ``,`` or ``;``, and may
be quoted as a spreadsheet quotes them (``"3","4"``); ``#`` starts a note. Every mistake is
told at its line and column, with the line, a caret and what to write instead.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from pathlib import Path

from legdsl.ir.paths import FARTHEST, PathSpec, Point, far, same_point
from legdsl.lang.errors import UsageError
from legdsl.lang.units import KINDS, UnitError, a_kind, parse_unit

LENGTH = KINDS["length"][0]
LINE = "a waypoint line is 'x,y': two numbers in metres, or lengths with their unit (50 cm)"
_QUANTITY = re.compile(
    r"\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?|[-+]?(?:inf|nan))\s*([^\d\s.+-].*?)?\s*"
)
_NUM = r"([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)"
_PLAIN = re.compile(rf"\s*{_NUM}\s*[,;]\s*{_NUM}\s*")  # a line of two numbers alone
_HEADER_UNIT = re.compile(r"[\[(]\s*([^\])]*?)\s*[\])]")  # 'x [cm]', 'x (cm)'


@dataclass(frozen=True)
class _Field:
    text: str  # as written, its quotes taken off
    col: int  # 1-based column of its first character (past spaces and a quote)


@dataclass(frozen=True)
class _Line:
    path: Path
    n: int
    line: str

    def refuse(self, col: int, message: str) -> UsageError:
        """The mistake at column ``col``: ``file:line:col: message``, the line and a caret."""
        pad = "".join(c if c == "\t" else " " for c in self.line[: col - 1])
        return UsageError(f"{self.path}:{self.n}:{col}: {message}\n    {self.line}\n    {pad}^")


def read_waypoints(path: Path, name: str) -> PathSpec:
    """The polyline through the file's points (see the module's docstring for the format)."""
    try:  # utf-8-sig: a spreadsheet's byte-order mark would hide the first point as a header
        lines = path.read_bytes().decode("utf-8-sig").splitlines()
    except UnicodeDecodeError as e:
        raise UsageError(
            f"--path {path}: not a text file of 'x,y' lines (byte {e.start}: {e.reason}); "
            "save it as UTF-8 text"
        ) from None
    except OSError as e:
        raise UsageError(
            f"--path {path}: cannot be read ({e.strerror or e}); give a readable file of "
            "'x,y' lines"
        ) from None
    points: list[Point] = []
    point_lines: list[int] = []
    units: tuple[float, ...] | None = None  # a header's, per column
    first = True  # the first line with text, after any notes and blank lines
    for n, raw in enumerate(lines, 1):
        text = raw.split("#", 1)[0]
        plain = _PLAIN.fullmatch(text)  # '3,4': read at once (200,000 lines in 0.3 s)
        if plain:
            x, y = (float(v) * (units[i] if units else 1.0) for i, v in enumerate(plain.groups()))
            if not (far(x) or far(y) or (points and same_point((x, y), points[-1]))):
                first = False
                points.append((x, y))
                point_lines.append(n)
                continue
        if not text.strip():
            continue
        at = _Line(path, n, raw)
        fields = _fields(text)
        if first and _is_header(fields):
            first, units = False, _header_units(at, fields)
            continue
        first = False
        point = _point(at, text, fields, units)
        if points and same_point(point, points[-1]):
            raise at.refuse(
                fields[0].col,
                f"this point repeats the one before it (line {point_lines[-1]}), and a path's "
                "segment needs a length; remove one of the two lines",
            )
        points.append(point)
        point_lines.append(n)
    if len(points) < 2:
        empty = "" if any(t.strip() for t in lines) else " (the file is empty)"
        raise UsageError(
            f"--path {path}: a path needs at least 2 points, got {len(points)}{empty}; "
            "give one 'x,y' line (metres) per point"
        )
    return PathSpec(name=name, shape="polyline", points=tuple(points))


def _fields(text: str) -> list[_Field]:
    """The line's fields, split at ',' or ';', each with its column; a field's surrounding
    spaces and a spreadsheet's double quotes about it are not part of it."""
    fields, start = [], 0
    for part in re.split(r"[,;]", text):
        lead = len(part) - len(part.lstrip())
        body = part.strip()
        if len(body) >= 2 and body[0] == body[-1] == '"':
            inner = body[1:-1]
            lead += 1 + len(inner) - len(inner.lstrip())
            body = inner.strip()
        fields.append(_Field(body, start + lead + 1))
        start += len(part) + 1
    return fields


def _is_header(fields: list[_Field]) -> bool:
    """A line of words: every field has a letter and none is a number ('x,y', 'x [cm],y [cm]',
    'east; north'; not '3,3', '"3","3"' nor '3 km,4 km', which are points)."""
    return all(re.search(r"[A-Za-z]", f.text) and not _QUANTITY.fullmatch(f.text) for f in fields)


def _header_units(at: _Line, fields: list[_Field]) -> tuple[float, ...] | None:
    """The factors to metres of a header's columns' units ('x [cm],y [cm]'), or None where it
    gives none; a unit that is not a length, or one column's without the other's, refused."""
    found = [(f, _HEADER_UNIT.search(f.text)) for f in fields]
    if not any(m for _, m in found):
        return None
    factors = []
    for f, m in found[:2]:
        if m is None:
            given = next(g for g in found if g[1] is not None)
            unit = given[1].group(1) if given[1] else ""
            raise at.refuse(
                f.col,
                f"the header gives one column a unit ('{unit}') and '{f.text}' none, and a bare "
                f"number would be read as metres in one column and {unit} in the other; write "
                f"'{f.text} [{unit}]', or take the units out of the header",
            )
        unit, col = m.group(1), f.col + m.start(1)
        try:
            factor, dim = parse_unit(unit)
        except UnitError as e:
            raise at.refuse(
                col,
                f"the header's unit '{unit}' is not one legdsl reads ({e}); write the column's "
                "unit of length in brackets, as in 'x [cm],y [cm]', or take it out (metres)",
            ) from None
        if dim != LENGTH:
            raise at.refuse(
                col,
                f"the header's unit '{unit}' is {a_kind(dim)}, and a waypoint is a length; "
                "write a unit of length, as in 'x [cm],y [cm]', or take it out (metres)",
            )
        factors.append(factor)
    return tuple(factors)


def _point(at: _Line, text: str, fields: list[_Field], units: tuple[float, ...] | None) -> Point:
    """The line's point, in metres; its mistakes refused at their column."""
    if len(fields) == 1:
        two = re.fullmatch(r"(\s*\S+)\s+(\S+)\s*", text)  # '0 0': a space for the comma
        if two and all(_QUANTITY.fullmatch(g) for g in two.groups()):
            x, y = two.group(1).strip(), two.group(2)
            raise at.refuse(
                text.index(y, len(two.group(1))) + 1,
                f"x and y are apart by a space, and {LINE}: write '{x},{y}'",
            )
        raise at.refuse(len(text.rstrip()) + 1, f"this line has x alone, and {LINE}: add ',y'")
    if len(fields) > 2:
        raise at.refuse(
            fields[2].col,
            f"this line has {len(fields)} fields, and {LINE}; a path lies on the ground (no z): "
            "remove the fields after y",
        )
    x, y = (_metres(at, f, index, units) for index, f in enumerate(fields))
    return (x, y)


def _metres(at: _Line, f: _Field, index: int, units: tuple[float, ...] | None) -> float:
    """One coordinate: a number (in metres, or the header's unit for its column), or a length
    with its unit (3 km); anything else refused at its column."""
    axis = "xy"[index]
    match = _QUANTITY.fullmatch(f.text)
    if match is None:
        if not f.text:
            raise at.refuse(f.col, f"{axis} is missing; {LINE}")
        header = (
            " (only the file's first line may be a header)" if re.match(r"[A-Za-z]", f.text) else ""
        )
        raise at.refuse(f.col, f"'{f.text}' is not a number{header}; {LINE}")
    number, unit = match.groups()
    if not unit:
        value = float(number) * (units[index] if units else 1.0)
    else:
        try:
            factor, dim = parse_unit(unit)
        except UnitError:
            dim = None
        if dim != LENGTH:
            said = f"is {a_kind(dim)}" if dim is not None else f"has the unknown unit {unit!r}"
            raise at.refuse(
                f.col,
                f"{f.text!r} {said}, and a waypoint is a length; write it in metres "
                f"({number}) or with a unit of length ({number} cm, {number} km)",
            )
        value = float(number) * factor
    if not math.isfinite(value):
        raise at.refuse(
            f.col, f"{axis} is {f.text!r}, not a finite number; give {axis} as a number (metres)"
        )
    if far(value):
        raise at.refuse(
            f.col,
            f"{axis} is more than {FARTHEST:g} m from the origin; give the path in metres near "
            "where the creature runs",
        )
    return value
