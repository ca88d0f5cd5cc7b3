"""The player's camera height in headless Chromium (docs/animation.md, "View"): the target it
orbits stays at a fixed height while the creature is in frame, and rises where the creature
would leave the default view at the top (the planar biped's somersault: its legs, above a
1.35 m mass centre at the apex, were out of the picture), by the lift the videos use.
"""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest
from anim_runs import creature_motion
from camera_runs import APEX, bumped, flip_motion
from chromium import Chromium
from external_tools import chromium

from legdsl.export.motion import Motion
from legdsl.export.player import camera_hints, write_player
from legdsl.export.player.camera import world_points

WIDTH, HEIGHT = 800, 450


@pytest.fixture(scope="module")
def browser() -> Iterator[Chromium]:
    with Chromium(chromium(), WIDTH, HEIGHT) as c:
        yield c


def open_player(browser: Chromium, motion: Motion, tmp_path: Path) -> None:
    page = tmp_path / "animation.html"
    write_player(motion, page)
    browser.events.clear()
    browser.open_player(page)
    assert browser.errors() == []


def target_height(browser: Chromium, t: float) -> float:
    return float(browser.evaluate(f"legdsl.setTime({float(t)!r}); legdsl.cameraTarget()[2]"))


def test_the_camera_rises_to_keep_the_flips_apex_in_frame(
    browser: Chromium, tmp_path: Path
) -> None:
    flip = flip_motion(tmp_path / "run")
    open_player(browser, flip, tmp_path)
    # every vertex of every link is drawn inside the picture, below its top edge
    f = flip.frame_at(APEX)
    top = drawn_top(browser, flip, float(flip.times[f]))
    assert top > 0.02 * HEIGHT, f"{top:.1f} px from the top"
    # as the target it looks at rose, from the height held while running before the flip
    held = camera_hints(flip)["lookHeight"]
    assert target_height(browser, 5.0) == pytest.approx(held, abs=1e-6)
    apex = target_height(browser, float(flip.times[f]))
    assert apex > held + 0.3  # the mass centre climbs 0.45 m, the legs above it
    assert target_height(browser, float(flip.times[-1])) == pytest.approx(held, abs=1e-6)
    # the drag and the wheel still orbit the raised target (only its height changed)
    browser.evaluate("legdsl.setView({azimuth: 0.3, elevation: 0.5, distance: 6})")
    assert target_height(browser, float(flip.times[f])) == pytest.approx(apex, abs=1e-6)
    assert browser.errors() == []


def drawn_top(browser: Chromium, motion: Motion, t: float) -> float:
    """The highest of the creature's vertices on the screen at ``t``, in pixels from the top."""
    f = motion.frame_at(t)
    browser.evaluate(f"legdsl.setTime({float(motion.times[f])!r})")
    points = world_points(motion)[f].tolist()
    drawn = browser.evaluate(f"{points}.map((p) => legdsl.project(p[0], p[1], p[2])[1])")
    return float(min(drawn))


def test_a_hop_that_stays_in_frame_keeps_the_camera_height(
    browser: Chromium, tmp_path: Path
) -> None:
    kangaroo = creature_motion("kangaroo", tmp_path / "run", 2.0)
    times = np.linspace(0, kangaroo.duration, 11)
    # The kangaroo's 2 s drop lifted by a 0.8 m hop would leave the frame at its top: the
    # target rises there, and only there.
    high = bumped(kangaroo, 0.8, at=1.0)
    open_player(browser, high, tmp_path)
    assert drawn_top(browser, high, 1.0) > 0.02 * HEIGHT
    held = camera_hints(high)["lookHeight"]
    heights = np.array([target_height(browser, t) for t in times]) - held
    assert heights[5] > 0.1 and heights[0] == heights[-1] == 0
    # Lifted by 0.3 m its head stays under the frame's top: the target stays where it is,
    hop = bumped(kangaroo, 0.3, at=1.0)
    open_player(browser, hop, tmp_path)
    held = camera_hints(hop)["lookHeight"]
    assert [target_height(browser, t) for t in times] == pytest.approx([held] * 11, abs=1e-6)
    # while the creature goes up and down on the screen.
    assert drawn_top(browser, hop, 1.0) < drawn_top(browser, hop, 0.0) - 20
