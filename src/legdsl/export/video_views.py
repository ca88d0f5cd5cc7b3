"""The pictures of a video's frames, those of the HTML player, drawn with matplotlib:

* ``SideView``, for planar creatures: a side view of the x-z plane, every link drawn as its
  outline (``legdsl.export.shapes.side_outline``) in its colour, the ground and terrain in
  section;
* ``PerspectiveView``, for 3D creatures: a perspective view from the player's default
  camera; the links' triangle meshes are projected, shaded by a fixed light, sorted back to
  front with the terrain's faces (``legdsl.export.video_order``) and drawn with their shadows
  on the ground and the terrain's tops (``legdsl.export.video_shadows``).

The camera follows the mass centre horizontally at a fixed height, raised smoothly only where
the creature would leave the frame at the top (``legdsl.export.player.camera``, the player's
rule). The overlays are those
of the player: controller state, commanded and actual speed, ground-force arrows,
footprints and the mass-centre trail. ``legdsl.export.video`` turns the frames into a file.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from legdsl.export.motion import Footprint, Motion, Snapshot, slope_tangent, terrain_height
from legdsl.export.player import camera_hints, grid_step
from legdsl.export.player.camera import camera_lift
from legdsl.export.shapes import Mesh, body_mesh, hex_rgb, side_outline
from legdsl.export.video_caption import CAPTION_SIZE, caption_chars, wrapped
from legdsl.export.video_order import Face, Wall, back_to_front, seen_faces
from legdsl.export.video_shadows import ground_shadows

SKY = "#eef0f3"
GROUND = "#d9d9d6"
GROUND_EDGE = "#9c9c96"
TERRAIN = "#c2c2bc"
SHADOW = "#a9a9a4"
FORCE = "#d2401e"
TRAIL = "#c0208a"
FOOTPRINT_COLORS = ("#1f5fbf", "#2a9d4b", "#b8860b", "#8e44ad", "#16a085", "#c0392b")
FIELD_OF_VIEW = 35.0  # degrees, vertical, as in the player


def _shade(color: tuple[float, float, float], factor: float) -> tuple[float, float, float]:
    r, g, b = color
    return (min(1.0, r * factor), min(1.0, g * factor), min(1.0, b * factor))


# ---------------------------------------------------------------- the two views


class View:
    """Artists of one view; ``update`` moves them to a snapshot."""

    def __init__(self, motion: Motion, ax: Any, overlays: tuple[str, ...]):
        self.motion = motion
        self.ax = ax
        self.overlays = overlays
        hints = camera_hints(motion)
        self.size = hints["size"]
        self.tilt = slope_tangent(motion.terrain)
        self.look_height = hints["lookHeight"]  # above the slope's plane, which the camera follows
        self.distance = hints["distance"]
        # per frame, how far the camera's target rises to keep the whole creature in frame
        self.lift = camera_lift(motion, self.look_height, self.distance, self.size)
        self.weight = motion.weight
        self.text = ax.text(
            0.012, 0.975, "", transform=ax.transAxes, va="top", ha="left", fontsize=CAPTION_SIZE,
            family="DejaVu Sans", zorder=100,
            bbox={"boxstyle": "round,pad=0.4", "fc": "white", "ec": "#cccccc", "alpha": 0.85},
        )  # fmt: skip

    def plane_z(self, x: Any) -> Any:
        """The height of the slope's plane at ``x`` (0 without a slope: steps and boxes are
        drawn as blocks on the floor)."""
        return self.tilt * x

    def target_height(self, snap: Snapshot) -> float:
        """The height the camera looks at: fixed above the ground's plane, raised by the lift
        (interpolated between frames, as the player does)."""
        cx = float(snap.com[0])
        raised = float(np.interp(snap.t, self.motion.times, self.lift)) if self.lift.any() else 0.0
        return float(self.look_height + self.plane_z(cx) + raised)

    def caption(self, snap: Snapshot) -> str:
        m = self.motion
        lines = [f"{m.creature}   t = {snap.t:6.3f} s"]
        if m.status != "ok":  # wrapped to the frame (a long message ran off its right edge)
            lines.extend(wrapped(f"{m.status}: {m.message}", caption_chars(self.ax)))
        if "state" in self.overlays:
            lines.append(f"state: {snap.state or '(no controller)'}")
        if "speed" in self.overlays:
            command = (
                f"{snap.speed_command:.2f} m/s" if math.isfinite(snap.speed_command) else "none"
            )
            lines.append(f"speed: {snap.speed:.2f} m/s   command: {command}")
        return "\n".join(lines)

    def update(self, snap: Snapshot) -> None:
        self.text.set_text(self.caption(snap))


class SideView(View):
    """A planar creature seen from -y: x to the right, z up."""

    def __init__(self, motion: Motion, ax: Any, overlays: tuple[str, ...], aspect: float):
        from matplotlib.collections import LineCollection
        from matplotlib.patches import Polygon

        super().__init__(motion, ax, overlays)
        ax.set_facecolor(SKY)
        self.height = 2 * self.distance * math.tan(math.radians(FIELD_OF_VIEW / 2))
        self.width = self.height * aspect
        self.outlines = [side_outline(b) for b in motion.bodies]
        self.links = []
        for body in motion.bodies:
            color = hex_rgb(body.color)
            patch = Polygon(
                np.zeros((3, 2)), closed=True, fc=color, ec=_shade(color, 0.6), lw=1.0, zorder=10
            )
            ax.add_patch(patch)
            self.links.append(patch)
        self.ground = Polygon(np.zeros((3, 2)), closed=True, fc=GROUND, ec=GROUND_EDGE, lw=1.2)
        ax.add_patch(self.ground)
        self.ticks = LineCollection([], colors=GROUND_EDGE, linewidths=0.8, zorder=1)
        ax.add_collection(self.ticks)
        self.trail = ax.plot([], [], color=TRAIL, lw=1.5, zorder=30)[0]
        self.com_marker = ax.plot([], [], "o", color=TRAIL, ms=5, zorder=31)[0]
        self.prints = ax.scatter([], [], s=160, marker="_", linewidths=5, zorder=5)
        self.arrows = [
            ax.annotate(
                "",
                xy=(0, 0),
                xytext=(0, 0),
                zorder=40,
                # drawn even when an end is outside the axes (update clips it to the frame)
                annotation_clip=False,
                arrowprops={"arrowstyle": "-|>", "color": FORCE, "lw": 2, "mutation_scale": 14},
            )  # fmt: skip
            for _ in motion.contact_names
        ]

    def _profile(self, x0: float, x1: float) -> np.ndarray:
        """The ground's section under [x0, x1] as points (x, z), with vertical edges at steps."""
        terrain = self.motion.terrain
        xs = {x0, x1}
        for t in terrain:
            for key in ("x", "x0", "x1"):
                if key in dict(t.params) and x0 < t.get(key) < x1:
                    xs |= {t.get(key) - 1e-9, t.get(key) + 1e-9}
        xs_sorted = sorted(xs)
        return np.array([(x, terrain_height(terrain, x)) for x in xs_sorted])

    def update(self, snap: Snapshot) -> None:
        super().update(snap)
        cx = float(snap.com[0])
        x0, x1 = cx - self.width / 2, cx + self.width / 2
        z0 = self.target_height(snap) - self.height / 2
        self.ax.set_xlim(x0, x1)
        self.ax.set_ylim(z0, z0 + self.height)
        top = self._profile(x0 - 1, x1 + 1)
        bottom = z0 - 1
        self.ground.set_xy(np.vstack([top, [(x1 + 1, bottom), (x0 - 1, bottom)]]))
        step = grid_step(self.size)
        marks = np.arange(math.floor(x0 / step) * step, x1 + step, step)
        depth = 0.02 * self.height
        self.ticks.set_segments(
            [
                [
                    (x, terrain_height(self.motion.terrain, x)),
                    (x, terrain_height(self.motion.terrain, x) - depth),
                ]
                for x in marks
            ]
        )
        for patch, outline, p, r in zip(
            self.links, self.outlines, snap.positions, snap.rotations, strict=True
        ):
            rot = np.array([[r[0, 0], r[0, 2]], [r[2, 0], r[2, 2]]])
            patch.set_xy(outline @ rot.T + np.array([p[0], p[2]]))
        m = self.motion
        show_trail = "com" in self.overlays
        self.trail.set_data(m.com[: snap.frame + 1, 0], m.com[: snap.frame + 1, 2])
        self.trail.set_visible(show_trail)
        self.com_marker.set_data([snap.com[0]], [snap.com[2]])
        self.com_marker.set_visible(show_trail)
        prints = (
            [fp for fp in m.footprints if fp.t <= snap.t + 1e-9]
            if "footprints" in self.overlays
            else []
        )
        self.prints.set_offsets(
            np.array([(fp.position[0], fp.position[2]) for fp in prints]).reshape(-1, 2)
        )
        self.prints.set_color(
            [FOOTPRINT_COLORS[fp.contact % len(FOOTPRINT_COLORS)] for fp in prints]
        )
        per_newton = 0.6 * self.size / self.weight
        margin = 0.02 * self.height
        box = (x0 + margin, z0 + margin, x1 - margin, z0 + self.height - margin)
        for arrow, p, f in zip(self.arrows, snap.contact_positions, snap.forces, strict=True):
            length = math.hypot(f[0], f[2]) * per_newton
            start = (float(p[0]), float(p[2]))
            end = clip_segment(start, (p[0] + f[0] * per_newton, p[2] + f[2] * per_newton), box)
            visible = "forces" in self.overlays and length > 1e-3 * self.size and end is not None
            arrow.set_visible(visible)
            if visible and end is not None:
                arrow.xy = end  # the head, at the frame's edge when the arrow is longer
                arrow.set_position(start)


def clip_segment(
    start: tuple[float, float], end: tuple[float, float], box: tuple[float, float, float, float]
) -> tuple[float, float] | None:
    """The end of the part of start->end inside ``box`` (x0, y0, x1, y1) that begins at start.

    None when ``start`` itself is outside the box (the arrow's foot is out of view).
    """
    x0, y0, x1, y1 = box
    if not (x0 <= start[0] <= x1 and y0 <= start[1] <= y1):
        return None
    t = 1.0
    for k, (lo, hi) in enumerate(((x0, x1), (y0, y1))):
        d = end[k] - start[k]
        if d > 0 and start[k] + d > hi:
            t = min(t, (hi - start[k]) / d)
        elif d < 0 and start[k] + d < lo:
            t = min(t, (lo - start[k]) / d)
    return (start[0] + t * (end[0] - start[0]), start[1] + t * (end[1] - start[1]))


class _Camera:
    """A perspective camera looking at a target from (azimuth, elevation, distance), z up."""

    def __init__(self, azimuth: float, elevation: float, distance: float, width: int, height: int):
        self.azimuth, self.elevation, self.distance = azimuth, elevation, distance
        self.focal = (height / 2) / math.tan(math.radians(FIELD_OF_VIEW / 2))
        self.cx, self.cy = width / 2, height / 2
        self.near = min(0.05, distance / 20)  # 5 cm would cut a mite, seen from 2 mm

    def aim(self, target: np.ndarray, tilt: float = 0.0) -> None:
        """Look at ``target``; on a slope of ``tilt`` (tan of its angle) the eye is tilted with
        the ground, so that it sees the slope as it sees level ground (not from under it)."""
        c = math.cos(self.elevation)
        offset = self.distance * np.array(
            [c * math.cos(self.azimuth), c * math.sin(self.azimuth), math.sin(self.elevation)]
        )
        if tilt:
            a = math.atan(tilt)
            x, z = offset[0], offset[2]
            offset[0], offset[2] = (
                x * math.cos(a) - z * math.sin(a),
                x * math.sin(a) + z * math.cos(a),
            )
        self.eye = target + offset
        forward = -offset / np.linalg.norm(offset)
        right = np.cross(forward, [0.0, 0.0, 1.0])
        right /= np.linalg.norm(right)
        up = np.cross(right, forward)
        self.rot = np.array([right, up, forward])  # world -> camera (x right, y up, z depth)

    def to_camera(self, points: np.ndarray) -> np.ndarray:
        return np.asarray((points - self.eye) @ self.rot.T)

    def to_pixels(self, cam: np.ndarray) -> np.ndarray:
        """Camera coordinates (depth > 0) to pixels, y up (matplotlib's)."""
        return np.column_stack(
            [
                self.cx + self.focal * cam[..., 0] / cam[..., 2],
                self.cy + self.focal * cam[..., 1] / cam[..., 2],
            ]
        )

    def clip(self, cam: np.ndarray) -> np.ndarray:
        """A convex polygon in camera coordinates cut to the part in front of the near plane."""
        out = []
        n = len(cam)
        for i in range(n):
            a, b = cam[i], cam[(i + 1) % n]
            a_in, b_in = a[2] >= self.near, b[2] >= self.near
            if a_in:
                out.append(a)
            if a_in != b_in:
                s = (self.near - a[2]) / (b[2] - a[2])
                out.append(a + s * (b - a))
        return np.array(out).reshape(-1, 3)


class PerspectiveView(View):
    """A 3D creature from the player's default camera: shaded meshes, shadows, ground grid."""

    LIGHT = np.array([4.0, -3.0, 8.0]) / math.sqrt(89.0)  # towards the light, as in the player

    def __init__(self, motion: Motion, ax: Any, overlays: tuple[str, ...], width: int, height: int):
        from matplotlib.collections import LineCollection, PolyCollection

        super().__init__(motion, ax, overlays)
        ax.set_facecolor(SKY)
        ax.set_xlim(0, width)
        ax.set_ylim(0, height)
        self.camera = _Camera(-math.pi / 3, 0.33, self.distance, width, height)
        self.meshes: list[Mesh] = [body_mesh(b, box_divisions=4) for b in motion.bodies]
        self.colors = [np.array(hex_rgb(b.color)) for b in motion.bodies]
        self.ground = PolyCollection([], facecolors=GROUND, edgecolors="none", zorder=0)
        self.grid = LineCollection([], colors="#b2b2ac", linewidths=0.7, zorder=1)
        self.shadows = PolyCollection(
            [], facecolors=SHADOW, edgecolors=SHADOW, linewidths=0.3, zorder=2
        )
        self.prints = PolyCollection([], edgecolors="none", alpha=0.8, zorder=3)
        self.trail = LineCollection([], colors=TRAIL, linewidths=1.6, zorder=50)
        # Edges in the face colour, wide enough to close the antialiasing seams between triangles.
        self.solids = PolyCollection([], linewidths=0.9, zorder=10)
        self.forces = LineCollection([], colors=FORCE, linewidths=2.2, zorder=60)
        for artist in (
            self.ground,
            self.grid,
            self.shadows,
            self.prints,
            self.solids,
            self.trail,
            self.forces,
        ):
            ax.add_collection(artist)
        self.com_marker = ax.plot([], [], "o", color=TRAIL, ms=5, zorder=51)[0]

    def _flat(self, polygons: list[np.ndarray]) -> list[np.ndarray]:
        """World polygons to clipped pixel polygons (dropping those wholly behind the camera)."""
        out = []
        for poly in polygons:
            cam = self.camera.clip(self.camera.to_camera(poly))
            if len(cam) >= 3:
                out.append(self.camera.to_pixels(cam))
        return out

    def _segments(self, segments: list[tuple[np.ndarray, np.ndarray]]) -> list[np.ndarray]:
        out = []
        for a, b in segments:
            ca, cb = self.camera.to_camera(np.array([a, b]))
            near = self.camera.near
            if ca[2] < near and cb[2] < near:
                continue
            if ca[2] < near:
                ca = ca + (near - ca[2]) / (cb[2] - ca[2]) * (cb - ca)
            elif cb[2] < near:
                cb = cb + (near - cb[2]) / (ca[2] - cb[2]) * (ca - cb)
            out.append(self.camera.to_pixels(np.array([ca, cb])))
        return out

    def update(self, snap: Snapshot) -> None:
        super().update(snap)
        cam = self.camera
        cx, cy = float(snap.com[0]), float(snap.com[1])
        target = np.array([cx, cy, self.target_height(snap)])
        cam.aim(target, self.tilt)
        m = self.motion
        reach = 4.0 * self.distance
        ground = [
            np.array(
                [
                    (cx - reach, cy - reach, self.plane_z(cx - reach)),
                    (cx + reach, cy - reach, self.plane_z(cx + reach)),
                    (cx + reach, cy + reach, self.plane_z(cx + reach)),
                    (cx - reach, cy + reach, self.plane_z(cx - reach)),
                ],
                dtype=float,
            )
        ]
        self.ground.set_verts(self._flat(ground))
        step = grid_step(self.size)
        span = 2.0 * self.distance
        lines = []
        for k in (
            np.arange(math.floor((cx - span) / step), math.ceil((cx + span) / step) + 1) * step
        ):
            z = self.plane_z(k)
            lines.append((np.array([k, cy - span, z]), np.array([k, cy + span, z])))
        for k in (
            np.arange(math.floor((cy - span) / step), math.ceil((cy + span) / step) + 1) * step
        ):
            ends = (self.plane_z(cx - span), self.plane_z(cx + span))
            lines.append((np.array([cx - span, k, ends[0]]), np.array([cx + span, k, ends[1]])))
        self.grid.set_segments(self._segments(lines))

        # The creature, the terrain blocks' faces and the shadows on their tops, back to front.
        def depth(poly: np.ndarray) -> float:
            return float(cam.to_camera(poly.mean(axis=0, keepdims=True))[0, 2])

        faces: list[Face] = []
        shadows: list[np.ndarray] = []  # on the floor or the slope
        raised: dict[int, list[Face]] = {}  # on the top of the terrain's step or box [index]
        for mesh, color, p, r in zip(
            self.meshes, self.colors, snap.positions, snap.rotations, strict=True
        ):
            world = mesh.positions @ r.T + p
            normals = mesh.normals @ r.T
            tris = world[mesh.indices]
            tri_normals = normals[mesh.indices].mean(axis=1)
            # Facing the camera: the normal points back along the line of sight (perspective).
            facing = np.einsum("ij,ij->i", tri_normals, tris.mean(axis=1) - cam.eye) < 0
            light = np.clip(tri_normals @ self.LIGHT, 0.0, 1.0)
            for tri, lit, front in zip(tris, light, facing, strict=True):
                if front:
                    faces.append((depth(tri), tri, _shade(tuple(color), 0.55 + 0.6 * lit)))
            on_floor, on_tops = ground_shadows(m.terrain, tris, self.LIGHT)
            shadows.extend(on_floor)
            for shadow, block in on_tops:
                raised.setdefault(block, []).append((depth(shadow), shadow, hex_rgb(SHADOW)))
        walls: list[Wall] = []
        for block, box in _terrain_boxes(m, cx, cy, reach):
            for k in seen_faces(box, cam.eye):  # a top seen from below hides its shadows
                on_it = raised.get(block, []) if k == 0 else []
                walls.append(((depth(box[k]), box[k], hex_rgb(TERRAIN)), on_it))
        faces = back_to_front(faces, walls, cam.eye, depth, self.size)
        polys = [f[1] for f in faces]
        flat = []
        colors = []
        for poly, (_, _, color) in zip(polys, faces, strict=True):
            cam_poly = cam.clip(cam.to_camera(poly))
            if len(cam_poly) >= 3:
                flat.append(cam.to_pixels(cam_poly))
                colors.append(color)
        self.solids.set_verts(flat)
        self.solids.set_facecolor(colors)
        self.solids.set_edgecolor(colors)
        self.shadows.set_verts(self._flat(shadows))

        prints = (
            [fp for fp in m.footprints if fp.t <= snap.t + 1e-9]
            if "footprints" in self.overlays
            else []
        )
        radius = 0.06 * self.size
        self.prints.set_verts(self._flat([footprint_disc(m, fp, radius) for fp in prints]))
        self.prints.set_facecolor(
            [FOOTPRINT_COLORS[fp.contact % len(FOOTPRINT_COLORS)] for fp in prints]
        )

        show_trail = "com" in self.overlays
        trail = m.com[: snap.frame + 1]
        self.trail.set_segments(
            self._segments(list(zip(trail[:-1], trail[1:], strict=True))) if show_trail else []
        )
        marker = cam.to_pixels(cam.to_camera(snap.com[None, :]))[0]
        self.com_marker.set_data([marker[0]], [marker[1]])
        self.com_marker.set_visible(show_trail)

        per_newton = 0.6 * self.size / self.weight
        arrows = []
        if "forces" in self.overlays:
            for p, f in zip(snap.contact_positions, snap.forces, strict=True):
                if np.linalg.norm(f) * per_newton > 1e-3 * self.size:
                    arrows += _arrow_segments(p, p + f * per_newton)
        self.forces.set_segments(self._segments(arrows))


def footprint_disc(m: Motion, fp: Footprint, radius: float, n: int = 16) -> np.ndarray:
    """A footprint as an (n, 3) polygon lying on the ground where the foot stood: centred on
    the ground under the touchdown point, on a slope in its tilted plane (drawn level, a disc
    stood out of the slope on one side and sank into it on the other)."""
    x, y = fp.position[0], fp.position[1]
    a = math.atan(slope_tangent(m.terrain))
    turn = np.linspace(0, 2 * np.pi, n, endpoint=False)
    along = np.array([math.cos(a), 0.0, math.sin(a)])  # the ground's x direction, up the slope
    rim = radius * (np.cos(turn)[:, None] * along + np.sin(turn)[:, None] * [0.0, 1.0, 0.0])
    return np.array([x, y, terrain_height(m.terrain, x, y)]) + rim


def _arrow_segments(a: np.ndarray, b: np.ndarray) -> list[tuple[np.ndarray, np.ndarray]]:
    """A shaft and a two-stroke head, in world space (the head lies in a vertical plane)."""
    d = b - a
    length = float(np.linalg.norm(d))
    u = d / length
    side = np.cross(u, [0.0, 0.0, 1.0])
    if np.linalg.norm(side) < 1e-6:
        side = np.array([1.0, 0.0, 0.0])
    side /= np.linalg.norm(side)
    head = 0.25 * length
    back = b - head * u
    return [(a, b), (b, back + 0.4 * head * side), (b, back - 0.4 * head * side)]


def _terrain_boxes(
    m: Motion, cx: float, cy: float, reach: float
) -> list[tuple[int, list[np.ndarray]]]:
    """The terrain's steps and boxes within ``reach``: each one's index in the terrain and its
    faces above the floor (four corners each, the top first)."""
    boxes = []
    for index, t in enumerate(m.terrain):
        if t.kind == "step":
            x0, x1, y0, y1 = t.get("x"), cx + reach, cy - reach, cy + reach
        elif t.kind == "box":
            x0, x1 = t.get("x0"), t.get("x1")
            y0, y1 = max(t.get("y0"), cy - reach), min(t.get("y1"), cy + reach)
        else:
            continue
        if x1 <= x0:
            continue
        h = t.get("height")
        c = np.array([[x, y, z] for z in (0, h) for y in (y0, y1) for x in (x0, x1)], dtype=float)
        quads = [(4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
        boxes.append((index, [c[list(q)] for q in quads]))
    return boxes
