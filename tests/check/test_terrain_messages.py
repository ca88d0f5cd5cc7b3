"""The terrain a user may not write gets an error at the argument that is wrong, saying what to
write instead: a step down (the floor is at 0 and a feature only raises it), a slope of 80 deg."""

from __future__ import annotations

from pathlib import Path

import pytest
from conftest import CREATURES

from legdsl.cli import main

HOPPER = CREATURES / "hopper.leg"


def _hopper_with(tmp_path: Path, terrain: str) -> Path:
    text = HOPPER.read_text()
    assert "    friction none\n  }" in text
    path = tmp_path / "hopper.leg"
    path.write_text(
        text.replace("    friction none\n  }", f"    friction none\n    {terrain}\n  }}", 1)
    )
    return path


@pytest.mark.parametrize(
    ("terrain", "points_at", "says"),
    [
        (
            "terrain step(x = 2 m, height = -5 cm)",
            "-5 cm",
            "for a step down at x = X, raise the floor before it",
        ),
        (
            "terrain box(x0 = 1 m, x1 = 2 m, height = 0 cm)",
            "0 cm",
            "for a pit, raise the floor on both sides",
        ),
        ("terrain slope(angle = 80 deg)", "80 deg", "79.9 deg is allowed, 80 deg is not"),
    ],
)
def test_terrain_refused_at_its_argument_with_the_fix(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], terrain: str, points_at: str, says: str
) -> None:
    path = _hopper_with(tmp_path, terrain)
    assert main(["check", str(path)]) == 2
    err = capsys.readouterr().err
    assert says in err
    line, caret = err.splitlines()[1:3]
    column = line.index(points_at)
    assert caret.index("^") == column, err  # the caret under the value, not the whole call
    assert (
        f":{column - 3}: error:" in err.splitlines()[0]
    )  # file:line:col (the line shown indented by 4)


def test_the_steepest_slope_and_the_step_down_the_message_gives_are_accepted(
    tmp_path: Path,
) -> None:
    assert main(["check", str(_hopper_with(tmp_path, "terrain slope(angle = 79.9 deg)"))]) == 0
    down = "terrain box(x0 = -100 m, x1 = 2 m, height = 10 cm)"
    assert main(["check", str(_hopper_with(tmp_path, down))]) == 0


@pytest.mark.parametrize(
    ("terrain", "points_at", "says"),
    [
        (
            "terrain slope(angle = 5 deg)\n    terrain step(x = 1 m, height = 5 cm)",
            "step(",
            "(the slope is on line 47); keep the slope alone",
        ),
        (
            "terrain box(x0 = 2 m, x1 = 150 cm, height = 5 cm)",
            "150 cm",
            "x1 = 1.5 m is not beyond x0 = 2 m; swap them",
        ),
    ],
)
def test_a_slope_beside_terrain_and_a_reversed_box_are_pointed_at(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], terrain: str, points_at: str, says: str
) -> None:
    path = _hopper_with(tmp_path, terrain)
    assert main(["check", str(path)]) == 2
    err = capsys.readouterr().err
    assert says in err
    line, caret = err.splitlines()[1:3]
    assert caret.index("^") == line.index(points_at), err
