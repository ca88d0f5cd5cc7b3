"""A 3D run's video on a slope: the ground and its grid lie on the tilted plane, and the
camera is tilted with it and follows it (before, the ground was drawn level at z = 0 and, on a
steep slope, the eye sat under the ground's plane)."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from anim_runs import creature_motion

from legdsl.export.motion import Motion
from legdsl.ir.model import Terrain
from legdsl.lang.errors import Span

ANGLE = math.radians(45)


@pytest.fixture(scope="module")
def on_slope(tmp_path_factory: pytest.TempPathFactory) -> Motion:
    motion = creature_motion("quadruped", tmp_path_factory.mktemp("quadruped") / "run", 0.3)
    slope = Terrain("slope", (("angle", ANGLE),), Span("x.leg", 1, 1, 1, 2))
    lift = np.tan(ANGLE) * motion.positions[..., :1]  # the creature carried up onto the slope
    return dataclasses.replace(
        motion,
        terrain=(slope,),
        positions=motion.positions + np.concatenate([0 * lift, 0 * lift, lift], axis=-1),
        com=motion.com + np.tan(ANGLE) * motion.com[:, :1] * np.array([0.0, 0.0, 1.0]),
    )


def test_the_eye_is_above_the_slope_and_the_picture_below_the_creature_is_ground(
    on_slope: Motion,
) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from legdsl.export.player import OVERLAYS
    from legdsl.export.video_views import GROUND, SKY, PerspectiveView

    fig = plt.figure(figsize=(3.2, 1.8), dpi=100)
    try:
        ax = fig.add_axes((0, 0, 1, 1))
        view = PerspectiveView(on_slope, ax, OVERLAYS, 320, 180)
        snap = on_slope.at(float(on_slope.times[-1]))
        view.update(snap)
        eye = view.camera.eye
        assert eye[2] - math.tan(ANGLE) * eye[0] > 0  # above the ground's plane, not under it
        corners = view.ground.get_paths()[0].vertices
        assert len(corners) >= 3
        fig.canvas.draw()
        image = np.asarray(fig.canvas.buffer_rgba())[..., :3].astype(float) / 255

        def share(color: str) -> float:
            rgb = np.array([int(color[i : i + 2], 16) for i in (1, 3, 5)]) / 255
            return float((np.abs(image[90:] - rgb).max(axis=-1) < 0.02).mean())

        assert share(SKY) < 0.05  # the lower half is the slope's ground, not sky behind it
        assert share(GROUND) > 0.3
    finally:
        plt.close(fig)


def test_the_side_view_follows_a_planar_creature_up_the_slope(
    tmp_path_factory: pytest.TempPathFactory,
) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from legdsl.export.player import OVERLAYS
    from legdsl.export.video_views import SideView

    hopper = creature_motion("hopper", tmp_path_factory.mktemp("hopper") / "run", 0.3)
    slope = Terrain("slope", (("angle", ANGLE),), Span("x.leg", 1, 1, 1, 2))
    far = 20.0  # the same run, 20 m along x and 20 m up the 45 deg slope
    moved = dataclasses.replace(
        hopper,
        terrain=(slope,),
        positions=hopper.positions + np.array([far, 0.0, far]),
        com=hopper.com + np.array([far, 0.0, far]),
    )
    fig = plt.figure(figsize=(3.2, 1.8), dpi=100)
    try:
        view = SideView(moved, fig.add_axes((0, 0, 1, 1)), OVERLAYS, 320 / 180)
        snap = moved.at(float(moved.times[-1]))
        view.update(snap)
        z0, z1 = view.ax.get_ylim()
        assert z0 < snap.com[2] < z1  # the creature is in the frame, 20 m up
    finally:
        plt.close(fig)


def test_the_footprints_lie_on_the_slope_where_the_feet_stood(on_slope: Motion) -> None:
    """Each footprint is drawn as a disc in the slope's plane, centred on the ground under the
    touchdown point (before, a level disc at the touchdown point's height: on a slope one side
    stood out of the ground and the other sank into it)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from legdsl.export.motion import Footprint
    from legdsl.export.video_views import PerspectiveView

    # touchdowns a little into and above the ground, as the contact springs leave them
    x0, x1 = float(on_slope.com[-1, 0]) + 0.3, float(on_slope.com[-1, 0]) - 0.3
    prints = (
        Footprint(0.0, 0, (x0, 0.12, x0 * math.tan(ANGLE) - 0.004)),
        Footprint(0.0, 1, (x1, -0.12, x1 * math.tan(ANGLE) + 0.002)),
    )
    moved = dataclasses.replace(on_slope, footprints=prints)
    fig = plt.figure(figsize=(3.2, 1.8), dpi=100)
    try:
        view = PerspectiveView(moved, fig.add_axes((0, 0, 1, 1)), ("footprints",), 320, 180)
        drawn: list[np.ndarray] = []
        flat = view._flat
        view._flat = lambda polygons: (drawn.extend(polygons), flat(polygons))[1]  # type: ignore[method-assign]
        view.update(moved.at(float(moved.times[-1])))
        discs = [p for p in drawn if len(p) >= 12]  # the ground is 4 corners, shadows 3
        assert len(discs) == len(prints) and len(view.prints.get_paths()) == len(prints)
        radius = 0.06 * view.size
        for disc, fp in zip(discs, prints, strict=True):
            assert np.abs(disc[:, 2] - disc[:, 0] * math.tan(ANGLE)).max() < 1e-9
            centre = disc.mean(axis=0)
            assert np.allclose(centre[:2], [fp.position[0], fp.position[1]], atol=1e-9)
            assert np.allclose(np.linalg.norm(disc - centre, axis=1), radius, atol=1e-9)
    finally:
        plt.close(fig)
