"""The terrain ahead of a point along a heading: the members ``terrain.ahead_*`` of a controller.

A controller that must step up, or jump over something, needs to know what is coming. The
ground's terrain (``ground { terrain step(...) | terrain box(...) }``) is a set of raised
features with flat tops; looking from a point in the ground plane along a heading (the
creature's: its root body's yaw, +x for a planar creature), the *next* feature is the one
whose near edge the heading line crosses first, strictly ahead of the point:

* ``ahead_distance``: how far along the heading that near edge is;
* ``ahead_height``: the height of the feature's top (world z; the floor is at 0);
* ``ahead_depth``: how far the heading line runs over the feature (a box's depth; 0 for a
  step, which has no far edge);
* ``ahead_given``: 1 when there is such a feature, 0 when there is none (the other members are
  then 0);

and ``height`` is the terrain's height under the point itself. A slope has no edges: it is
never a feature ahead. A feature the point is already over is behind it (its near edge is).
"""

from __future__ import annotations

import math
from collections.abc import Iterable

from legdsl.ir.model import Terrain

NONE = {"ahead_distance": 0.0, "ahead_height": 0.0, "ahead_depth": 0.0, "ahead_given": 0.0}
MEMBERS = (*NONE, "height")


def _crossing(t: Terrain, x: float, y: float, c: float, s: float) -> tuple[float, float] | None:
    """(distance to the near edge, depth along the heading) of one feature, or None."""
    if t.kind == "step":
        if c <= 0.0 or x >= t.get("x"):
            return None
        return (t.get("x") - x) / c, 0.0
    if t.kind != "box":
        return None
    enter, leave = -math.inf, math.inf
    for p, d, lo, hi in ((x, c, t.get("x0"), t.get("x1")), (y, s, t.get("y0"), t.get("y1"))):
        if abs(d) < 1e-12:
            if not lo <= p <= hi:
                return None
            continue
        a, b = (lo - p) / d, (hi - p) / d
        enter, leave = max(enter, min(a, b)), min(leave, max(a, b))
    if enter <= 0.0 or leave < enter:
        return None
    return enter, leave - enter


def ahead(terrain: Iterable[Terrain], x: float, y: float, yaw: float) -> dict[str, float]:
    """The ``ahead_*`` members for a point (x, y) looking along ``yaw`` (radians from +x)."""
    c, s = math.cos(yaw), math.sin(yaw)
    best: tuple[float, float, float] | None = None
    for t in terrain:
        hit = _crossing(t, x, y, c, s)
        if hit is not None and (best is None or hit[0] < best[0]):
            best = (hit[0], hit[1], t.get("height"))
    if best is None:
        return dict(NONE)
    return {
        "ahead_distance": best[0],
        "ahead_height": best[2],
        "ahead_depth": best[1],
        "ahead_given": 1.0,
    }
