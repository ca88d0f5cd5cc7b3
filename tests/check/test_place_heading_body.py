"""A body whose yaw turns an action's ``place`` goals into the heading frame must be the root:
``place_foot_3d(active, shank, ...)`` checked clean and turned the hopper's velocity by the
shank's yaw, while ``place`` offsets the foot in the root's heading frame."""

from __future__ import annotations

from pathlib import Path

import pytest

from legdsl.check.source import check_model
from legdsl.lang.errors import LegError

ROOT = Path(__file__).resolve().parents[2]
MONOPOD = (ROOT / "tests" / "good" / "outside" / "monopod_3d.leg").read_text(encoding="utf-8")
CALL = "place_foot_3d(active, body,"


def _check(tmp_path: Path, text: str) -> None:
    path = tmp_path / "monopod_3d.leg"
    path.write_text(text, encoding="utf-8")
    check_model(path)


@pytest.mark.parametrize("body", ["shank", "thigh"])
def test_a_leg_body_given_to_place_foot_3d_is_told_at_the_argument(
    tmp_path: Path, body: str
) -> None:
    assert CALL in MONOPOD
    text = MONOPOD.replace(CALL, f"place_foot_3d(active, {body},")
    with pytest.raises(LegError) as caught:
        _check(tmp_path, text)
    (d,) = caught.value.diagnostics
    assert d.message.startswith(f"action 'place_foot_3d' places a foot from the yaw of '{body}'")
    assert "turned by the yaw of the root body 'body'; did you mean 'body'?" in d.message
    line = text.splitlines()[d.span.line - 1]
    assert line[d.span.col - 1 :].startswith(f"{body},")


def test_a_body_welded_to_the_root_places_too(tmp_path: Path) -> None:
    head = (
        "  body head on body via fixed neck { mass 0.5 kg  inertia (0.001, 0.001, 0.001) kg*m^2 }\n"
    )
    text = MONOPOD.replace("  contact toe", head + "  contact toe")
    _check(tmp_path, text.replace(CALL, "place_foot_3d(active, head,"))


def test_a_leg_body_read_for_pitch_in_a_place_is_not_told(tmp_path: Path) -> None:
    """Only the yaw turns the goals into the heading frame: an action placing the foot by a
    leg body's pitch is the writer's business."""
    action = (
        "  action tilt(leg, link) {\n"
        "    place leg at (x = 0.1 m * sin(link.pitch), y = 0 m) using leg.hip_servo, leg.roll_servo\n"
        "  }\n"
    )
    text = MONOPOD.replace("  roles active = main\n", "  roles active = main\n" + action)
    line = "  state LOADING     on touchdown(active):       free_hip_3d(active)"
    assert line in text
    _check(tmp_path, text.replace(line, line.replace("free_hip_3d(active)", "tilt(active, shank)")))
