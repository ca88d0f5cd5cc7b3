"""A 3D video's shadows with terrain: the links cast them on the floor, on the tops of steps
and boxes, and on a slope (the video drew none once the ground had any terrain, though the
player does)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from anim_runs import creature_motion

from legdsl.export.motion import Motion
from legdsl.ir.model import Terrain
from legdsl.lang.errors import Span

HEIGHT = 0.05  # m: the box the creature stands on in the second case


def terrain(kind: str, **params: float) -> Terrain:
    return Terrain(kind, tuple(params.items()), Span("x.leg", 1, 1, 1, 2))


@pytest.fixture(scope="module")
def quadruped(tmp_path_factory: pytest.TempPathFactory) -> Motion:
    return creature_motion("quadruped", tmp_path_factory.mktemp("quadruped") / "run", 0.3)


def drawn(motion: Motion) -> tuple[int, int]:
    """(shadow polygons on the floor, shadow-coloured faces among the solids) of the last frame."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from legdsl.export.shapes import hex_rgb
    from legdsl.export.video_views import SHADOW, PerspectiveView

    fig = plt.figure(figsize=(3.2, 1.8), dpi=100)
    try:
        view = PerspectiveView(motion, fig.add_axes((0, 0, 1, 1)), (), 320, 180)
        view.update(motion.at(float(motion.times[-1])))
        colours = view.solids.get_facecolor()[:, :3]
        on_tops = int(np.all(np.abs(colours - hex_rgb(SHADOW)) < 1e-6, axis=1).sum())
        return len(view.shadows.get_paths()), on_tops
    finally:
        plt.close(fig)


def test_a_box_away_from_the_creature_leaves_its_shadow_on_the_floor(quadruped: Motion) -> None:
    far = float(quadruped.positions[..., 0].max()) + 1.0  # ahead, past its shadow
    boxed = dataclasses.replace(
        quadruped, terrain=(terrain("box", x0=far, x1=far + 0.3, y0=-0.5, y1=0.5, height=0.04),)
    )
    floor, _ = drawn(quadruped)
    assert floor > 0 and drawn(boxed) == (floor, 0)  # as on level ground


def test_a_creature_on_a_box_casts_its_shadow_on_the_boxs_top(quadruped: Motion) -> None:
    lo, hi = (
        quadruped.positions[..., :2].min(axis=(0, 1)),
        quadruped.positions[..., :2].max(axis=(0, 1)),
    )
    box = terrain(
        "box", x0=lo[0] - 1, x1=hi[0] + 1, y0=lo[1] - 1, y1=hi[1] + 1, height=HEIGHT
    )  # wide enough for the whole shadow
    up = np.array([0.0, 0.0, HEIGHT])
    raised = dataclasses.replace(
        quadruped,
        terrain=(box,),
        positions=quadruped.positions + up,
        com=quadruped.com + up,
        contact_positions=quadruped.contact_positions + up,
    )
    floor, on_tops = drawn(raised)
    assert on_tops >= drawn(quadruped)[0] // 2 and floor < on_tops


def test_a_slope_takes_the_shadow_in_its_plane(quadruped: Motion) -> None:
    from legdsl.export.shapes import body_mesh
    from legdsl.export.video_shadows import ground_shadows
    from legdsl.export.video_views import PerspectiveView

    slope = (terrain("slope", angle=np.radians(20)),)
    tris = body_mesh(quadruped.bodies[0]).positions[body_mesh(quadruped.bodies[0]).indices] + [
        0.0,
        0.0,
        1.0,
    ]
    cast, on_tops = ground_shadows(slope, tris, PerspectiveView.LIGHT)
    assert not on_tops and len(cast) == len(tris)
    cast = np.array(cast)
    assert np.allclose(cast[..., 2], np.tan(np.radians(20)) * cast[..., 0], atol=1e-12)
    assert drawn(dataclasses.replace(quadruped, terrain=slope))[0] > 0
