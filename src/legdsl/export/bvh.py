"""Export a run as BVH (Biovision hierarchy), the motion-capture tools' skeleton-and-channels format.

* The skeleton is the link tree: ``ROOT`` is the root body, each other body a
  ``JOINT`` inside its parent's block, with ``OFFSET`` its joint origin in the
  parent frame (legdsl writes bodies at zero joint coordinates with their
  parents' axes, which is BVH's rest pose: every joint frame parallel to the
  world's). A body with no children ends in an ``End Site`` at its link's tip.
* Axes: y-up as BVH tools expect: x stays x (forward), legdsl's z (up) is y
  and legdsl's y (left) is -z, the same turn as the glTF export. Lengths are in
  metres (Blender: import at scale 1).
* Channels: the root has ``Xposition Yposition Zposition Zrotation Xrotation
  Yrotation`` (its world position and orientation); a joint with only hinges
  has ``Zrotation Xrotation Yrotation``; a joint with a slide also has the
  three position channels, which hold its whole local translation (the offset
  plus the slide's displacement, so the offset at rest): as Blender's importer
  and exporter and motion-capture tools read them, position channels replace
  ``OFFSET``, they are not added to it (the root's ``OFFSET`` is 0 and its
  channels its world position, the same either way). Rotations are in degrees, applied in the listed order (the
  joint's local rotation is Rz Rx Ry), relative to the parent joint; each
  frame's angles are the solution nearest the frame before's (whole turns
  added), so that a channel never jumps by a turn between frames.
* ``Frame Time`` is one over the frame rate (``--fps``).
* Numbers: angles with six decimals (1e-6 degree); lengths with six decimals (1 um) for a
  creature of 10 cm or more, and one more for each tenfold smaller (a 0.7 mm mite's are
  written to 1e-9 m), so a small creature's motion is not rounded away.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from legdsl.export.gltf import local_poses
from legdsl.export.motion import Motion, frame_rate, quaternion_to_matrix
from legdsl.files import write_atomic

# legdsl z-up to BVH y-up: (x, y, z) -> (x, z, -y)
Z_UP_TO_Y_UP = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]])
ROTATION_CHANNELS = ("Zrotation", "Xrotation", "Yrotation")
ANGLE_DECIMALS = 6  # 1e-6 degree
LENGTH_DECIMALS = 6  # 1 um, for creatures of FULL_PRECISION_SIZE and more
FULL_PRECISION_SIZE = 0.1  # m
END_SITE_LENGTH = 0.01  # m: a leaf body with no tip; at most a tenth of a smaller creature
POSITION_CHANNELS = ("Xposition", "Yposition", "Zposition")


def euler_zxy(m: np.ndarray) -> tuple[float, float, float]:
    """Angles (z, x, y) in degrees with ``m = Rz(z) Rx(x) Ry(y)``."""
    x = math.asin(max(-1.0, min(1.0, m[2, 1])))
    if abs(m[2, 1]) < 1.0 - 1e-12:
        z = math.atan2(-m[0, 1], m[1, 1])
        y = math.atan2(-m[2, 0], m[2, 2])
    else:  # gimbal lock: put the whole turn about the vertical into z
        z = math.atan2(m[1, 0], m[0, 0])
        y = 0.0
    return math.degrees(z), math.degrees(x), math.degrees(y)


def nearest_euler(angles: tuple[float, float, float], previous: np.ndarray) -> np.ndarray:
    """The (z, x, y) angles of the same turn as ``angles`` nearest to ``previous``: of its two
    solutions, (z, x, y) and (z + 180, 180 - x, y + 180), each angle moved by whole turns.
    Tools interpolate the channels (and resample them to their own frame rate), so an angle
    that wrapped from 179 to -179 degrees would spin the joint a whole turn between frames."""
    z, x, y = angles
    best = np.array(angles)
    best_distance = math.inf
    for candidate in (np.array([z, x, y]), np.array([z + 180.0, 180.0 - x, y + 180.0])):
        candidate = candidate - 360.0 * np.round((candidate - previous) / 360.0)
        distance = float(np.abs(candidate - previous).sum())
        if distance < best_distance:
            best, best_distance = candidate, distance
    return best


def skeleton_size(motion: Motion, offsets: np.ndarray) -> float:
    """The creature's size in metres: its longest joint origin or link, or its extent at the
    first frame, whichever is the most."""
    tips = np.array([np.asarray(b.tip, dtype=float) for b in motion.bodies]).reshape(-1, 3)
    lengths = np.concatenate([np.linalg.norm(offsets, axis=1), np.linalg.norm(tips, axis=1)])
    extent = np.ptp(motion.positions[0], axis=0).max() if motion.frames else 0.0
    return float(max(lengths.max(initial=0.0), extent))


def length_decimals(size: float) -> int:
    """Decimals of metres that keep 1e-6 of a creature of ``size`` (six from 10 cm up)."""
    if not size > 0 or size >= FULL_PRECISION_SIZE:
        return LENGTH_DECIMALS
    return LENGTH_DECIMALS + math.ceil(math.log10(FULL_PRECISION_SIZE / size) - 1e-9)


def bvh_text(motion: Motion) -> str:
    """The BVH file of ``motion`` (see the module docstring)."""
    translations, rotations = local_poses(motion)
    nb = len(motion.bodies)
    if motion.joint_origins is not None:
        offsets = motion.joint_origins
        slides = list(motion.joint_slides)
    else:  # a motion made without its model: every joint that moves from where it starts slides
        offsets = translations[0]
        moved = np.abs(translations - offsets[None]).max(axis=0).max(axis=1)
        slides = [bool(m > 1e-9) for m in moved]
    children: dict[int, list[int]] = {b: [] for b in range(-1, nb)}
    for b, parent in enumerate(motion.parents):
        children[parent].append(b)

    size = skeleton_size(motion, offsets)
    decimals = length_decimals(size)
    end_site_length = min(END_SITE_LENGTH, 0.1 * size) if size > 0 else END_SITE_LENGTH
    lines = ["HIERARCHY"]
    order: list[int] = []

    def fmt(v: np.ndarray, places: int = decimals) -> str:
        return " ".join(f"{float(x):.{places}f}" for x in v)

    def joint(b: int, depth: int) -> None:
        pad = "  " * depth
        root = motion.parents[b] < 0
        order.append(b)
        lines.append(f"{pad}{'ROOT' if root else 'JOINT'} {motion.bodies[b].name}")
        lines.append(f"{pad}{{")
        offset = np.zeros(3) if root else Z_UP_TO_Y_UP @ offsets[b]
        lines.append(f"{pad}  OFFSET {fmt(offset)}")
        channels = (
            (*POSITION_CHANNELS, *ROTATION_CHANNELS) if root or slides[b] else ROTATION_CHANNELS
        )
        lines.append(f"{pad}  CHANNELS {len(channels)} {' '.join(channels)}")
        for child in children[b]:
            joint(child, depth + 1)
        if not children[b]:
            tip = np.asarray(motion.bodies[b].tip, dtype=float)
            end = Z_UP_TO_Y_UP @ (tip if np.any(tip) else np.array([0.0, 0.0, end_site_length]))
            lines.append(f"{pad}  End Site")
            lines.append(f"{pad}  {{")
            lines.append(f"{pad}    OFFSET {fmt(end)}")
            lines.append(f"{pad}  }}")
        lines.append(f"{pad}}}")

    for root in children[-1]:
        joint(root, 0)
    lines.append("MOTION")
    lines.append(f"Frames: {motion.frames}")
    lines.append(f"Frame Time: {1.0 / frame_rate(motion):.9f}")
    previous = np.zeros((nb, 3))  # each joint's angles at the frame before (the rest pose first)
    for f in range(motion.frames):
        row: list[str] = []
        for b in order:
            r = Z_UP_TO_Y_UP @ quaternion_to_matrix(rotations[f, b]) @ Z_UP_TO_Y_UP.T
            if motion.parents[b] < 0 or slides[b]:  # the whole local translation
                row.append(fmt(Z_UP_TO_Y_UP @ translations[f, b]))
            previous[b] = nearest_euler(euler_zxy(r), previous[b])
            row.append(fmt(previous[b], ANGLE_DECIMALS))
        lines.append(" ".join(row))
    return "\n".join(lines) + "\n"


def write_bvh(motion: Motion, path: Path) -> int:
    """Write ``path``; returns its size (the bytes written: a pipe's size says nothing)."""
    data = bvh_text(motion).encode("utf-8")
    write_atomic(path, data)
    return len(data)
