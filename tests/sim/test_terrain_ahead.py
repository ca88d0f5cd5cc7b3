"""The terrain ahead (members terrain.ahead_*, legdsl.sim.terrain_ahead): distances in closed
form, and the members as a controller reads them."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from legdsl.check.source import check_model
from legdsl.ir.model import Terrain
from legdsl.lang.errors import LegError, Span
from legdsl.sim.terrain_ahead import ahead

SPAN = Span("t", 1, 1, 1, 2)


def box(x0: float, x1: float, h: float, y0: float = -1e3, y1: float = 1e3) -> Terrain:
    return Terrain("box", (("x0", x0), ("x1", x1), ("y0", y0), ("y1", y1), ("height", h)), SPAN)


def step(x: float, h: float) -> Terrain:
    return Terrain("step", (("x", x), ("height", h)), SPAN)


def test_the_next_feature_along_the_heading() -> None:
    terrain = [box(10.0, 10.3, 0.3), step(20.0, 0.1), box(4.0, 4.5, 0.2)]
    near = ahead(terrain, 1.0, 0.0, 0.0)
    assert near == pytest.approx(
        {"ahead_distance": 3.0, "ahead_height": 0.2, "ahead_depth": 0.5, "ahead_given": 1.0}
    )
    # over the first box, it is behind: the next is the 0.3 m box
    over = ahead(terrain, 4.2, 0.0, 0.0)
    assert over["ahead_distance"] == pytest.approx(5.8) and over["ahead_height"] == 0.3
    past = ahead(terrain, 15.0, 0.0, 0.0)  # a step has no far edge
    assert past == pytest.approx(
        {"ahead_distance": 5.0, "ahead_height": 0.1, "ahead_depth": 0.0, "ahead_given": 1.0}
    )
    assert ahead(terrain, 25.0, 0.0, 0.0)["ahead_given"] == 0.0
    # looking backwards from 15 m: the 0.3 m box, 4.7 m away, its far edge first
    back = ahead(terrain, 15.0, 0.0, math.pi)
    assert back["ahead_distance"] == pytest.approx(4.7) and back["ahead_depth"] == pytest.approx(
        0.3
    )


def test_a_box_in_3d_is_met_at_an_angle_or_missed() -> None:
    block = [box(2.0, 3.0, 0.5, y0=-0.5, y1=0.5)]
    diagonal = ahead(block, 0.0, -2.0, math.atan2(2.0, 2.5))
    # the line from (0, -2) with slope 2/2.5 reaches x = 2 at y = -0.4 (inside the y range)
    assert diagonal["ahead_given"] == 1.0
    assert diagonal["ahead_distance"] == pytest.approx(math.hypot(2.0, 1.6))
    assert ahead(block, 0.0, 2.0, 0.0)["ahead_given"] == 0.0  # passes beside it
    assert ahead([Terrain("slope", (("angle", 0.1),), SPAN)], 0.0, 0.0, 0.0)["ahead_given"] == 0.0


CONTROLLER = """
controller look {
  signal gap = terrain.ahead_distance - terrain.ahead_depth
  table {
    state ONLY on time > 0: body_servo.setpoint = select(terrain.ahead_given > 0 and gap > 1 m, 1 m, terrain.height)
  }
}
"""
CREATURE = """
creature slider {
  planar
  body base free { mass 1 kg  inertia 0.01 kg*m^2 }
  body arm on base via prismatic slide at (0 m, 0 m) { mass 0.1 kg  inertia 0.001 kg*m^2 }
  actuator body_servo on slide servo(kp = 10 N/m, kv = 1 N*s/m)
  ground { normal spring(k = 1e4 N/m)  tangent spring(k = 1e4 N/m) }
}
"""


def test_the_members_are_lengths_and_checked(tmp_path: Path) -> None:
    path = tmp_path / "slider.leg"
    path.write_text(CREATURE + CONTROLLER, encoding="utf-8")
    model = check_model(path)
    assert model.controller("look") is not None
    path.write_text(CREATURE + CONTROLLER.replace("ahead_depth", "ahead_deep"), encoding="utf-8")
    with pytest.raises(LegError) as err:
        check_model(path)
    assert "a terrain ahead has no member 'ahead_deep'" in str(err.value)
    assert "did you mean 'ahead_depth'" in str(err.value)
