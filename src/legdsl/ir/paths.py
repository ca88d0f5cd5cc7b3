"""Paths for a controller to follow, as checked: a circle, a polyline or polygon, or a square.

A controller declares ``path route = circle(center = (0, 5) m, radius = 5 m, turn = left)``
(or ``polyline(...)``, ``polygon(...)``, ``square(...)``; ``legdsl run --path`` overrides
it). Every control tick the runtime projects the centre of mass onto the path
(``legdsl.sim.path_tracking.PathTracker``) and the generated control module reads the members
listed in ``MEMBERS`` as sensors (``route.lateral`` is the sensor key
``path.route.lateral``). The steering law that turns them into a heading is
written in ``.leg`` (``steer_path`` in the standard library), not here.

Conventions: x, y in the world's ground plane, headings measured from +x
towards +y, ``lateral`` positive when the point is to the left of the path
(looking along it), ``progress`` the arclength travelled along the path,
counted without wrapping (a closed path's second lap goes on from its length).
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from pathlib import Path

Point = tuple[float, float]

SHAPES = ("circle", "polyline", "polygon", "square")
MEMBERS = (
    "lateral", "heading", "progress", "length", "x", "y",
    "ahead_x", "ahead_y", "ahead_heading", "given",
)  # fmt: skip
DEFAULT_LOOKAHEAD = 1.0  # m
# A path's coordinates and sizes are at most this (m): far beyond any run, and a
# segment's squared length stays finite (the tracker divides by it); beyond about 1e154 m
# it overflows and every point projects onto the segment's start.
FARTHEST = 1e9
# Points nearer than this (m) are one point: a path's checks refuse a segment between them.
SAME_POINT = 1e-12


def number(value: float) -> str:
    """``value`` as short as it reads back the same (5 for 5.0, 1000.0001 whole, not 1000)."""
    short = f"{value:g}"
    return short if float(short) == value else repr(value)


def far(value: float) -> bool:
    """Whether a coordinate or size is past ``FARTHEST``."""
    return not abs(value) <= FARTHEST


def same_point(a: Point, b: Point) -> bool:
    """Whether two points are one (a path's checks refuse a segment no longer than this)."""
    return math.dist(a, b) <= SAME_POINT


@dataclass(frozen=True)
class PathSpec:
    """A checked path: a circle (``center``, ``radius``, ``turn`` +1 left, -1 right) or vertices.

    The shape ``none`` is a path declared without one (``path route``): not given.
    """

    name: str
    shape: str
    points: tuple[Point, ...] = ()
    closed: bool = False
    center: Point = (0.0, 0.0)
    radius: float = 0.0
    turn: int = 1
    lookahead: float = DEFAULT_LOOKAHEAD

    def describe(self) -> str:
        """The path as it could be written in a .leg file (SI units)."""
        look = self.lookahead
        look_text = f", lookahead = {number(look)} m" if look != DEFAULT_LOOKAHEAD else ""
        if self.shape == "none":
            return "none"
        if self.shape == "circle":
            side = "left" if self.turn > 0 else "right"
            return (
                f"circle(center = ({number(self.center[0])}, {number(self.center[1])}) m, "
                f"radius = {number(self.radius)} m, turn = {side}{look_text})"
            )
        points = ", ".join(f"({number(x)}, {number(y)}) m" for x, y in self.points)
        return f"{'polygon' if self.closed else 'polyline'}({points}{look_text})"

    def as_json(self) -> dict[str, object]:
        return {
            "name": self.name,
            "shape": self.shape,
            "points": [list(p) for p in self.points],
            "closed": self.closed,
            "center": list(self.center),
            "radius": self.radius,
            "turn": self.turn,
            "lookahead": self.lookahead,
            "text": self.describe(),
        }

    @staticmethod
    def from_json(data: dict[str, object]) -> PathSpec:
        def pt(v: object) -> Point:
            assert isinstance(v, list | tuple)
            return (float(v[0]), float(v[1]))

        points = data.get("points", [])
        assert isinstance(points, list)
        return PathSpec(
            name=str(data["name"]),
            shape=str(data["shape"]),
            points=tuple(pt(p) for p in points),
            closed=bool(data.get("closed", False)),
            center=pt(data.get("center", [0.0, 0.0])),
            radius=float(data.get("radius", 0.0)),  # type: ignore[arg-type]
            turn=int(data.get("turn", 1)),  # type: ignore[call-overload]
            lookahead=float(data.get("lookahead", DEFAULT_LOOKAHEAD)),  # type: ignore[arg-type]
        )


def square_corners(corner: Point, side: float, turn: int) -> tuple[Point, ...]:
    """A square with one corner at ``corner``, its first side along +x, turning left or right."""
    x, y = corner
    d = side * turn
    return ((x, y), (x + side, y), (x + side, y + d), (x, y + d))


def read_waypoints(path: Path, name: str) -> PathSpec:
    """``x,y`` per line (metres, or lengths with their unit: ``30 cm``; ``#`` comments and a
    first line of words alone, ``x,y``, are skipped: a first line with a number is a point)."""
    from legdsl.lang.errors import UsageError

    try:  # utf-8-sig: a spreadsheet's byte-order mark would hide the first point as a header
        lines = path.read_bytes().decode("utf-8-sig").splitlines()
    except UnicodeDecodeError as e:
        raise UsageError(
            f"--path {path}: not a text file of 'x,y' lines (byte {e.start}: {e.reason}); "
            "save it as UTF-8 text"
        ) from None
    points: list[Point] = []
    header_allowed = True  # the first line with text, after any comments and blank lines
    for n, line in enumerate(lines, 1):
        text = line.split("#", 1)[0].strip()
        if not text:
            continue
        first, header_allowed = header_allowed, False
        if first and not _NUMBER.search(text):
            continue  # a header: words alone ('0 0' or '3 km,4 km' is a point, read or refused)
        parts = text.replace(";", ",").split(",")
        if len(parts) != 2:
            raise UsageError(
                f"--path {path}: line {n} is not 'x,y' (two numbers in metres): {line!r}"
            )
        point = (_metres(path, n, line, parts[0], 0), _metres(path, n, line, parts[1], 1))
        if not all(math.isfinite(c) for c in point):
            raise UsageError(f"--path {path}: line {n} is not finite: {line!r}")
        if far(point[0]) or far(point[1]):
            raise UsageError(
                f"--path {path}: line {n} is more than {FARTHEST:g} m from the origin: "
                f"{line!r}; give the path in metres near where the creature runs"
            )
        if points and same_point(point, points[-1]):
            raise UsageError(
                f"--path {path}: line {n} repeats the point before it; remove the repeat"
            )
        points.append(point)
    if len(points) < 2:
        raise UsageError(
            f"--path {path}: a path needs at least 2 points, got {len(points)}; "
            "give one 'x,y' line (metres) per point"
        )
    return PathSpec(name=name, shape="polyline", points=tuple(points))


# a number as a field of a waypoint line starts (a word such as 'x1' does not)
_NUMBER = re.compile(r"(?:^|[\s,;])[-+]?(?:\d|\.\d)")
_QUANTITY = re.compile(
    r"\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?|[-+]?(?:inf|nan))\s*([^\d\s.+-].*?)?\s*"
)


def _metres(path: Path, n: int, line: str, field: str, index: int) -> float:
    """One coordinate of line ``n``: a number in metres, or a length with its unit (3 km);
    anything else refused at its column, with the line and a caret."""
    from legdsl.lang.errors import UsageError
    from legdsl.lang.units import KINDS, UnitError, a_kind, parse_unit

    col = len(line) - len(line.lstrip()) + 1  # where the field starts in the line
    if index:
        col = line.replace(";", ",").index(",", col - 1) + 2
    col += len(field) - len(field.lstrip())
    shown = f"\n    {line}\n    {' ' * (col - 1)}^"
    where = f"{path}:{n}:{col}"
    match = _QUANTITY.fullmatch(field)
    if match is None:  # '0 0', 'abc': the line's shape is wrong (told in one line)
        raise UsageError(
            f"--path {path}: line {n} is not 'x,y' (two numbers in metres, or lengths with "
            f"their unit): {line!r}"
        )
    number, unit = match.groups()
    if not unit:
        return float(number)
    try:
        factor, dim = parse_unit(unit)
    except UnitError:
        dim = None
    if dim != KINDS["length"][0]:
        said = f"is {a_kind(dim)}" if dim is not None else f"has the unknown unit {unit!r}"
        raise UsageError(
            f"{where}: {field.strip()!r} {said}, and a waypoint is a length; write it in metres "
            f"({number}) or with a unit of length ({number} cm, {number} km){shown}"
        )
    return float(number) * factor
