"""Path geometry at run time: the nearest point of a path, its arclength and tangent, and the
tracker the runtime evaluates every control tick (the path itself is ``legdsl.ir.paths.PathSpec``).

Conventions: x, y in the world's ground plane, headings measured from +x towards +y,
``lateral`` positive when the point is to the left of the path (looking along it),
``progress`` the arclength travelled along the path, counted without wrapping.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from legdsl.ir.paths import MEMBERS, PathSpec, Point


@dataclass(frozen=True)
class Projection:
    """The point of a path nearest to a query point."""

    s: float  # arclength of the nearest point, in [0, length]
    x: float
    y: float
    heading: float  # the tangent's direction there
    lateral: float  # signed distance, positive to the left of the path


def _wrap(angle: float) -> float:
    return math.atan2(math.sin(angle), math.cos(angle))


class PathGeometry:
    """Closest points, arclength and tangents of a circle or a polyline (open or closed)."""

    def __init__(self, spec: PathSpec):
        self.spec = spec
        self.closed = spec.closed or spec.shape == "circle"
        if spec.shape == "circle":
            self.length = 2 * math.pi * spec.radius
            self.vertices: tuple[Point, ...] = ()
            self.starts: list[float] = []
            return
        pts = list(spec.points)
        if self.closed and pts[0] != pts[-1]:
            pts.append(pts[0])
        # drop a vertex whose segment has no direction (``project`` divides by its squared
        # length) or adds nothing to the arclength (``at`` divides by that: 1e-8 m after 1e9 m
        # of path). Not SAME_POINT: a checked path scaled by --scale 4 has sides under it.
        clean, self.starts = [pts[0]], [0.0]
        for p in pts[1:]:
            seg = math.dist(clean[-1], p)
            end = self.starts[-1] + seg
            if seg * seg > 0 and end > self.starts[-1]:
                clean.append(p)
                self.starts.append(end)
        self.vertices = tuple(clean)
        self.length = self.starts[-1]

    # ---------------------------------------------------------------- circle
    def _circle_angle(self, s: float) -> float:
        """The polar angle (about the centre) of the point at arclength ``s``; s = 0 at angle 0 - 90 deg * turn."""
        spec = self.spec
        return -spec.turn * math.pi / 2 + spec.turn * s / spec.radius

    # ---------------------------------------------------------------- queries
    def project(self, x: float, y: float) -> Projection:
        spec = self.spec
        if spec.shape == "circle":
            cx, cy = spec.center
            dx, dy = x - cx, y - cy
            r = math.hypot(dx, dy)
            phi = math.atan2(dy, dx) if r > 0 else 0.0
            start = -spec.turn * math.pi / 2
            s = ((phi - start) * spec.turn) % (2 * math.pi) * spec.radius
            heading = phi + spec.turn * math.pi / 2
            # to the left of a left (counter-clockwise) circle is inside it
            lateral = (spec.radius - r) * spec.turn
            return Projection(
                s, cx + spec.radius * math.cos(phi), cy + spec.radius * math.sin(phi),
                _wrap(heading), lateral,
            )  # fmt: skip
        best: Projection | None = None
        best_d = math.inf
        for i, (a, b) in enumerate(zip(self.vertices, self.vertices[1:], strict=False)):
            ex, ey = b[0] - a[0], b[1] - a[1]
            seg = math.hypot(ex, ey)
            u = ((x - a[0]) * ex + (y - a[1]) * ey) / (seg * seg)
            u = min(1.0, max(0.0, u))
            px, py = a[0] + u * ex, a[1] + u * ey
            d = math.hypot(x - px, y - py)
            if d < best_d - 1e-12:
                best_d = d
                tx, ty = ex / seg, ey / seg
                cross = tx * (y - py) - ty * (x - px)
                if not self.closed and (
                    (i == 0 and u == 0.0) or (u == 1.0 and i == len(self.vertices) - 2)
                ):
                    lateral = cross  # past an open end: the distance to the end's tangent line
                else:
                    lateral = math.copysign(d, cross) if d > 0 else 0.0
                best = Projection(self.starts[i] + u * seg, px, py, math.atan2(ty, tx), lateral)
        assert best is not None
        return best

    def at(self, s: float) -> tuple[float, float, float]:
        """The point at arclength ``s`` and the tangent's heading; wraps if closed, else clamps."""
        spec = self.spec
        if spec.shape == "circle":
            phi = self._circle_angle(s)
            cx, cy = spec.center
            return (
                cx + spec.radius * math.cos(phi),
                cy + spec.radius * math.sin(phi),
                _wrap(phi + spec.turn * math.pi / 2),
            )
        s = s % self.length if self.closed else min(max(s, 0.0), self.length)
        i = 0
        while i < len(self.starts) - 2 and s >= self.starts[i + 1]:
            i += 1
        a, b = self.vertices[i], self.vertices[i + 1]
        seg = self.starts[i + 1] - self.starts[i]
        u = (s - self.starts[i]) / seg
        return (
            a[0] + u * (b[0] - a[0]),
            a[1] + u * (b[1] - a[1]),
            math.atan2(b[1] - a[1], b[0] - a[0]),
        )


class PathTracker:
    """One path, followed by one creature: the members of ``MEMBERS``, updated each control tick.

    ``progress`` is unwrapped: on a closed path a step from near its end to near its
    start counts forward (the nearer way round), so that ``progress / length`` counts laps.
    """

    def __init__(self, spec: PathSpec | None):
        self.spec = spec
        self.geometry = PathGeometry(spec) if spec is not None and spec.shape != "none" else None
        self.progress = math.nan
        self._last_s = math.nan
        self.values: dict[str, float] = dict.fromkeys(MEMBERS, 0.0)

    def update(self, x: float, y: float) -> dict[str, float]:
        geo = self.geometry
        if geo is None:
            return self.values
        assert self.spec is not None
        p = geo.project(x, y)
        if math.isnan(self._last_s):
            self.progress = p.s
        else:
            ds = p.s - self._last_s
            if geo.closed:
                ds = (ds + geo.length / 2) % geo.length - geo.length / 2
            self.progress += ds
        self._last_s = p.s
        ax, ay, ah = geo.at(p.s + self.spec.lookahead)
        self.values = {
            "lateral": p.lateral,
            "heading": p.heading,
            "progress": self.progress,
            "length": geo.length,
            "x": p.x,
            "y": p.y,
            "ahead_x": ax,
            "ahead_y": ay,
            "ahead_heading": ah,
            "given": 1.0,
        }
        return self.values


def track(spec: PathSpec, xs: list[float], ys: list[float]) -> tuple[list[float], list[float]]:
    """The lateral error and the unwrapped progress at every point of a track (for reports)."""
    tracker = PathTracker(spec)
    lateral, progress = [], []
    for x, y in zip(xs, ys, strict=True):
        v = tracker.update(x, y)
        lateral.append(v["lateral"])
        progress.append(v["progress"])
    return lateral, progress
