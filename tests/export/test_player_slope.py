"""The HTML player on a slope: the camera's height is kept above the slope's plane, so a
creature 20 m up a 45 deg slope is in the picture (before, the camera stayed at its height over
z = 0 and the climb left the frame), and the look-at height is measured above that plane."""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest
from anim_runs import creature_motion
from chromium import Chromium
from external_tools import chromium

from legdsl.export.motion import Motion
from legdsl.export.player import camera_hints, write_player
from legdsl.ir.model import Terrain
from legdsl.lang.errors import Span

WIDTH, HEIGHT = 800, 450
ANGLE = math.radians(45)
FAR = 20.0


@pytest.fixture(scope="module")
def up_the_slope(tmp_path_factory: pytest.TempPathFactory) -> Motion:
    motion = creature_motion("quadruped", tmp_path_factory.mktemp("quadruped") / "run", 0.3)
    slope = Terrain("slope", (("angle", ANGLE),), Span("x.leg", 1, 1, 1, 2))
    shift = np.array([FAR, 0.0, FAR * math.tan(ANGLE)])
    return dataclasses.replace(
        motion, terrain=(slope,), positions=motion.positions + shift, com=motion.com + shift
    )


def test_the_look_height_is_above_the_slope(up_the_slope: Motion) -> None:
    level = dataclasses.replace(
        up_the_slope,
        terrain=(),
        positions=up_the_slope.positions - np.array([0.0, 0.0, FAR]),
        com=up_the_slope.com - np.array([0.0, 0.0, FAR]),
    )
    assert camera_hints(up_the_slope)["lookHeight"] == pytest.approx(
        camera_hints(level)["lookHeight"]
    )


@pytest.fixture(scope="module")
def browser() -> Iterator[Chromium]:
    with Chromium(chromium(), WIDTH, HEIGHT) as c:
        yield c


def test_the_player_keeps_a_creature_up_the_slope_in_the_picture(
    browser: Chromium, up_the_slope: Motion, tmp_path: Path
) -> None:
    page = tmp_path / "animation.html"
    write_player(up_the_slope, page)
    browser.open_player(page)
    assert browser.errors() == []
    browser.evaluate(f"legdsl.setTime({up_the_slope.duration})")
    x, y, z = (float(v) for v in up_the_slope.com[-1])
    px, py = browser.evaluate(f"legdsl.project({x}, {y}, {z})")
    assert 0 <= px <= WIDTH and 0 <= py <= HEIGHT, (px, py)


STEEP = math.radians(60)


@pytest.mark.parametrize(
    "view",
    [
        {},  # the default view
        {"elevation": -0.2, "azimuth": 0.0},  # dragged as low as it goes, looking down the slope
        {"elevation": -0.2, "azimuth": math.pi / 2},
        {"elevation": 0.0, "azimuth": -math.pi / 3, "distance": 30.0},  # zoomed out
        {"elevation": 1.5, "azimuth": math.pi},  # from above, uphill
    ],
)
def test_the_orbit_camera_stays_above_a_steep_slope(
    browser: Chromium, up_the_slope: Motion, tmp_path: Path, view: dict[str, float]
) -> None:
    """On a 60 deg slope the level orbit put the default eye under the ground; the orbit is now
    tilted with the slope and kept at least a tenth of the creature's size above its plane."""

    def reseated(points: np.ndarray) -> np.ndarray:  # from the 45 deg slope onto the steep one
        lift = (math.tan(STEEP) - math.tan(ANGLE)) * points[..., 0]
        return points + np.stack([0 * lift, 0 * lift, lift], axis=-1)

    steep = dataclasses.replace(
        up_the_slope,
        terrain=(dataclasses.replace(up_the_slope.terrain[0], params=(("angle", STEEP),)),),
        positions=reseated(up_the_slope.positions),
        com=reseated(up_the_slope.com),
        contact_positions=reseated(up_the_slope.contact_positions),
    )
    page = tmp_path / "animation.html"
    write_player(steep, page)
    browser.open_player(page)
    if view:
        browser.evaluate(f"legdsl.setView({{{', '.join(f'{k}: {v!r}' for k, v in view.items())}}})")
    size = camera_hints(steep)["size"]
    for t in (0.0, steep.duration):
        browser.evaluate(f"legdsl.setTime({t})")
        x, _, z = browser.evaluate("legdsl.cameraPosition()")
        above = (z - x * math.tan(STEEP)) * math.cos(STEEP)  # distance from the plane
        assert above >= 0.1 * size - 1e-6, (view, t, above)
    assert browser.errors() == []
