"""Flat shadows of a 3D video's links, cast along the light onto the ground the player shows:
the slope's plane, or the floor and the tops of the terrain's steps and boxes.

Without a slope a point's shadow falls on the floor (z = 0) unless a block is under that spot,
then on the block's top. A triangle whose three corners fall on one block's top is that top's
(``PerspectiveView`` draws it over the top face); any other is the floor's, and the blocks'
faces drawn in front hide what falls behind them. (The video drew no shadow at all once the
ground had any terrain, though the player draws them.)
"""

from __future__ import annotations

import numpy as np

from legdsl.export.motion import slope_tangent, terrain_height
from legdsl.ir.model import Terrain


def ground_shadows(
    terrain: tuple[Terrain, ...], tris: np.ndarray, light: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """The shadows of the triangles ``tris`` (T, 3, 3) cast along ``light`` (towards the
    light, unit), and the height of the block top each lies on (0: the floor or slope)."""
    tilt = slope_tangent(terrain)
    z = tris[..., 2:3]
    if tilt or not terrain:  # one plane, z = tilt x, through the origin
        along = (z - tilt * tris[..., 0:1]) / (light[2] - tilt * light[0])
        return tris - along * light, np.zeros(len(tris))
    on_floor = tris - (z / light[2]) * light
    height = np.vectorize(lambda x, y: terrain_height(terrain, x, y))(
        on_floor[..., 0], on_floor[..., 1]
    )
    shadows = tris - ((z - height[..., None]) / light[2]) * light
    # a triangle falling across a block's edge is drawn on the floor, where the block hides it
    top = np.where(np.ptp(height, axis=1) == 0, height[:, 0], 0.0)
    return shadows, top


def lies_on(face: np.ndarray, point: np.ndarray) -> bool:
    """Whether ``point`` lies on the level rectangle ``face`` (its four corners)."""
    low, high = face.min(axis=0), face.max(axis=0)
    return bool(
        np.all(point[:2] >= low[:2] - 1e-12)
        and np.all(point[:2] <= high[:2] + 1e-12)
        and abs(point[2] - face[0, 2]) <= 1e-9 * max(1.0, abs(face[0, 2]))
    )
