"""The HTML run player: one self-contained file that plays a recorded run.

``player_html(motion)`` fills ``template.html`` with three things, all inline:

* the run as JSON (``legdsl-data``): per body its mesh (from
  ``legdsl.export.formats.formats.shapes``) and colour, and per frame every body's position and
  quaternion, contact positions, ground forces, mass centre, speeds and
  controller state, as little-endian float32 (int16 for the state) arrays in
  base64; the footprints, the terrain and a few camera hints;
* three.js (the vendored minified module build, ``legdsl/export/player/vendor/three``),
  kept as text and imported from a blob URL, so the page needs no network
  and no server;
* ``player.js``, which draws and plays it.
"""

from __future__ import annotations

import base64
import json
import math
import re
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np

from legdsl import __version__
from legdsl.export.motion import Motion, slope_tangent
from legdsl.export.shapes import body_mesh, hex_rgb
from legdsl.files import write_atomic

THREE_VERSION = "0.170.0"
OVERLAYS = ("state", "speed", "forces", "footprints", "com")
FIELD_OF_VIEW = 35.0  # degrees, vertical; player.js uses the same


def _b64(array: np.ndarray, dtype: str = "<f4") -> str:
    return base64.b64encode(np.ascontiguousarray(array, dtype=dtype).tobytes()).decode("ascii")


def _resource(*parts: str) -> str:
    return resources.files("legdsl").joinpath(*parts).read_text(encoding="utf-8")


def three_module() -> str:
    return _resource("export", "player", "vendor", "three", "three.module.min.js")


def world_vertices(motion: Motion, frame: int = 0) -> np.ndarray:
    """Every mesh vertex of the creature in world coordinates at ``frame``."""
    from legdsl.export.motion import quaternion_to_matrix

    points = []
    for b, body in enumerate(motion.bodies):
        rot = quaternion_to_matrix(motion.quaternions[frame, b])
        points.append(body_mesh(body).positions @ rot.T + motion.positions[frame, b])
    return np.concatenate(points)


SMALLEST_SIZE = 1e-5  # m: a creature's size is never taken as less (a mesh of one point)


def grid_step(size: float) -> float:
    """The ground grid's spacing: 0.25 m for creatures from 15 cm to 1.5 m, 1 m up to 15 m,
    else the power of ten at or below the size (a 7 cm pogo's 1 cm, a 0.7 mm mite's 0.1 mm,
    a 24 m giant's 10 m), so a few cells always span the creature."""
    if 0.15 <= size < 1.5:
        return 0.25
    if 1.5 <= size < 15.0:
        return 1.0
    return float(10.0 ** math.floor(math.log10(size)))


def camera_hints(motion: Motion) -> dict[str, float]:
    """The creature's size, and a camera distance and look-at height that frame it."""
    points = world_vertices(motion)
    # a 5 cm floor, now only for creatures under 15 cm, framed a 0.7 mm mite as a speck
    extent = float(np.ptp(points, axis=0).max())
    size = max(extent, SMALLEST_SIZE) if extent < 0.15 else max(extent, 0.05)
    slope = slope_tangent(motion.terrain)
    return {
        "size": size,
        "distance": 0.9 * size / math.tan(math.radians(FIELD_OF_VIEW / 2)),
        # above a slope's plane, which the camera follows (above z = 0 it left a climb's frame)
        "lookHeight": float(0.8 * np.median(motion.com[:, 2] - slope * motion.com[:, 0])),
    }


def ground_extent(motion: Motion, size: float) -> tuple[float, float, float, float]:
    """The ground quad: the run's area and ten sizes, and the eight metres around a creature
    of 40 cm or more, twenty sizes around a smaller one: past the fog's far end (4.5 camera
    distances, 13 sizes, from the eye) nothing shows, and a 16 m quad seen from half a
    millimetre lost the depth test's precision (drawn over a 0.16 mm creature, no grid)."""
    margin = 10 * size + min(8.0, 20 * size)
    x0, x1 = float(motion.com[:, 0].min()) - margin, float(motion.com[:, 0].max()) + margin
    y0, y1 = float(motion.com[:, 1].min()) - margin, float(motion.com[:, 1].max()) + margin
    return x0, x1, y0, y1


def player_data(motion: Motion, overlays: tuple[str, ...] = OVERLAYS) -> dict[str, Any]:
    from legdsl.export.player.camera import camera_lift

    hints = camera_hints(motion)
    lift = camera_lift(motion, hints["lookHeight"], hints["distance"], hints["size"])
    poses = np.concatenate([motion.positions, motion.quaternions], axis=2)
    bodies = []
    for body in motion.bodies:
        mesh = body_mesh(body)
        r, g, b = hex_rgb(body.color)
        bodies.append(
            {
                "name": body.name,
                "color": f"#{round(r * 255):02x}{round(g * 255):02x}{round(b * 255):02x}",
                "mesh": {
                    "positions": _b64(mesh.positions),
                    "normals": _b64(mesh.normals),
                    "indices": _b64(mesh.indices, "<u4"),
                },
            }
        )
    return {
        "creature": motion.creature,
        "planar": motion.planar,
        "status": motion.status,
        "message": motion.message,
        "bodies": bodies,
        "contacts": list(motion.contact_names),
        "stateNames": list(motion.state_names),
        "times": _b64(motion.times),
        "poses": _b64(poses),
        "contactPositions": _b64(motion.contact_positions),
        "forces": _b64(motion.forces),
        "com": _b64(motion.com),
        "speed": _b64(motion.speed),
        "speedCommand": _b64(motion.speed_command),
        "state": _b64(motion.state, "<i2"),
        "footprints": footprint_rows(motion, hints["size"]),
        "ground": {
            "terrain": [{"kind": t.kind, **dict(t.params)} for t in motion.terrain],
            "extent": ground_extent(motion, hints["size"]),
            "grid": grid_step(hints["size"]),
        },
        "paths": [
            {
                "name": name,
                "points": _b64(points),
                "nearest": _b64(motion.path_nearest[k]) if motion.path_nearest else None,
                "lateral": _b64(motion.path_lateral[k]) if motion.path_lateral else None,
                # when it was followed: [[from, to], ...] s, or None for the whole run
                "followed": _spans(motion, k),
            }
            for k, (name, points) in enumerate(zip(motion.path_names, motion.paths, strict=True))
        ],
        "weight": motion.weight,
        # per frame, how far the camera's target rises to keep the creature in frame
        # (player/camera.py); null when it never does
        "cameraLift": _b64(lift) if lift.any() else None,
        "overlays": [o for o in overlays if o in OVERLAYS],
        **hints,
    }


def footprint_rows(motion: Motion, size: float) -> list[list[float]]:
    """[t, contact, x, y, z] per footprint: lengths to the BVH's decimals (1e-6 of the
    creature's size), times to the nanosecond. Five decimals put a 53 um creature's footprints
    up to 5 um, a tenth of it, off the touchdown point."""
    from legdsl.export.bvh import length_decimals

    decimals = length_decimals(size)
    return [
        [round(fp.t, 9), fp.contact, *(round(x, decimals) for x in fp.position)]
        for fp in motion.footprints
    ]


def _spans(motion: Motion, k: int) -> list[list[float]] | None:
    """The spans path ``k`` was followed in, as JSON; None when the whole run followed it."""
    spans = motion.path_spans[k] if motion.path_spans else None
    return None if spans is None else [list(s) for s in spans]


def _inline_safe(text: str, what: str) -> str:
    """Text that may sit inside a <script> element as it is."""
    if re.search(r"</script|<!--|<script", text, re.IGNORECASE):
        raise ValueError(f"{what} contains a sequence that would end its <script> element")
    return text


def player_html(motion: Motion, overlays: tuple[str, ...] = OVERLAYS) -> str:
    data = json.dumps(player_data(motion, overlays), separators=(",", ":"), allow_nan=False)
    parts = {
        "TITLE": f"{motion.creature}: legdsl run player",
        "VERSION": __version__,
        "THREE_VERSION": THREE_VERSION,
        "DATA": data.replace("</", "<\\/").replace("<!--", "<\\!--"),
        "THREE": _inline_safe(three_module(), "three.js"),
        "PLAYER": _inline_safe(_resource("export", "player", "player.js"), "player.js"),
    }
    template = _resource("export", "player", "template.html")
    return re.sub(r"__([A-Z_]+)__", lambda m: parts[m.group(1)], template)


def write_player(motion: Motion, path: Path, overlays: tuple[str, ...] = OVERLAYS) -> int:
    """Write the player to ``path`` (atomically); returns its size in bytes."""
    text = player_html(motion, overlays).encode("utf-8")
    write_atomic(path, text)
    return len(text)
