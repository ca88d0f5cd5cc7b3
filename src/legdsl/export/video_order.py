"""The order a 3D video paints its polygons in: back to front, each terrain face between
what lies behind its plane and what lies in front of it.

The links' triangles are small, and sorting them by their centres' depth is enough among
themselves. A step's top is one polygon from the step's edge to the floor's far end: its
centre's depth said nothing of what it hides, and it was painted over a link standing above
it (a leg over a 5 cm step cut off at the step's edge). A terrain face's plane decides it
instead: nothing behind the plane (away from the eye) can hide the face, and the face can
hide nothing in front of it, so drawing the one side, the face, then the other is right
wherever the polygons' pictures overlap (a binary space partition over the faces the camera
sees). A polygon across a plane is cut along it.
"""

from __future__ import annotations

from typing import Any

import numpy as np

Face = tuple[float, np.ndarray, Any]  # depth of its centre, (k, 3) polygon, colour


def split_polygon(
    poly: np.ndarray, normal: np.ndarray, offset: float
) -> tuple[np.ndarray | None, np.ndarray | None]:
    """The parts of the convex polygon ``poly`` where ``normal . p >= offset`` and where it is
    at most ``offset`` (None for a part with fewer than three corners)."""
    s = poly @ normal - offset
    inside: list[np.ndarray] = []
    outside: list[np.ndarray] = []
    for i in range(len(poly)):
        j = (i + 1) % len(poly)
        if s[i] >= 0:
            inside.append(poly[i])
        if s[i] <= 0:
            outside.append(poly[i])
        if s[i] * s[j] < 0:  # the edge crosses the plane: its crossing is a corner of both
            cross = poly[i] + (s[i] / (s[i] - s[j])) * (poly[j] - poly[i])
            inside.append(cross)
            outside.append(cross)
    return (
        np.array(inside) if len(inside) >= 3 else None,
        np.array(outside) if len(outside) >= 3 else None,
    )


def sides(polys: list[np.ndarray], normals: np.ndarray, offsets: np.ndarray) -> np.ndarray:
    """Each polygon's least and greatest ``normal . p - offset`` over its corners, for each
    plane: (2, len(polys), planes), in one pass over all corners."""
    corners = np.concatenate(polys)
    s = corners @ np.atleast_2d(normals).T - offsets
    starts = np.cumsum([0] + [len(p) for p in polys[:-1]])
    return np.stack([np.minimum.reduceat(s, starts), np.maximum.reduceat(s, starts)])


def seen_faces(box: list[np.ndarray], eye: np.ndarray) -> list[int]:
    """Which faces of a terrain block (a convex solid) face ``eye``: the others are hidden
    behind them, and would only add planes to cut along."""
    centre = np.concatenate(box).mean(axis=0)
    seen = []
    for k, face in enumerate(box):
        normal = np.cross(face[1] - face[0], face[2] - face[0])
        outward = normal if normal @ (face.mean(axis=0) - centre) > 0 else -normal
        if outward @ (eye - face[0]) > 0:
            seen.append(k)
    return seen


Wall = tuple[Face, list[Face]]  # a terrain face and what lies on it (shadows), drawn with it


def back_to_front(
    faces: list[Face], walls: list[Wall], eye: np.ndarray, depth: Any, scale: float
) -> list[Face]:
    """``faces`` and the terrain's ``walls`` (faces facing ``eye``, each followed by the
    shadows on it) in the order to paint them. Without walls, the faces by depth as before;
    ``depth`` gives a cut part its centre's depth; a polygon within a billionth of ``scale``
    of a wall's plane (a foot standing on a step) is in front of it."""
    if not walls:
        return sorted(faces, key=lambda f: -f[0])
    (wall, on_it), rest = walls[0], walls[1:]
    normal = np.cross(wall[1][1] - wall[1][0], wall[1][2] - wall[1][0])
    normal /= np.linalg.norm(normal)
    if normal @ (eye - wall[1][0]) < 0:  # the eye's side is the plane's front
        normal = -normal
    offset = float(normal @ wall[1][0])
    tol = 1e-9 * max(scale, abs(offset))

    def parted(group: list[Face]) -> tuple[list[Face], list[Face]]:
        """``group`` in front of the plane and behind it, those across it cut in two."""
        front: list[Face] = []
        back: list[Face] = []
        if not group:
            return front, back
        low, high = sides([f[1] for f in group], normal, np.array([offset]))[:, :, 0]
        for face, least, most in zip(group, low, high, strict=True):
            if least >= -tol:
                front.append(face)
            elif most <= tol:
                back.append(face)
            else:
                parts = split_polygon(face[1], normal, offset)
                for part, side in zip(parts, (front, back), strict=True):
                    if part is not None:
                        side.append((depth(part), part, face[2]))
        return front, back

    front_faces, back_faces = parted(faces)
    front_walls: list[Wall] = []
    back_walls: list[Wall] = []
    for other, shadows in rest:  # a wall cut in two takes the shadows' parts on each
        ahead, behind = parted([other])
        shadows_ahead, shadows_behind = parted(shadows)
        front_walls += [(part, shadows_ahead) for part in ahead]
        back_walls += [(part, shadows_behind) for part in behind]
    return (
        back_to_front(back_faces, back_walls, eye, depth, scale)
        + [wall, *on_it]
        + back_to_front(front_faces, front_walls, eye, depth, scale)
    )
