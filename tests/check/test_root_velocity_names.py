"""A root's velocity written under `initial` (or its pose under `velocity`) is told where it
goes: `initial ..., vy = 0.3 m/s` on a 3D root was told "did you mean 'y'?", which would set a
position; a 3D root's `vx` on a planar root, whose velocity is named by its coordinates, too."""

from __future__ import annotations

from pathlib import Path

import pytest

from legdsl.check.source import check_model
from legdsl.lang.errors import LegError

ROOT = Path(__file__).resolve().parents[2]
MONOPOD = (ROOT / "tests" / "good" / "outside" / "monopod_3d.leg").read_text(encoding="utf-8")
HOPPER = (ROOT / "creatures" / "hopper.leg").read_text(encoding="utf-8")
POSE_3D = "initial x = 0 m, y = 0 m, z = 0.72 m"
POSE_2D = "initial x = 0 m, z = 0.95 m, pitch = 0 deg"


def _message(tmp_path: Path, text: str) -> str:
    path = tmp_path / "creature.leg"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(LegError) as caught:
        check_model(path)
    (d,) = caught.value.diagnostics
    return d.message


@pytest.mark.parametrize(
    ("added", "said"),
    [
        (", vy = 0.3 m/s", "'vy' is a velocity: write it as 'velocity vy = ...'"),
        ("\n    velocity wz = 1 deg/s, roll = 2 deg", "write it as 'initial roll = ...'"),
        ("\n    velocity vxx = 1 m/s", "did you mean 'vx'?"),
    ],
)
def test_a_3d_roots_names_under_the_other_key_say_where_they_go(
    tmp_path: Path, added: str, said: str
) -> None:
    assert POSE_3D in MONOPOD
    message = _message(tmp_path, MONOPOD.replace(POSE_3D, POSE_3D + added))
    assert "is not a coordinate of a 3D free root" in message and said in message


def test_a_planar_roots_velocity_is_named_by_its_coordinate(tmp_path: Path) -> None:
    assert POSE_2D in HOPPER
    message = _message(tmp_path, HOPPER.replace(POSE_2D, POSE_2D + "\n    velocity vx = 1 m/s"))
    assert message.endswith("it has x, z, pitch; a velocity is named by its coordinate: "
                            "write 'velocity x = ...'")  # fmt: skip
