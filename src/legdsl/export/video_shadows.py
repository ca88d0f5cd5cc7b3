"""Flat shadows of a 3D video's links, cast along the light onto the ground the player shows:
the slope's plane, or the floor and the tops of the terrain's steps and boxes.

Without a slope, the part of a triangle whose light meets a block's top falls on that top;
the rest falls on the floor, where the blocks drawn over it hide what is under them. A
triangle across a block's edge is cut there (it was drawn whole on the floor, under the
block: a leg's shadow reaching onto a step kept a dot of it). ``PerspectiveView`` draws a
top's shadows in front of the top. (The video drew no shadow at all once the ground had any
terrain, though the player draws them.)
"""

from __future__ import annotations

import math

import numpy as np

from legdsl.export.motion import slope_tangent
from legdsl.export.video_order import sides, split_polygon
from legdsl.ir.model import Terrain


def ground_shadows(
    terrain: tuple[Terrain, ...], tris: np.ndarray, light: np.ndarray
) -> tuple[list[np.ndarray], list[tuple[np.ndarray, int]]]:
    """The shadows of the triangles ``tris`` (T, 3, 3) cast along ``light`` (towards the
    light, unit): the polygons on the floor or slope, and those on a block's top with the
    block's index in ``terrain``."""
    tilt = slope_tangent(terrain)
    if tilt or not terrain:  # one plane, z = tilt x, through the origin
        along = (tris[..., 2:3] - tilt * tris[..., 0:1]) / (light[2] - tilt * light[0])
        return list(tris - along * light), []
    whole = tris  # the triangles whose light no block's top has met (yet), as one array
    pieces: list[np.ndarray] = []  # and the parts of those cut, one by one
    raised: list[tuple[np.ndarray, int]] = []
    for normals, offsets, block in _light_over_tops(terrain, light):
        height = terrain[block].get("height")
        s = whole @ normals.T - offsets  # (T, 3 corners, planes)
        inside = np.all(s.min(axis=1) >= 0, axis=1)
        outside = np.any(s.max(axis=1) <= 0, axis=1)
        raised += [(top, block) for top in _cast(whole[inside], light, height)]
        cut_out, cut_in = _parted(list(whole[~inside & ~outside]) + pieces, normals, offsets)
        raised += [(_cast(p, light, height), block) for p in cut_in]
        whole, pieces = whole[outside], cut_out
    return list(_cast(whole, light, 0.0)) + [_cast(p, light, 0.0) for p in pieces], raised


def _cast(polys: np.ndarray, light: np.ndarray, height: float) -> np.ndarray:
    """``polys`` (a polygon's corners, or triangles') moved along ``light`` onto the level
    plane z = ``height``."""
    return polys - ((polys[..., 2:3] - height) / light[2]) * light


def _light_over_tops(
    terrain: tuple[Terrain, ...], light: np.ndarray
) -> list[tuple[np.ndarray, np.ndarray, int]]:
    """For each step and box, highest first, the planes (normals . p >= offsets) bounding the
    points above its top whose light meets the top, and its index in ``terrain``."""
    kx, ky = light[0] / light[2], light[1] / light[2]  # the light's run per unit of rise
    blocks = []
    for index, t in enumerate(terrain):
        if t.kind == "step":
            bounds = (t.get("x"), math.inf, -math.inf, math.inf)
        elif t.kind == "box":
            bounds = (t.get("x0"), t.get("x1"), t.get("y0"), t.get("y1"))
        else:
            continue
        h = t.get("height")
        if h <= 0:
            continue
        # where the light crosses z = h: x - kx (z - h), y - ky (z - h), within the top
        normals, offsets = [np.array([0.0, 0.0, 1.0])], [h]
        for low, high, along in (
            (*bounds[:2], np.array([1.0, 0.0, -kx])),
            (*bounds[2:], np.array([0.0, 1.0, -ky])),
        ):
            k = -along[2]
            if low > -math.inf:
                normals.append(along)
                offsets.append(low - k * h)
            if high < math.inf:
                normals.append(-along)
                offsets.append(k * h - high)
        blocks.append((h, np.array(normals), np.array(offsets), index))
    return [b[1:] for b in sorted(blocks, key=lambda b: -b[0])]


def _parted(
    polys: list[np.ndarray], normals: np.ndarray, offsets: np.ndarray
) -> tuple[list[np.ndarray], list[np.ndarray]]:
    """The parts of ``polys`` outside the convex region ``normals . p >= offsets``, and those
    inside; only a polygon across its bounds is cut (one outside a plane stays whole)."""
    if not polys:
        return [], []
    low, high = sides(polys, normals, offsets)
    outside, inside = [], []
    for poly, least, most in zip(polys, low, high, strict=True):
        if np.all(least >= 0):
            inside.append(poly)
            continue
        if np.any(most <= 0):
            outside.append(poly)
            continue
        rest = poly
        for normal, offset, lowest in zip(normals, offsets, least, strict=True):
            if lowest >= 0:  # wholly inside this plane: nothing to cut off
                continue
            kept, cut = split_polygon(rest, normal, float(offset))
            if cut is not None:
                outside.append(cut)
            if kept is None:
                break
            rest = kept
        else:
            inside.append(rest)
    return outside, inside
