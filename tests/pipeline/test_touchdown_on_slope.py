"""The foot's speed over the ground at touchdown on a slope is its speed along the tilted
surface: a foot that lands moving with the slope's surface reads its speed along it, and one
that comes straight down at it reads the part of that motion along the surface, not the
horizontal speed (which was right only on level ground)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from conftest import CREATURES

from legdsl.check.source import check_model
from legdsl.pipeline import touchdown
from legdsl.pipeline.apex import Kinematics
from legdsl.pipeline.scaled import q_factors
from legdsl.sim.trajectory import Trajectory, empty

ANGLE = math.radians(30)


def _hopper(tmp_path: Path, terrain: str) -> Path:
    text = CREATURES.joinpath("hopper.leg").read_text()
    assert "    friction none\n  }" in text
    path = tmp_path / "hopper.leg"
    path.write_text(
        text.replace("    friction none\n  }", f"    friction none\n    {terrain}\n  }}", 1)
    )
    return path


class _FootMoving:
    """Generated dynamics whose one contact always moves at ``velocity``."""

    def __init__(self, velocity: tuple[float, float, float]) -> None:
        self.velocity = velocity

    def contact_velocities(self, q: list[float], v: list[float]) -> list[tuple[float, ...]]:
        return [self.velocity]


def _landing(model: object, nq: int) -> Trajectory:
    n = 10
    tr = empty(
        n, nq, nq, 1, 1, q_names=tuple(f"q{i}" for i in range(nq)),
        v_names=tuple(f"q{i}" for i in range(nq)), contact_names=("toe",),
        leg_names=("main",), leg_feet=(0,), total_mass=1.0,
    )  # fmt: skip
    tr.t[:] = np.linspace(0.0, 0.09, n)
    tr.q[:] = 0.0
    tr.v[:] = 0.0
    tr.contact[:, 0] = 0
    tr.contact[5:8, 0] = 1  # one complete stance, touching down at the sixth sample
    return tr


@pytest.mark.parametrize(
    ("terrain", "velocity", "expected"),
    [
        # straight down at a 30 deg slope: 1 m/s of it runs along the surface, sin(30 deg)
        ("terrain slope(angle = 30 deg)", (0.0, 0.0, -1.0), math.sin(ANGLE)),
        # moving with the surface, up the slope: its whole speed is along the ground
        ("terrain slope(angle = 30 deg)", (math.cos(ANGLE), 0.0, math.sin(ANGLE)), 1.0),
        # level ground, and a step's top: the horizontal speed, as before
        ("terrain step(x = 2 m, height = 5 cm)", (0.6, 0.0, -1.0), 0.6),
    ],
)
def test_the_foot_speed_at_touchdown_is_along_the_ground_under_it(
    tmp_path: Path,
    terrain: str,
    velocity: tuple[float, float, float],
    expected: float,
) -> None:
    model = check_model(_hopper(tmp_path, terrain))
    kinematics = Kinematics(model, _FootMoving(velocity), q_factors(model, 1.0), 1.0)
    row = touchdown.touchdown_speed_row(kinematics, _landing(model, model.nq), 0.0, None)
    assert row.value == pytest.approx(expected)
    assert row.n == 1
