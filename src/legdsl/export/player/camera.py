"""The height the default view's camera follows: fixed, raised only to keep the creature in frame.

The player and the videos look at a target that follows the mass centre horizontally at a
fixed height (``camera_hints``' ``lookHeight`` above the ground's plane), so that hops and
drops show as motion on the screen. A creature that jumps high for its size (the planar
biped's somersault, its legs above a 1.35 m mass centre) would leave the frame at the top:
``camera_lift`` gives, per frame, how much the target rises so that every link's extent stays
inside the default view with a margin. It is zero while the creature stays in frame (the
camera keeps its height), and where it is not it is smoothed in time, rising before it is
needed and coming down after, with no jump between frames. It is not raised past what keeps
the creature's lowest point in frame: a creature taller than the frame (a light link flung
metres above the rest) shows its feet and the ground, not the sky around that link.

The player reads the lift per stored frame (``cameraLift``) and the video's views
interpolate it the same way, so both follow the same height.
"""

from __future__ import annotations

import math

import numpy as np

from legdsl.export.motion import Motion, quaternion_to_matrix, slope_tangent
from legdsl.export.shapes import body_mesh

FIELD_OF_VIEW = 35.0  # degrees, vertical, as in the player
MARGIN = 0.05  # of the frame's height, kept free above the creature
PLANAR_VIEW = (-math.pi / 2, 0.08)  # the player's default (azimuth, elevation), planar
SPATIAL_VIEW = (-math.pi / 3, 0.33)  # and for 3D creatures
EASE = 0.5  # of the creature's natural time sqrt(size / g): how early the camera starts rising
GRAVITY = 9.81  # m/s^2, for the natural time only
# A frame whose creature is more than this many sizes above the camera's fixed height (a
# diverged run's last frames, 1e7 m out) is not followed: eased towards, it raised the camera
# as far at every frame of the window, and a planar run's whole player showed empty sky.
FARTHEST_FOLLOWED = 100.0


def hull_points(motion: Motion) -> list[np.ndarray]:
    """Each body's mesh vertices in its own frame, without repeats."""
    return [np.unique(body_mesh(b).positions.round(9), axis=0) for b in motion.bodies]


# Frames whose vertices are held at once: all of a run's (with the arrays made from them)
# took some 40 KB a frame, four times the memory of the run itself (3.7 GB for a 30 min
# quadruped run), for a maximum and a minimum per frame
FRAMES_AT_ONCE = 1024


def world_points(motion: Motion, frames: slice = slice(None)) -> np.ndarray:
    """(F, N, 3): every body's mesh vertices in world coordinates at every frame (of ``frames``)."""
    out = []
    for b, local in enumerate(hull_points(motion)):
        rot = np.array([quaternion_to_matrix(q) for q in motion.quaternions[frames, b]])
        out.append(np.einsum("fij,nj->fni", rot, local) + motion.positions[frames, b, None, :])
    return np.concatenate(out, axis=1)


def camera_axes(
    azimuth: float, elevation: float, tilt: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The eye's offset from the target (unit), and the camera's up and forward directions,
    as ``video_views._Camera.aim`` and the player's ``placeCamera`` place them."""
    c = math.cos(elevation)
    offset = np.array([c * math.cos(azimuth), c * math.sin(azimuth), math.sin(elevation)])
    if tilt:
        a = math.atan(tilt)
        x, z = offset[0], offset[2]
        offset[0], offset[2] = x * math.cos(a) - z * math.sin(a), x * math.sin(a) + z * math.cos(a)
    forward = -offset
    right = np.cross(forward, [0.0, 0.0, 1.0])
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    return offset, up, forward


def lift_range(motion: Motion, look_height: float, distance: float) -> np.ndarray:
    """(F, 2): at each frame, how far the target must rise for the creature's highest point
    to be a margin under the frame's top (negative: that far to spare), and how far it may
    rise with its lowest point still a margin over the frame's bottom.

    Planar creatures: the video's side view, an orthographic frame ``2 d tan(fov / 2)`` high
    centred on the target. 3D creatures: the perspective default view; raising the target by
    h raises the eye by h, so a point at camera coordinates (y up, z depth) is under the top
    when ``y - h up_z <= T (z - h forward_z)`` and over the bottom when ``y - h up_z >=
    -T (z - h forward_z)``, T the tangent of the allowed half-angle.
    """
    starts = range(0, motion.frames, FRAMES_AT_ONCE)
    parts = [_lift_range(motion, look_height, distance, slice(a, a + FRAMES_AT_ONCE))
             for a in starts]  # fmt: skip
    return np.concatenate(parts) if parts else np.zeros((0, 2))


def _lift_range(motion: Motion, look_height: float, distance: float, frames: slice) -> np.ndarray:
    """``lift_range`` of ``frames``."""
    points = world_points(motion, frames)
    tilt = slope_tangent(motion.terrain)
    com = motion.com[frames]
    base = look_height + tilt * com[:, 0]  # the target's height without a lift
    half = math.tan(math.radians(FIELD_OF_VIEW / 2))
    if motion.planar:
        room = 2 * distance * half * (0.5 - MARGIN)
        z = points[..., 2]
        return np.column_stack([z.max(axis=1) - (base + room), z.min(axis=1) - (base - room)])
    azimuth, elevation = SPATIAL_VIEW
    offset, up, forward = camera_axes(azimuth, elevation, tilt)
    target = np.column_stack([com[:, 0], com[:, 1], base])
    rel = points - (target + distance * offset)[:, None, :]
    y, z = rel @ up, rel @ forward
    t = half * (1 - 2 * MARGIN)
    need = (y - t * z) / (up[2] - t * forward[2])
    may = (y + t * z) / (up[2] + t * forward[2])
    ahead = z > 0  # points behind the eye are not framed anyway
    need, may = np.where(ahead, need, -np.inf), np.where(ahead, may, np.inf)
    return np.column_stack([need.max(axis=1), may.min(axis=1)])


def camera_lift(motion: Motion, look_height: float, distance: float, size: float) -> np.ndarray:
    """(F,) m: how far the camera's target rises above its fixed height at each frame.

    The least smooth curve over the needed lift: its running maximum over a window of
    ``EASE`` natural times either side, averaged over the same window with a Hann
    weighting, is at least the need at every frame (every sample averaged is a maximum over
    a window that holds that frame) and changes smoothly; where the need is never positive
    within the window, the lift is exactly zero. The need goes no further than what keeps the
    creature's lowest point in the frame: one taller than the frame shows its feet and the
    ground, its top cut off.
    """
    need, may = lift_range(motion, look_height, distance).T
    # a creature taller than the frame (a link flung high above the rest) keeps its lowest
    # point in view, and the ground under it: raised to its top, the frame showed only sky
    need = np.clip(need, 0.0, np.maximum(may, 0.0))
    need = np.where(need <= FARTHEST_FOLLOWED * size, need, 0.0)
    if not need.any() or motion.frames < 2:
        return need
    step = float(np.median(np.diff(motion.times)))
    n = max(1, round(EASE * math.sqrt(size / GRAVITY) / step))
    padded = np.pad(need, n, mode="edge")
    peak = np.lib.stride_tricks.sliding_window_view(padded, 2 * n + 1).max(axis=1)
    weights = np.hanning(2 * n + 3)[1:-1]  # no zero taps
    weights /= weights.sum()
    return np.asarray(np.convolve(np.pad(peak, n, mode="edge"), weights, mode="valid"))
