"""Drawing shapes as geometry: triangle meshes (player, glTF, 3D video) and side outlines (2D video).

Every shape lives in its body's frame (see ``legdsl.ir.model.Shape``): a box is
centred at its ``center``; a frustum, cylinder or capsule runs along the link
from the body origin to ``Body.tip``; a sphere sits at its ``center``. A body
with a frustum, cylinder or capsule but no length is drawn as a sphere of the
first radius. Meshes have their own vertices per flat face (so normals are
sharp at box edges and cylinder rims) and counter-clockwise triangles seen
from outside.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from legdsl.ir.model import Body, Terrain

SEGMENTS = 24  # around a solid of revolution
RINGS = 6  # per hemisphere of a sphere or capsule end
DEFAULT_COLOR = "#9a9a9a"


@dataclass(frozen=True)
class Mesh:
    positions: np.ndarray  # (V, 3) float32
    normals: np.ndarray  # (V, 3) float32, unit
    indices: np.ndarray  # (T, 3) uint32

    @property
    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        return self.positions.min(axis=0), self.positions.max(axis=0)


class _Builder:
    def __init__(self) -> None:
        self.pos: list[np.ndarray] = []
        self.nrm: list[np.ndarray] = []
        self.tri: list[np.ndarray] = []
        self.count = 0

    def add(self, pos: np.ndarray, nrm: np.ndarray, tri: np.ndarray) -> None:
        self.pos.append(pos)
        self.nrm.append(nrm / np.linalg.norm(nrm, axis=1, keepdims=True))
        self.tri.append(tri + self.count)
        self.count += len(pos)

    def mesh(self) -> Mesh:
        return Mesh(
            np.concatenate(self.pos).astype(np.float32),
            np.concatenate(self.nrm).astype(np.float32),
            np.concatenate(self.tri).astype(np.uint32),
        )


def _basis(axis: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Two unit vectors that make (u, w, axis) a right-handed orthonormal frame."""
    helper = np.array([1.0, 0.0, 0.0]) if abs(axis[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    u = np.cross(helper, axis)
    u /= np.linalg.norm(u)
    return u, np.cross(axis, u)


def _grid_triangles(rows: int, cols: int) -> np.ndarray:
    """Triangles of a row-major (rows+1) x (cols+1) vertex grid, facing along rows x columns."""
    tris = []
    for i in range(rows):
        for j in range(cols):
            a = i * (cols + 1) + j
            b, c, d = a + 1, a + cols + 1, a + cols + 2
            tris += [(a, b, c), (b, d, c)]
    return np.array(tris, dtype=np.int64)


def _disc(b: _Builder, centre: np.ndarray, radius: float, normal: np.ndarray) -> None:
    u, w = _basis(normal)
    angles = np.linspace(0.0, 2 * math.pi, SEGMENTS, endpoint=False)
    rim = centre + radius * (np.outer(np.cos(angles), u) + np.outer(np.sin(angles), w))
    pos = np.vstack([centre, rim])
    tri = np.array([(0, 1 + k, 1 + (k + 1) % SEGMENTS) for k in range(SEGMENTS)])
    b.add(pos, np.tile(normal, (len(pos), 1)), tri)


def _side(b: _Builder, p0: np.ndarray, p1: np.ndarray, r0: float, r1: float) -> None:
    """The lateral surface of a frustum from p0 (radius r0) to p1 (radius r1)."""
    axis = p1 - p0
    length = float(np.linalg.norm(axis))
    axis = axis / length
    u, w = _basis(axis)
    angles = np.linspace(0.0, 2 * math.pi, SEGMENTS + 1)
    radial = np.outer(np.cos(angles), u) + np.outer(np.sin(angles), w)
    pos = np.vstack([p0 + r0 * radial, p1 + r1 * radial])
    slant = radial * length + axis * (r0 - r1)
    b.add(pos, np.vstack([slant, slant]), _grid_triangles(1, SEGMENTS))


def _cap(b: _Builder, centre: np.ndarray, radius: float, pole: np.ndarray) -> None:
    """A hemisphere on ``centre`` bulging towards ``pole`` (unit)."""
    u, w = _basis(pole)
    lat = np.linspace(0.0, math.pi / 2, RINGS + 1)  # from the rim to the pole
    lon = np.linspace(0.0, 2 * math.pi, SEGMENTS + 1)
    dirs = np.array(
        [
            math.cos(a) * (math.cos(o) * u + math.sin(o) * w) + math.sin(a) * pole
            for a in lat
            for o in lon
        ]
    )
    tri = _grid_triangles(RINGS, SEGMENTS)
    b.add(centre + radius * dirs, dirs, tri)


def _box(b: _Builder, centre: np.ndarray, size: np.ndarray, divisions: int) -> None:
    """Six faces, each a ``divisions`` x ``divisions`` grid of quads."""
    half = size / 2
    steps = np.linspace(-1.0, 1.0, divisions + 1)
    for axis in range(3):
        for sign in (-1.0, 1.0):
            n = np.zeros(3)
            n[axis] = sign
            u_axis, w_axis = (axis + 1) % 3, (axis + 2) % 3
            if sign < 0:
                u_axis, w_axis = w_axis, u_axis
            points = []
            for cw in steps:  # rows along w, columns along u
                for cu in steps:
                    p = centre + n * half
                    p[u_axis] += cu * half[u_axis]
                    p[w_axis] += cw * half[w_axis]
                    points.append(p)
            tri = _grid_triangles(divisions, divisions)
            b.add(np.array(points), np.tile(n, (len(points), 1)), tri)


def _sphere(b: _Builder, centre: np.ndarray, radius: float) -> None:
    z = np.array([0.0, 0.0, 1.0])
    _cap(b, centre, radius, z)
    _cap(b, centre, radius, -z)


def body_mesh(body: Body, box_divisions: int = 1) -> Mesh:
    """The body's shape as a triangle mesh in its frame.

    ``box_divisions`` splits each box face into a grid: more triangles, which
    a renderer that sorts triangles back to front (the 3D video) orders better.
    """
    shape = body.shape
    b = _Builder()
    centre = np.array(shape.center, dtype=float)
    tip = np.array(body.tip, dtype=float)
    origin = np.zeros(3)
    if shape.kind == "box":
        _box(b, centre, np.array([shape.get("x"), shape.get("y"), shape.get("z")]), box_divisions)
    elif shape.kind == "sphere" or not np.any(tip):
        radius = shape.get("r") if shape.kind in ("sphere", "capsule", "cylinder") else None
        _sphere(b, centre if shape.kind == "sphere" else origin, radius or shape.get("r0"))
    else:
        r0, r1 = (
            (shape.get("r0"), shape.get("r1")) if shape.kind == "frustum" else (shape.get("r"),) * 2
        )
        axis = tip / np.linalg.norm(tip)
        _side(b, origin, tip, r0, r1)
        if shape.kind == "capsule":
            _cap(b, origin, r0, -axis)
            _cap(b, tip, r1, axis)
        else:
            _disc(b, origin, r0, -axis)
            _disc(b, tip, r1, axis)
    return b.mesh()


def side_outline(body: Body) -> np.ndarray:
    """The shape seen from the side (along y) as a closed polygon of (x, z) in the body frame.

    For planar creatures, whose bodies only turn about y.
    """
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
        a = np.linspace(0.0, 2 * math.pi, 2 * SEGMENTS, endpoint=False)
        return np.column_stack([centre[0] + radius * np.cos(a), centre[1] + radius * np.sin(a)])
    r0, r1 = (
        (shape.get("r0"), shape.get("r1")) if shape.kind == "frustum" else (shape.get("r"),) * 2
    )
    length = float(np.linalg.norm(tip))
    d = tip / length
    n = np.array([-d[1], d[0]])  # the side normal, 90 degrees from d
    if shape.kind != "capsule":
        return np.array([r0 * n, tip + r1 * n, tip - r1 * n, -r0 * n])
    a = np.linspace(-math.pi / 2, math.pi / 2, SEGMENTS // 2 + 1)
    end = [tip + r1 * (math.cos(t) * d + math.sin(t) * n) for t in a]
    start = [-r0 * (math.cos(t) * d + math.sin(t) * n) for t in a]
    return np.array(end + start)


def hex_rgb(color: str | None) -> tuple[float, float, float]:
    """``#rrggbb`` (sRGB) as three floats in [0, 1]."""
    text = (color or DEFAULT_COLOR).lstrip("#")
    return (int(text[0:2], 16) / 255, int(text[2:4], 16) / 255, int(text[4:6], 16) / 255)


def srgb_to_linear(c: float) -> float:
    return c / 12.92 if c <= 0.04045 else ((c + 0.055) / 1.055) ** 2.4


GROUND_COLOR = "#d9d9cc"
TERRAIN_COLOR = "#b3b3a6"


def ground_meshes(
    terrain: tuple[Terrain, ...], lo: np.ndarray, hi: np.ndarray
) -> list[tuple[str, Mesh, str]]:
    """The ground under the area ``lo``..``hi`` (x, y) in world coordinates (z up), as meshes.

    (name, mesh, colour) for the ``floor`` (a flat quad, or the slope's tilted quad,
    as ``legdsl.sim.contact`` has them) and each raised step or box (a box from
    the floor to its height), cut to the floor's area: a step runs to its +x end (a
    step ran a metre past a mite's 9 cm floor). Features at or below the floor change
    nothing in the simulation and are left out, and so are those wholly off the floor.
    """
    out = []
    slope = next((t for t in terrain if t.kind == "slope"), None)
    (x0, y0), (x1, y1) = lo, hi
    corners = np.array([[x0, y0, 0.0], [x1, y0, 0.0], [x1, y1, 0.0], [x0, y1, 0.0]])
    normal = np.array([0.0, 0.0, 1.0])
    if slope is not None:  # tilted about y, rising towards +x, through the origin
        a = slope.get("angle")
        corners[:, 2] = corners[:, 0] * math.tan(a)
        normal = np.array([-math.sin(a), 0.0, math.cos(a)])
    b = _Builder()
    b.add(corners, np.tile(normal, (4, 1)), np.array([[0, 1, 2], [0, 2, 3]]))
    out.append(("floor", b.mesh(), GROUND_COLOR))
    for i, t in enumerate(terrain):
        if t.kind == "slope" or t.get("height") <= 0:
            continue
        h = t.get("height")
        if t.kind == "step":
            xa, xb, ya, yb = max(t.get("x"), x0), x1, y0, y1
        else:
            xa, xb = max(t.get("x0"), x0), min(t.get("x1"), x1)
            ya, yb = max(t.get("y0"), y0), min(t.get("y1"), y1)
        if xb <= xa or yb <= ya:
            continue
        b = _Builder()
        _box(b, np.array([(xa + xb) / 2, (ya + yb) / 2, h / 2]), np.array([xb - xa, yb - ya, h]), 1)
        out.append((f"terrain{i}_{t.kind}", b.mesh(), TERRAIN_COLOR))
    return out
