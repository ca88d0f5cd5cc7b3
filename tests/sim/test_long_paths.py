"""A long path (a waypoints file of 200,000 points) took 3 minutes to report on after a 3 s
run, and ``legdsl metrics`` of a run along 20,000 points 8 s: each reading projected the
centre of mass onto every segment of the path (13 ms a reading), window or not, and
``PathGeometry.at`` walked the segments from the start. The segments a window reaches are
found by bisection now, and ``at``'s segment too: the same projections, bit for bit (the
segments skipped are those the window's checks skipped), on both backends."""

from __future__ import annotations

import math
import time

import numpy as np
import pytest

from legdsl.ir.paths import PathSpec
from legdsl.sim.path_tracking import PathGeometry, Projection, _goes_on, _least_turn, _wrap, track


def scanned(
    geo: PathGeometry, x: float, y: float, lo: float, hi: float, last: float, slack: float
) -> Projection:
    """``PathGeometry.project`` of a polyline as it was: every segment of every lap looked at."""
    best: Projection | None = None
    best_d = math.inf
    laps = (-geo.length, 0.0, geo.length) if geo.closed and hi - lo < math.inf else (0.0,)
    for lap in laps:
        for i, (a, b) in enumerate(zip(geo.vertices, geo.vertices[1:], strict=False)):
            start, end = geo.starts[i] + lap, geo.starts[i + 1] + lap
            if end < lo or start > hi:
                continue
            ex, ey = b[0] - a[0], b[1] - a[1]
            seg = math.hypot(ex, ey)
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
                if not geo.closed and (
                    (i == 0 and u == 0.0) or (u == 1.0 and i == len(geo.vertices) - 2)
                ):
                    lateral = cross
                else:
                    lateral = math.copysign(d, cross) if d > 0 else 0.0
                best = Projection(s, px, py, math.atan2(ty, tx), lateral)
    assert best is not None
    return best


def walked(geo: PathGeometry, s: float) -> int:
    """The segment ``PathGeometry.at`` took for ``s`` (wrapped or clamped) as it was."""
    i = 0
    while i < len(geo.starts) - 2 and s >= geo.starts[i + 1]:
        i += 1
    return i


def random_path(rng: np.random.Generator) -> PathSpec:
    n = int(rng.integers(2, 60))
    kind = rng.integers(0, 3)
    if kind == 0:  # a walk, segments of very different lengths, hairpins and crossings
        steps = rng.normal(size=(n, 2)) * 10.0 ** rng.uniform(-6, 2, size=(n, 1))
        pts = np.cumsum(steps, axis=0)
    elif kind == 1:  # a dense circle, coming back through its start
        a = np.linspace(0, 2 * math.pi * rng.uniform(0.5, 2.5), n)
        pts = np.stack([5 * np.sin(a), 5 - 5 * np.cos(a)], axis=1)
    else:  # back and forth along one line: every window holds stretches as near
        pts = np.stack([np.where(np.arange(n) % 2, 3.0, 0.0), 0.01 * np.arange(n)], axis=1)
    points = tuple((float(x), float(y)) for x, y in pts)
    closed = bool(rng.random() < 0.4) and n >= 3
    return PathSpec("p", "polygon" if closed else "polyline", points, closed=closed)


@pytest.mark.parametrize("seed", range(40))
def test_projections_are_those_of_every_segment(seed: int) -> None:
    rng = np.random.default_rng(seed)
    geo = PathGeometry(random_path(rng))
    span = max(geo.length, 1e-9)
    for _ in range(60):
        x, y = (float(v) for v in rng.normal(size=2) * 3.0)
        last = float(rng.uniform(-0.2, 1.2) * span)
        lo, hi = sorted(float(v) for v in rng.uniform(-0.6, 1.6, size=2) * span)
        windows = [(lo, hi, last, 1e-12), (-math.inf, math.inf, math.nan, 1.0)]
        windows += [(last - 1e-3 * span, last + 1e-3 * span, last, 1e-12), (last, last, last, 0.0)]
        windows += [(math.nan, math.nan, last, 1e-12), (lo, math.inf, last, 1e-12)]
        windows += [(-math.inf, hi, last, 1e-12), (hi, lo, last, 1e-12)]  # an empty window
        for lo_, hi_, last_, slack in windows:
            try:
                want = scanned(geo, x, y, lo_, hi_, last_, slack)
            except AssertionError:  # no segment in the window: so it stays
                with pytest.raises(AssertionError):
                    geo.project(x, y, lo_, hi_, last_, slack)
                continue
            assert geo.project(x, y, lo_, hi_, last_, slack) == want
        for s in (*rng.uniform(-0.5, 1.5, size=8) * span, 0.0, geo.length, *geo.starts, math.nan):
            wrapped = s % geo.length if geo.closed else min(max(s, 0.0), geo.length)
            i = walked(geo, wrapped)
            a, b = geo.vertices[i], geo.vertices[i + 1]
            u = (wrapped - geo.starts[i]) / (geo.starts[i + 1] - geo.starts[i])
            want_at = (a[0] + u * (b[0] - a[0]), a[1] + u * (b[1] - a[1]))
            got = geo.at(float(s))
            assert got[:2] == want_at or (math.isnan(s) and all(map(math.isnan, got[:2])))


def test_a_path_of_100000_points_is_followed_in_time() -> None:
    """500 readings along 100,000 points: 10 s or more when each looked at every segment."""
    u = np.linspace(0.0, 1000.0, 100_000)
    spec = PathSpec("p", "polyline", tuple(zip(u.tolist(), np.sin(u / 10).tolist(), strict=True)))
    xs = np.linspace(0.0, 20.0, 500)
    start = time.process_time()
    lateral, progress = track(spec, xs.tolist(), (np.sin(xs / 10) + 0.05).tolist())
    took = time.process_time() - start
    assert took < 3.0, f"{took:.1f} s"
    assert progress[-1] == pytest.approx(math.dist((0, 0), (20, math.sin(2))), rel=0.01)
    assert all(abs(v - 0.05) < 0.01 for v in lateral)


def summed_afresh(geo: PathGeometry, look: float) -> float:
    """``_least_turn`` as it was: the turns up to each point summed afresh (O(n^2))."""
    v, starts, length = geo.vertices, geo.starts, geo.length
    n = len(v) - 1
    heads = [math.atan2(v[k + 1][1] - v[k][1], v[k + 1][0] - v[k][0]) for k in range(n)]
    turns = [_wrap(heads[k] - heads[k - 1]) for k in range(n)]
    total = sum(turns)

    def turned_to(u: float) -> float:
        laps = math.floor(u / length)
        rest = u - laps * length
        return laps * total + sum(t for t, at in zip(turns, starts, strict=False) if at <= rest)

    marks = sorted({*starts[:n], *((at - look) % length for at in starts[:n])})
    marks.append(marks[0] + length)
    return min(
        abs(turned_to(s + look) - turned_to(s))
        for s in ((a + b) / 2 for a, b in zip(marks, marks[1:], strict=False))
    )


@pytest.mark.parametrize("seed", range(20))
def test_the_least_turn_within_the_lookahead_is_as_it_was(seed: int) -> None:
    """A closed path's lookahead note summed the turns afresh for each point: 40 s for a
    polygon of 20,000 sides. The sums are kept now, added in the same order: the same bits."""
    rng = np.random.default_rng(seed)
    spec = random_path(rng)
    if not spec.closed:
        spec = PathSpec("p", "polygon", spec.points + ((7.0, -3.0),), closed=True)
    geo = PathGeometry(spec)
    for look in (1e-3, 0.5, 1.0, 0.3 * geo.length, 2.5 * geo.length):
        assert _least_turn(geo, look) == summed_afresh(geo, look)


def test_a_polygon_of_20000_sides_is_checked_in_time() -> None:
    a = np.linspace(0.0, 2 * math.pi, 20_000, endpoint=False)
    spec = PathSpec(
        "p",
        "polygon",
        tuple(zip((5 * np.sin(a)).tolist(), (5 - 5 * np.cos(a)).tolist(), strict=True)),
        closed=True,
    )
    start = time.process_time()
    turned = _least_turn(PathGeometry(spec), 1.0)
    assert time.process_time() - start < 2.0
    assert turned == pytest.approx(0.2, rel=1e-3)  # 1 m round a 5 m circle: 0.2 rad
