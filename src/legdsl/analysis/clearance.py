"""Does the creature's body pass through the terrain? Its shapes against the terrain's boxes and steps.

The simulation's ground acts on the contact points only (the side faces of steps and boxes
are not modelled, ``legdsl.sim.contact``), so a trunk or a tail can pass through a box
without feeling it. This check takes the recorded body poses (``dyn.body_poses(q)`` for
each sample: the world origin and row-major rotation of every body, in the model's body
order) and each body's drawing shape (``Body.shape``, in the body frame, as the player
draws it) and measures, for every sample and feature, the *margin* between them: the
distance by which they are apart, negative when they overlap (by the depth of the overlap).

For a planar creature the test is exact: the shapes seen from the side are convex polygons
(a sphere's circle and a capsule's ends are circumscribed polygons, so the margin errs
towards an overlap by well under a millimetre) and a planar box or step spans every y, so
the separating-axis test on the two polygons gives the margin. In 3D the shapes are
sampled on their surfaces (a few hundred points each) and a point inside a feature counts
as an overlap; the margin is then the smallest distance of a sampled point to it (inside,
minus the depth of the deepest point).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from legdsl.ir.model import Body, Terrain

Pose = tuple[Sequence[float], Sequence[float]]  # (origin, row-major 3x3 rotation)
SIDES = 32  # a circle's polygon
FAR = 1e3  # how far a step extends (it has no far edge)


@dataclass(frozen=True)
class Contact:
    """The least margin between one feature and the creature over a run."""

    feature: int  # index into the terrain
    margin: float  # m; negative: the shapes overlap the feature by that depth
    t: float  # when it is least
    body: str  # the body that comes closest (or overlaps most)
    overlapping: tuple[float, ...]  # the sample times at which some body overlaps it


def _circle(cx: float, cz: float, r: float) -> list[tuple[float, float]]:
    out = r / math.cos(math.pi / SIDES)  # circumscribed: never smaller than the circle
    return [
        (cx + out * math.cos(2 * math.pi * k / SIDES), cz + out * math.sin(2 * math.pi * k / SIDES))
        for k in range(SIDES)
    ]


def side_polygon(body: Body) -> np.ndarray:
    """The body's shape seen from the side, as a convex polygon of (x, z) in its frame."""
    shape = body.shape
    cx, _, cz = shape.center
    tip = np.array([body.tip[0], body.tip[2]])
    if shape.kind == "box":
        hx, hz = shape.get("x") / 2, shape.get("z") / 2
        return np.array(
            [(cx - hx, cz - hz), (cx + hx, cz - hz), (cx + hx, cz + hz), (cx - hx, cz + hz)]
        )
    if shape.kind == "sphere" or not np.any(tip):
        radius = shape.get("r") if shape.kind != "frustum" else shape.get("r0")
        centre = (cx, cz) if shape.kind == "sphere" else (0.0, 0.0)
        return np.array(_circle(centre[0], centre[1], radius))
    r0, r1 = (
        (shape.get("r0"), shape.get("r1")) if shape.kind == "frustum" else (shape.get("r"),) * 2
    )
    if shape.kind == "capsule":
        points = _circle(0.0, 0.0, r0) + _circle(float(tip[0]), float(tip[1]), r1)
        return _hull(np.array(points))
    d = tip / float(np.linalg.norm(tip))
    n = np.array([-d[1], d[0]])
    return np.array([r0 * n, tip + r1 * n, tip - r1 * n, -r0 * n])


def _hull(points: np.ndarray) -> np.ndarray:
    """The convex hull (monotone chain), counter-clockwise."""
    pts = sorted({(float(x), float(z)) for x, z in points})

    def half(seq: list[tuple[float, float]]) -> list[tuple[float, float]]:
        out: list[tuple[float, float]] = []
        for p in seq:
            while len(out) >= 2:
                (ax, az), (bx, bz) = out[-2], out[-1]
                if (bx - ax) * (p[1] - az) - (bz - az) * (p[0] - ax) > 0:
                    break
                out.pop()
            out.append(p)
        return out

    lower, upper = half(pts), half(pts[::-1])
    return np.array(lower[:-1] + upper[:-1])


def _rect(t: Terrain) -> tuple[float, float, float]:
    """(x0, x1, height) of a feature seen from the side."""
    if t.kind == "step":
        return t.get("x"), t.get("x") + FAR, t.get("height")
    return t.get("x0"), t.get("x1"), t.get("height")


def _separation(a: np.ndarray, b: np.ndarray) -> float:
    """The largest gap between two convex polygons along their edge normals (< 0: overlap)."""
    best = -math.inf
    for poly in (a, b):
        edges = np.roll(poly, -1, axis=0) - poly
        normals = np.column_stack([edges[:, 1], -edges[:, 0]])
        normals /= np.linalg.norm(normals, axis=1, keepdims=True)
        pa, pb = a @ normals.T, b @ normals.T
        gaps = np.maximum(pb.min(axis=0) - pa.max(axis=0), pa.min(axis=0) - pb.max(axis=0))
        best = max(best, float(gaps.max()))
    return best


def _surface_points(body: Body) -> np.ndarray:
    """Points on the body's shape in its frame (3D creatures)."""
    poly = side_polygon(body)  # the outline in x-z, swept about the shape's own axis
    shape = body.shape
    if shape.kind == "box":
        sx, sy, sz = shape.get("x"), shape.get("y"), shape.get("z")
        g = np.linspace(-0.5, 0.5, 9)
        grid = np.array([(a, b, c) for a in g for b in g for c in g])
        on = np.abs(grid).max(axis=1) >= 0.5
        return grid[on] * (sx, sy, sz) + np.array(shape.center)
    tip = np.array(body.tip, dtype=float)
    if shape.kind == "sphere" or not np.any(tip):
        r = float(np.max(np.linalg.norm(poly - poly.mean(axis=0), axis=1)))
        centre = np.array(shape.center if shape.kind == "sphere" else (0.0, 0.0, 0.0))
        u = np.linspace(0, math.pi, 9)
        v = np.linspace(0, 2 * math.pi, 16, endpoint=False)
        return centre + r * np.array(
            [
                (math.sin(a) * math.cos(b), math.sin(a) * math.sin(b), math.cos(a))
                for a in u
                for b in v
            ]
        )
    r0, r1 = (
        (shape.get("r0"), shape.get("r1")) if shape.kind == "frustum" else (shape.get("r"),) * 2
    )
    axis = tip / np.linalg.norm(tip)
    helper = np.array([1.0, 0.0, 0.0]) if abs(axis[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    u = np.cross(helper, axis)
    u /= np.linalg.norm(u)
    w = np.cross(axis, u)
    out = []
    for f in np.linspace(0.0, 1.0, 9):
        r = r0 + (r1 - r0) * f
        for a in np.linspace(0, 2 * math.pi, 16, endpoint=False):
            for scale in (1.0, 0.5, 0.0) if f in (0.0, 1.0) else (1.0,):
                out.append(f * tip + scale * r * (math.cos(a) * u + math.sin(a) * w))
    return np.array(out)


def _box_margin(points: np.ndarray, t: Terrain) -> float:
    """The smallest distance of any point to a feature's block (< 0: inside, by the depth)."""
    x0, x1, h = _rect(t)
    y0, y1 = (t.get("y0"), t.get("y1")) if t.kind == "box" else (-FAR, FAR)
    lo, hi = np.array([x0, y0, -FAR]), np.array([x1, y1, h])
    outside = np.maximum(lo - points, points - hi)
    gap = np.linalg.norm(np.maximum(outside, 0.0), axis=1)
    inside = np.minimum(outside.max(axis=1), 0.0)
    return float(np.min(np.where(gap > 0, gap, inside)))


def terrain_contacts(
    bodies: Sequence[Body],
    terrain: Sequence[Terrain],
    times: Sequence[float],
    poses: Sequence[Sequence[Pose]],
    planar: bool,
) -> list[Contact]:
    """For each step or box of the terrain, the least margin to the creature's shapes over the run."""
    features = [(i, t) for i, t in enumerate(terrain) if t.kind in ("step", "box")]
    if planar:
        local = [side_polygon(b) for b in bodies]
        rects = {
            i: np.array([(x0, -FAR), (x1, -FAR), (x1, h), (x0, h)])
            for i, t in features
            for x0, x1, h in [_rect(t)]
        }
    else:
        local = [_surface_points(b) for b in bodies]
    out = []
    for i, t in features:
        least, when, who, hits = math.inf, math.nan, "", []
        for time, pose in zip(times, poses, strict=True):
            overlap = False
            for body, shape, (origin, rot) in zip(bodies, local, pose, strict=True):
                r = np.array(rot, dtype=float).reshape(3, 3)
                o = np.array(origin, dtype=float)
                if planar:
                    # the x-z plane of the body frame: world (x, z) = o + R[[0,2]][:, [0,2]] p
                    m = r[np.ix_([0, 2], [0, 2])]
                    world = shape @ m.T + o[[0, 2]]
                    margin = _separation(world, rects[i])
                else:
                    margin = _box_margin(shape @ r.T + o, t)
                if margin < least:
                    least, when, who = margin, float(time), body.name
                overlap = overlap or margin < 0
            if overlap:
                hits.append(float(time))
        out.append(Contact(i, least, when, who, tuple(hits)))
    return out
