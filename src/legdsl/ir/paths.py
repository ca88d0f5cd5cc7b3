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
from dataclasses import dataclass, field

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
    ``lookahead_default`` says the lookahead was not written (a ``--path`` shape or a file of
    waypoints without one): ``DEFAULT_LOOKAHEAD`` is a default for a creature of about a
    metre, and for one given to the creature scaled by L (``--scale L``) it is L times that,
    as the paths ``legdsl scale`` writes (``legdsl.pipeline.scaled.scale_path``). It is how
    the path was written, not the path: two specs that differ only in it are equal.
    """

    name: str
    shape: str
    points: tuple[Point, ...] = ()
    closed: bool = False
    center: Point = (0.0, 0.0)
    radius: float = 0.0
    turn: int = 1
    lookahead: float = DEFAULT_LOOKAHEAD
    lookahead_default: bool = field(default=False, compare=False)

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
            "closed": self.closed or self.shape == "circle",  # as a path report says it
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
            closed=bool(data.get("closed", False)) and data["shape"] != "circle",  # its own
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
