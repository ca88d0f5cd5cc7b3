"""The creature's shapes against the terrain (legdsl.analysis.clearance), on poses whose
margins are known in closed form, planar (exact) and 3D (sampled)."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from legdsl.analysis.clearance import side_polygon, terrain_contacts
from legdsl.check.source import check_model

PLANAR = """
creature block {
  planar
  body slab free { mass 1 kg  inertia 0.01 kg*m^2  shape box(0.2 m, 0.1 m) }
  body rod on slab via revolute pin at (0 m, 0 m) {
    length 0.4 m  mass 0.1 kg  inertia 0.001 kg*m^2  shape frustum(0.04 m, 0.02 m)
  }
  ground {
    normal spring(k = 1e4 N/m)  tangent spring(k = 1e4 N/m)
    terrain box(x0 = 0.9 m, x1 = 1.1 m, height = 0.3 m)
    terrain step(x = 5 m, height = 0.1 m)
  }
}
"""
SPATIAL = (
    PLANAR.replace("  planar\n", "  spatial\n")
    .replace("box(0.2 m, 0.1 m)", "box(0.2 m, 0.2 m, 0.1 m)")
    .replace("x1 = 1.1 m, height", "x1 = 1.1 m, y0 = -0.5 m, y1 = 0.5 m, height")
    .replace("inertia 0.01 kg*m^2", "inertia (0.01, 0.01, 0.01) kg*m^2")
    .replace("inertia 0.001 kg*m^2", "inertia (0.001, 0.001, 0.001) kg*m^2")
    .replace("at (0 m, 0 m)", "at (0, 0, 0) m")
)


def _rot(pitch: float) -> tuple[float, ...]:
    c, s = math.cos(pitch), math.sin(pitch)
    return (c, 0.0, s, 0.0, 1.0, 0.0, -s, 0.0, c)  # about y


def _model(tmp_path: Path, text: str):  # type: ignore[no-untyped-def]
    path = tmp_path / "block.leg"
    path.write_text(text, encoding="utf-8")
    return check_model(path)


def _poses(x: float, z: float, pitch: float, rod_x: float = -10.0):  # type: ignore[no-untyped-def]
    # the rod hangs straight down from (rod_x, 0.65): its tip at z = 0.25
    return [((x, 0.0, z), _rot(pitch)), ((rod_x, 0.0, 0.65), _rot(0.0))]


@pytest.mark.parametrize("text", [PLANAR, SPATIAL])
def test_margins_over_a_box_in_closed_form(tmp_path: Path, text: str) -> None:
    model = _model(tmp_path, text)
    planar = text is PLANAR
    tol = 1e-9 if planar else 2e-3  # 3D: sampled surface points
    samples = [
        (0.0, _poses(1.0, 0.2, 0.0)),  # through the box: the slab's bottom 0.15 m in it
        (0.1, _poses(1.0, 0.5, 0.0)),  # above it: 0.5 - 0.05 - 0.3
        (0.2, _poses(1.0, 0.5, math.pi / 2)),  # turned on end: 0.5 - 0.1 - 0.3
    ]
    # overlapping, the planar margin is the depth along the best separating axis (0.15 m,
    # up); in 3D that of the deepest sampled point (the slab's centre, 0.1 m from the sides)
    deepest = -0.15 if planar else -0.10
    for k, expected in ((0, deepest), (1, 0.15), (2, 0.10)):
        (box, step) = terrain_contacts(
            model.bodies, model.ground.terrain, [samples[k][0]], [samples[k][1]], planar
        )
        assert box.margin == pytest.approx(expected, abs=tol)
        assert box.body == "slab"
        assert (box.overlapping == (samples[k][0],)) == (expected < 0)
        assert step.margin > 3.0  # the step is 4 m further on
    whole = terrain_contacts(
        model.bodies, model.ground.terrain, [s[0] for s in samples], [s[1] for s in samples], planar
    )
    assert whole[0].margin == pytest.approx(deepest, abs=tol) and whole[0].t == 0.0
    assert whole[0].overlapping == (0.0,)


def test_a_hanging_rod_clips_the_corner_of_the_box(tmp_path: Path) -> None:
    model = _model(tmp_path, PLANAR)
    # the rod (0.4 m long, radius 4 cm at its top, 2 cm at its tip) hangs from z = 0.65, its
    # tip at 0.25, below the box's top (0.3): 1 cm left of the box's edge it overlaps it
    inside = terrain_contacts(
        model.bodies, model.ground.terrain, [0.0], [_poses(-3.0, 1.0, 0.0, rod_x=0.89)], True
    )[0]
    assert inside.body == "rod" and inside.margin < 0 and inside.overlapping == (0.0,)
    # 5 cm left of it the rod's tapering side passes the corner (0.9, 0.3) at the distance
    # of the corner from the line (0.89, 0.65)-(0.87, 0.25): (0.03, 0.05) . (0.9988, -0.0499)
    clear = terrain_contacts(
        model.bodies, model.ground.terrain, [0.0], [_poses(-3.0, 1.0, 0.0, rod_x=0.85)], True
    )[0]
    assert clear.margin == pytest.approx(0.03 * 0.99875 - 0.05 * 0.04994, abs=1e-4)
    assert clear.overlapping == ()


def test_a_side_polygon_is_convex_and_covers_a_circle() -> None:
    from legdsl.ir.model import Body, Shape
    from legdsl.lang.errors import Span

    ball = Body(
        "ball", None, "free", 1.0, (0.0, 0.0, 0.0), ((0.0,) * 3,) * 3, None, (0.0, 0.0, -1.0),
        Shape("sphere", (("r", 0.1),)), None, Span("x", 1, 1, 1, 2),
    )  # fmt: skip
    poly = side_polygon(ball)
    radii = [math.hypot(x, z) for x, z in poly]
    assert min(radii) >= 0.1  # circumscribed
    assert max(radii) < 0.1 * 1.006
