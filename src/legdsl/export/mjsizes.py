"""The creature's size as the MJCF export needs it: its contact spheres' radius, the length of
a ``step``'s box and MuJoCo's view scale (``<statistic>``), all from the creature, not from
the terrain (a 100 m step made a 5 cm hopper's near clipping plane 1.4 m away)."""

from __future__ import annotations

import math

import numpy as np

from legdsl.ir.model import Body, Model

CONTACT_RADIUS = 0.005  # m: the sphere touches the floor when the contact point is this high
RADIUS_PER_LINK = 0.02  # a small creature's spheres: this times its longest link
TERRAIN_EXTENT = 50.0  # m, least half length of the box that draws a 'step' (it extends to +x)
TERRAIN_PER_SIZE = 25.0  # a large creature's step: half as long as this many of its sizes


def _body_points(body: Body, model: Model) -> list[np.ndarray]:
    """The body's origin, link tip, contact points and shape's bounding corners, in its frame."""
    s = body.shape
    tip = np.asarray(body.tip, float)
    points = [np.zeros(3), tip]
    points += [np.asarray(c.point, float) for c in model.contacts if c.body == body.name]
    if s.kind == "box":
        half = np.array([s.get("x"), s.get("y"), s.get("z")]) / 2
        centres = [np.asarray(s.center, float)]
    else:
        r = max(s.get("r0"), s.get("r1")) if s.kind == "frustum" else s.get("r")
        half = np.full(3, r)
        centres = [np.asarray(s.center, float)] if s.kind == "sphere" else [np.zeros(3), tip]
    points += [c + sign * half for c in centres for sign in (-1.0, 1.0)]
    return points


def creature_box(model: Model) -> tuple[np.ndarray, np.ndarray]:
    """The bounding box (low and high corners) of the creature as the MJCF writes it, at zero
    joint coordinates: bodies at their joints' origins, with their shapes and contacts."""
    origin: dict[str, np.ndarray] = {}
    points: list[np.ndarray] = []
    joints = {j.child: j for j in model.joints}
    for body in model.bodies:  # parents come before their children
        at = origin.get(body.parent or "", np.zeros(3)) + np.asarray(joints[body.name].origin)
        origin[body.name] = at
        points += [at + p for p in _body_points(body, model)]
    stacked = np.vstack(points)
    return stacked.min(axis=0), stacked.max(axis=0)


def creature_size(model: Model) -> float:
    """The diagonal of ``creature_box``, as MuJoCo measures its ``stat.extent``."""
    low, high = creature_box(model)
    return float(np.linalg.norm(high - low))


def step_half_length(model: Model) -> float:
    """Half the length of a step's box: 50 m, or more for a creature over 2 m."""
    return max(TERRAIN_EXTENT, TERRAIN_PER_SIZE * creature_size(model))


def contact_radius(model: Model) -> float:
    """The contact spheres' radius: 5 mm, at most a fiftieth of the longest link, or of the
    creature's size where it has no link lengths (a 3 mm brick kept 5 mm spheres, whose
    surface, where MuJoCo's contact force acts, was 5 mm below its corners)."""
    links = [math.hypot(*j.origin) for j in model.joints] + [
        math.hypot(*b.tip) for b in model.bodies
    ]
    longest = max(links, default=0.0) or creature_size(model)
    return min(CONTACT_RADIUS, RADIUS_PER_LINK * longest) if longest > 0 else CONTACT_RADIUS
