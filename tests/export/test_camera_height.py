"""The height the videos' camera looks at (docs/animation.md, "View"): fixed, so that hops show
as motion on the screen, and raised smoothly, only as much as needed, where the creature would
leave the frame at the top (legdsl.export.player.camera, the player's rule too).

Before, the planar biped's somersault left the frame at its apex: its legs, above a 1.35 m
mass centre, were cut off at the top of the picture.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from anim_runs import creature_motion
from camera_runs import APEX, bumped, flip_motion
from pixels import hue_mask

from legdsl.analysis.plot import pyplot
from legdsl.export.motion import Motion
from legdsl.export.player.camera import MARGIN, hull_points, world_points
from legdsl.export.shapes import hex_rgb
from legdsl.export.video import render_video
from legdsl.export.video_views import SKY, PerspectiveView, SideView, View

WIDTH, HEIGHT = 640, 360


@pytest.fixture(scope="module")
def flip(tmp_path_factory: pytest.TempPathFactory) -> Motion:
    return flip_motion(tmp_path_factory.mktemp("flip") / "run")


def views(motion: Motion) -> tuple[object, View]:
    plt = pyplot()
    fig = plt.figure(figsize=(WIDTH / 100, HEIGHT / 100), dpi=100, facecolor=SKY)
    ax = fig.add_axes((0, 0, 1, 1))
    ax.set_autoscale_on(False)
    view: View
    if motion.planar:
        ax.set_aspect("auto")
        view = SideView(motion, ax, (), WIDTH / HEIGHT)
    else:
        view = PerspectiveView(motion, ax, (), WIDTH, HEIGHT)
    return fig, view


def side_frames(motion: Motion) -> tuple[np.ndarray, np.ndarray]:
    """Per frame, the side view's (bottom, top) and the creature's highest point."""
    fig, view = views(motion)
    try:
        limits = []
        for t in motion.times:
            view.update(motion.at(float(t)))
            limits.append(view.ax.get_ylim())
    finally:
        pyplot().close(fig)
    return np.array(limits), world_points(motion)[..., 2].max(axis=1)


def gif_frames(path: Path) -> list[np.ndarray]:
    from PIL import Image

    frames = []
    with Image.open(path) as gif:
        for k in range(gif.n_frames):
            gif.seek(k)
            frames.append(np.asarray(gif.convert("RGB")).astype(float) / 255)
    return frames


def only_sky_on_top(frame: np.ndarray) -> bool:
    """Nothing but sky along the top of the picture, right of the caption's box."""
    band = frame[: round(0.03 * HEIGHT), round(0.4 * WIDTH) :]
    return bool(np.abs(band - np.array(hex_rgb(SKY))).max() < 0.06)


def test_the_flips_apex_is_in_the_videos_frame(flip: Motion, tmp_path: Path) -> None:
    path = tmp_path / "flip.gif"
    render_video(flip, path, fps=2, size=(WIDTH, HEIGHT), overlays=())
    frames = gif_frames(path)
    apex = frames[round(APEX * 2)]
    sky = np.array(hex_rgb(SKY))
    assert (np.abs(apex - sky).max(axis=2) > 0.2).sum() > 2000  # the creature is drawn
    # before, its legs crossed the top edge here
    assert only_sky_on_top(apex)


def test_the_side_view_keeps_every_link_in_frame_and_rises_smoothly(flip: Motion) -> None:
    limits, top = side_frames(flip)
    height = limits[:, 1] - limits[:, 0]
    assert np.allclose(height, height[0])
    allowed = limits[:, 1] - MARGIN * height
    assert (top <= allowed + 1e-9).all(), f"{(top - allowed).max():.3f} m out at the top"
    middle = limits.mean(axis=1)
    held = middle[0]
    raised = middle - held
    apex = flip.frame_at(APEX)
    assert raised[apex] > 0.3  # the mass centre climbs 0.45 m, the legs go above it
    # held before the flip's take-off (6.03 s) and back down after the landing (6.87 s)
    assert np.all(raised[flip.times < 5.9] == 0) and raised[-1] == 0
    # smoothly: no jump between frames (60 a second), no kick in its speed
    step = 1 / 60
    assert np.abs(np.diff(raised)).max() < 3.0 * step  # under 3 m/s
    assert np.abs(np.diff(raised, 2)).max() < 30.0 * step**2  # under 30 m/s^2
    # only as much as needed: the highest link touches the margin's line at the apex
    assert (allowed - top)[raised > 0].min() < 1e-6


def test_a_hop_that_stays_in_frame_keeps_the_camera_height(tmp_path: Path) -> None:
    # The kangaroo's 2 s drop, lifted by a 0.3 m hop: its head stays under the frame's top.
    kangaroo = creature_motion("kangaroo", tmp_path / "run", 2.0)
    limits, top = side_frames(bumped(kangaroo, 0.3, at=1.0))
    assert np.all(limits == limits[0])  # not a pixel of camera motion
    assert top.max() - top.min() > 0.3  # while the creature went up and down in the picture
    assert (top < limits[0, 1] - MARGIN * (limits[0, 1] - limits[0, 0])).all()
    # lifted by 0.8 m it would leave the frame: the camera rises, and only then
    limits, top = side_frames(bumped(kangaroo, 0.8, at=1.0))
    raised = limits[:, 1] - limits[0, 1]
    assert raised.max() > 0.1 and raised[0] == 0 and raised[-1] == 0
    assert (top <= limits[:, 1] - MARGIN * (limits[:, 1] - limits[:, 0]) + 1e-9).all()


def test_the_3d_view_keeps_a_high_hop_in_frame(tmp_path: Path) -> None:
    # The quadruped's 1 s drop lifted by a 0.8 m hop: at its top, the trunk was cut off.
    quadruped = bumped(creature_motion("quadruped", tmp_path / "run"), 0.8)
    fig, view = views(quadruped)
    assert isinstance(view, PerspectiveView)
    points = world_points(quadruped)
    heights = []
    try:
        for f, t in enumerate(quadruped.times):
            view.update(quadruped.at(float(t)))
            cam = view.camera
            pixels = cam.to_pixels(cam.to_camera(points[f]))
            assert pixels[:, 1].max() <= HEIGHT * (1 - MARGIN) + 1e-6, t
            heights.append(cam.eye[2])
    finally:
        pyplot().close(fig)
    raised = np.array(heights) - heights[0]
    assert raised[quadruped.frame_at(0.5)] > 0.05
    assert raised[0] == 0 and np.abs(np.diff(raised)).max() < 3.0 / 60
    path = tmp_path / "hop.gif"
    render_video(quadruped, path, fps=4, size=(WIDTH, HEIGHT), overlays=())
    top = gif_frames(path)[2]  # 0.5 s
    assert hue_mask(top, quadruped.bodies[0].color or "").sum() > 2000
    assert only_sky_on_top(top)


def test_a_link_flung_far_above_keeps_the_rest_and_the_ground_in_frame(tmp_path: Path) -> None:
    """One light link of a random rig flew 19 m up in 0.3 s (LEGDSL_RANDOM_PLAYER_SEED=14700):
    raised to keep it in frame, the camera showed only sky, the rest of the creature and the
    ground far below. A creature taller than the frame keeps its lowest point in view."""
    quadruped = creature_motion("quadruped", tmp_path / "run")
    flung = quadruped.positions.copy()
    flung[:, -1, 2] += 20.0 * quadruped.times / quadruped.times[-1]  # one body, up to 20 m
    motion = dataclasses.replace(quadruped, positions=flung)
    fig, view = views(motion)
    assert isinstance(view, PerspectiveView)
    points = world_points(motion)
    # world_points lists the bodies in order: all but the last, the flung one
    rest = points.shape[1] - len(hull_points(motion)[-1])
    try:
        for f, t in enumerate(motion.times):
            view.update(motion.at(float(t)))
            cam = view.camera
            ys = cam.to_pixels(cam.to_camera(points[f, :rest]))[:, 1]
            assert ys.min() > 0, t  # the feet in the frame (the easing may take the margin)
            assert view.camera.eye[2] < 5.0, t  # not raised towards the flung link
    finally:
        pyplot().close(fig)


def _repeated(motion: Motion, times: int) -> Motion:
    """``motion`` played ``times`` times over, as one run."""
    tiled = {name: np.concatenate([getattr(motion, name)] * times)
             for name in ("positions", "quaternions", "com")}  # fmt: skip
    step = float(motion.times[1] - motion.times[0])
    return dataclasses.replace(motion, times=np.arange(times * motion.frames) * step, **tiled)


def _peak_bytes(work: Callable[[], Any]) -> tuple[Any, int]:
    import tracemalloc

    tracemalloc.start()
    try:
        done = work()
        return done, tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()


def test_the_lift_of_a_long_run_needs_no_more_memory_than_a_short_one(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Every mesh vertex of every frame was held at once (with five arrays made from them):
    some 40 KB a frame, 0.8 GB for a 300 s quadruped player whose run was recorded in 0.2 GB
    (3.7 GB for a 30 min run). The lift is the same, a block of frames at a time, in as much
    memory for three times the frames."""
    from legdsl.export.player import camera

    short = creature_motion("quadruped", tmp_path / "run")  # 61 frames
    motion, longer = _repeated(short, 40), _repeated(short, 120)
    lift, peak = _peak_bytes(lambda: camera.lift_range(motion, 0.5, 3.0))
    _, peak_longer = _peak_bytes(lambda: camera.lift_range(longer, 0.5, 3.0))
    assert lift.shape == (motion.frames, 2)
    assert peak_longer < 1.3 * peak
    monkeypatch.setattr(camera, "FRAMES_AT_ONCE", 10**9)  # all at once, as before
    assert np.array_equal(camera.lift_range(motion, 0.5, 3.0), lift)
