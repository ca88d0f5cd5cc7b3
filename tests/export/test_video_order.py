"""The 3D video's painting order with terrain: a step's top was one polygon from its edge to the
floor's far end, sorted by its centre's depth, and was painted over the links above it (a box
held over a step lost its lower faces, a leg over a 5 cm step was cut at the step's edge, as
the player never draws them). Each terrain face is now painted between what lies behind its
plane and what lies in front of it."""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np
import pytest
from anim_runs import creature_motion

from legdsl.export.motion import Motion
from legdsl.ir.model import Terrain
from legdsl.lang.errors import Span

LIFT = 0.07  # m: the quadruped held this far up (its feet sink 2.3 mm into the ground)
STEP = 0.06  # m: the height of a step under all of it


def terrain(kind: str, **params: float) -> Terrain:
    return Terrain(kind, tuple(params.items()), Span("x.leg", 1, 1, 1, 2))


@pytest.fixture(scope="module")
def raised(tmp_path_factory: pytest.TempPathFactory) -> Motion:
    """The quadruped's passive drop, LIFT higher: nothing of it below z = STEP."""
    motion = creature_motion("quadruped", tmp_path_factory.mktemp("quadruped") / "run", 0.3)
    up = np.array([0.0, 0.0, LIFT])
    return dataclasses.replace(
        motion,
        positions=motion.positions + up,
        com=motion.com + up,
        contact_positions=motion.contact_positions + up,
    )


def picture(motion: Motion) -> tuple[np.ndarray, Any]:
    """The last frame's pixels, and the view that drew them."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from legdsl.export.video_views import PerspectiveView

    fig = plt.figure(figsize=(4.8, 2.7), dpi=100)
    try:
        ax = fig.add_axes((0, 0, 1, 1))
        ax.set_axis_off()  # as the video draws it: no frame
        view = PerspectiveView(motion, ax, (), 480, 270)
        view.update(motion.at(float(motion.times[-1])))
        view.text.set_visible(False)  # the caption's dark letters are not the creature
        fig.canvas.draw()
        return np.asarray(fig.canvas.buffer_rgba())[..., :3].astype(int), view
    finally:
        plt.close(fig)


def creature(pixels: np.ndarray) -> np.ndarray:
    """Where the quadruped is drawn: its olive and dark links are darker than the sky, the
    ground, the terrain and the shadows (#a9a9a4 the darkest of them)."""
    return pixels.max(axis=2) < 150


def test_a_step_under_the_creature_hides_none_of_it(raised: Motion) -> None:
    alone, _ = picture(raised)
    x_mid = float(raised.com[-1, 0])  # the step's edge under the middle of the creature
    on_step = dataclasses.replace(raised, terrain=(terrain("step", x=x_mid, height=STEP),))
    assert raised.contact_positions[..., 2].min() > STEP
    stepped, _ = picture(on_step)
    seen = creature(alone)
    assert seen.sum() > 1000
    kept = (creature(stepped) & seen).sum() / seen.sum()
    assert kept > 0.99, f"only {kept:.1%} of the creature is drawn over the step"
    terrain_grey = np.all(np.abs(stepped - (0xC2, 0xC2, 0xBC)) <= 2, axis=2)
    assert terrain_grey.sum() > 10000  # the step is drawn, around the creature


def test_a_box_between_the_camera_and_the_creature_still_hides_it(raised: Motion) -> None:
    """The other way round: a wall of a box in front of the creature is painted over it."""
    alone, view = picture(raised)
    target = raised.com[-1]
    middle = (view.camera.eye + target) / 2  # halfway to the eye, as high as the eye
    wall = terrain(
        "box",
        x0=middle[0] - 0.3,
        x1=middle[0] + 0.3,
        y0=middle[1] - 0.3,
        y1=middle[1] + 0.3,
        height=float(view.camera.eye[2]) + 1.0,
    )
    hidden, _ = picture(dataclasses.replace(raised, terrain=(wall,)))
    assert creature(alone).sum() > 1000 and creature(hidden).sum() == 0


def test_a_shadow_across_a_steps_edge_falls_on_its_top_and_on_the_floor() -> None:
    """A triangle whose shadow crossed the step's edge was drawn whole on the floor, under the
    step (a leg's shadow on a step kept a dot of it); its part on the top is cut off there."""
    from legdsl.export.video_shadows import ground_shadows
    from legdsl.export.video_views import PerspectiveView

    light = PerspectiveView.LIGHT
    step = (terrain("step", x=0.0, height=0.05),)
    tri = np.array([[[-0.3, 0.0, 0.3], [0.3, 0.0, 0.3], [0.3, 0.05, 0.3]]])
    floor, on_tops = ground_shadows(step, tri, light)
    assert len(floor) == 1 and len(on_tops) == 1 and on_tops[0][1] == 0
    top = on_tops[0][0]
    assert np.allclose(top[:, 2], 0.05) and top[:, 0].min() >= -1e-12
    assert np.allclose(floor[0][:, 2], 0.0)
    # the floor's part is where the light passes the step's edge: ahead of it, before x = 0
    passes = floor[0][:, 0] + (0.05 / light[2]) * light[0]
    assert passes.max() <= 1e-12

    def area(poly: np.ndarray) -> float:
        x, y = poly[:, 0], poly[:, 1]
        return 0.5 * abs(float(x @ np.roll(y, -1) - y @ np.roll(x, -1)))

    whole = ground_shadows((), tri, light)[0][0]  # on level ground: the same area, in one piece
    assert area(top) + area(floor[0]) == pytest.approx(area(whole), rel=1e-9)
