"""Path geometry at run time: the nearest point of a path, its arclength and tangent, and the
tracker the runtime evaluates every control tick (the path itself is ``legdsl.ir.paths.PathSpec``).

Conventions: x, y in the world's ground plane, headings measured from +x towards +y,
``lateral`` positive when the point is to the left of the path (looking along it),
``progress`` the arclength travelled along the path, counted without wrapping.

The tracker follows a polyline in its order, not only to its globally nearest point (see
``PathTracker.update``): a stretch the path comes back along, a hairpin or a crossing is
taken when the creature gets there, and ``progress`` goes on along it.
"""

from __future__ import annotations

import bisect
import itertools
import math
from dataclasses import dataclass, replace

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


SAME_S = 1e-9  # m: arclengths this near are one point of the path (a vertex, from either side)


def _goes_on(s: float, best: float, last: float) -> bool:
    """Whether the point at arclength ``s`` goes on from the last reading's (``last``) better
    than the one at ``best``, as near: not behind it where ``best`` is, else nearer to it
    (never without a last reading, nor between two arclengths that are one point)."""
    behind, best_behind = s < last - SAME_S, best < last - SAME_S
    if behind != best_behind:
        return best_behind
    return abs(s - last) < abs(best - last) - SAME_S


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
    def project(
        self,
        x: float,
        y: float,
        lo: float = -math.inf,
        hi: float = math.inf,
        last: float = math.nan,
        slack: float = 1e-12,
    ) -> Projection:
        """The nearest point of the path; of a polyline, the nearest whose arclength is within
        [lo, hi] (unwrapped: a closed path's window may reach past its end or before its
        start, and ``s`` is then unwrapped too), of points as near (within ``slack``) the
        first, or with ``last`` (the last reading's arclength) the one that goes on from it:
        not behind it if one is not, else the nearer to it (a stretch the path comes back
        along is two points at one place)."""
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
        laps = (-self.length, 0.0, self.length) if self.closed and hi - lo < math.inf else (0.0,)
        for lap in laps:
            for i in range(*self._within(lo, hi, lap)):
                a, b = self.vertices[i], self.vertices[i + 1]
                start, end = self.starts[i] + lap, self.starts[i + 1] + lap
                if end < lo or start > hi:
                    continue
                ex, ey = b[0] - a[0], b[1] - a[1]
                seg = math.hypot(ex, ey)
                # the part of the segment in the window (all of it: 0 to 1, as without one)
                ulo = min(1.0, (lo - start) / seg) if start < lo else 0.0
                uhi = max(0.0, (hi - start) / seg) if end > hi else 1.0
                u = ((x - a[0]) * ex + (y - a[1]) * ey) / (seg * seg)
                u = min(uhi, max(ulo, u))
                px, py = a[0] + u * ex, a[1] + u * ey
                d = math.hypot(x - px, y - py)
                s = start + u * seg
                if d < best_d - slack or (
                    d <= best_d + 1e-12 and best is not None and _goes_on(s, best.s, last)
                ):
                    best_d = d
                    tx, ty = ex / seg, ey / seg
                    cross = tx * (y - py) - ty * (x - px)
                    if not self.closed and (
                        (i == 0 and u == 0.0) or (u == 1.0 and i == len(self.vertices) - 2)
                    ):
                        lateral = cross  # past an open end: the distance to the end's tangent line
                    else:
                        lateral = math.copysign(d, cross) if d > 0 else 0.0
                    best = Projection(s, px, py, math.atan2(ty, tx), lateral)
        assert best is not None
        return best

    def _within(self, lo: float, hi: float, lap: float) -> tuple[int, int]:
        """The segments that may reach into the window [lo, hi] (shifted by ``lap``): found by
        bisection, a segment more either side (the loop keeps only those that do), so that a
        path of 200,000 points costs a tick as one of 20 does. A NaN window: all of them."""
        if math.isnan(lo) or math.isnan(hi):  # its checks keep every segment
            return 0, len(self.starts) - 1
        first = bisect.bisect_left(self.starts, lo, key=lambda v: v + lap) - 2
        stop = bisect.bisect_right(self.starts, hi, key=lambda v: v + lap) + 1
        return max(0, first), min(len(self.starts) - 1, stop)

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
        i = 0  # the segment s is on (the last one from its start on; the first for NaN)
        if len(self.starts) > 2 and s >= self.starts[1]:
            i = min(len(self.starts) - 2, bisect.bisect_right(self.starts, s) - 1)
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
    The nearest point is the whole path's at the first reading, then a polyline's within a
    window about the last (``update``): it follows the path's order.
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
        last = self._last_s
        if math.isnan(last):
            # the first reading: the nearest point of the whole path, or an earlier one as near
            # within the lookahead (a creature at the start of a path that comes back through
            # it starts at its start)
            p = geo.project(x, y, slack=self.spec.lookahead)
            self.progress = p.s
        elif geo.spec.shape == "circle":  # its nearest point is the only one near
            p = geo.project(x, y)
            ds = p.s - last
            ds = (ds + geo.length / 2) % geo.length - geo.length / 2
            self.progress += ds
        else:
            # Then the nearest point within a window of arclength about the last one, so that
            # the projection moves along the path, not across to another stretch of it (one
            # the path comes back along or passes near): the window reaches either way as far
            # as the creature now is from the last nearest point (along a straight stretch it
            # cannot have gone further), and the lookahead more ahead (where the path turns
            # back on itself, the way on is found within it; the tie rule of ``project``
            # takes it). A creature that strays widens the window as far as it strays, and a
            # reading at the window's edge moves the next window on. A closed path's window
            # wraps (a lap at most, half either way); an open one's ends clamp it.
            reach = math.hypot(x - self.values["x"], y - self.values["y"])
            lo, hi = last - reach, last + self.spec.lookahead + reach
            if geo.closed and not hi - lo < geo.length:
                lo, hi = last - geo.length / 2, last + geo.length / 2
            p = geo.project(x, y, lo, hi, last)
            self.progress += p.s - last
            p = replace(p, s=p.s % geo.length if geo.closed else p.s)
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


# The most the path's tangent may turn within the lookahead (rad, 57 deg) all the way along it.
# With more, steering by the look-ahead tangent (``steer_path``) cannot hold the path: the
# biped's ``run`` at 1.5 m/s with the default 1 m lookahead holds a 1 m circle to 0.08 m RMS, an
# 0.8 m one to 0.41 m (half a lap in 15 s), runs a 0.6 m one the wrong way round and runs away
# from a 0.3 m one (the tangent 1 m on is 191 deg round), as from a square of 0.5 m sides.
TURN_WITHIN_LOOKAHEAD = 1.0


def lookahead_note(spec: PathSpec) -> str | None:
    """A note when the lookahead is too long for the path's turns, else None: a circle's
    longer than its radius, or a closed polyline's within which the tangent turns more than
    ``TURN_WITHIN_LOOKAHEAD`` from every point of it (the look-ahead tangent never points
    along the path where the creature is). One tight turn, even a hairpin, is not this: the
    creature turns early, and takes it."""
    if spec.shape == "none" or not (spec.shape == "circle" or spec.closed):
        return None
    look, name = spec.lookahead, spec.name or "(--path)"
    if spec.shape == "circle":
        if look <= spec.radius:
            return None
        told = (
            f"its lookahead ({look:g} m) is longer than its radius ({spec.radius:g} m): the "
            f"tangent {look:g} m on is {math.degrees(look / spec.radius):.0f} deg round from"
        )
        fix = f"give the path 'lookahead = {spec.radius:.3g} m' or less, or a larger radius"
    else:
        geo = PathGeometry(spec)
        turned = _least_turn(geo, look)
        if turned <= TURN_WITHIN_LOOKAHEAD:
            return None
        side = max(b - a for a, b in itertools.pairwise(geo.starts))
        told = (
            f"within its lookahead ({look:g} m) the path turns by "
            f"{math.degrees(turned):.0f} deg or more: the tangent {look:g} m on is as far round from"
        )
        fix = f"give the path a lookahead shorter than its longest side ({side:.3g} m)"
    return (
        f"path {name}: {told} the nearest point's, all the way along, and a creature steering "
        f"by it (steer_path) cuts inside, runs round the wrong way or runs off; {fix}"
    )


def _least_turn(geo: PathGeometry, look: float) -> float:
    """The least the tangent of a closed polyline turns (net, in magnitude, rad) between a
    point and the point ``look`` further on, over every point."""
    v, starts, length = geo.vertices, geo.starts, geo.length
    n = len(v) - 1  # segments; vertex k (0 the closing one) turns from segment k-1 to k
    heads = [math.atan2(v[k + 1][1] - v[k][1], v[k + 1][0] - v[k][0]) for k in range(n)]
    turns = [_wrap(heads[k] - heads[k - 1]) for k in range(n)]
    # the sums of the turns up to each vertex, added in order as sum() adds them (the same
    # bits): a polygon of 20,000 sides took 40 s summing them afresh for each point
    summed = list(itertools.accumulate(turns, initial=0))
    total, at = summed[-1], starts[:n]

    def turned_to(u: float) -> float:  # the net turn from arclength 0- to u
        laps = math.floor(u / length)
        rest = u - laps * length
        return laps * total + summed[bisect.bisect_right(at, rest)]

    marks = sorted({*starts[:n], *((at - look) % length for at in starts[:n])})
    marks.append(marks[0] + length)
    return min(
        abs(turned_to(s + look) - turned_to(s))
        for s in ((a + b) / 2 for a, b in zip(marks, marks[1:], strict=False))
    )
