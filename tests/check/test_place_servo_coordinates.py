"""Each servo of a ``place`` moves its own coordinate: a 3D leg whose `roll_servo` alias names
its pitch servo (or a place naming one servo twice) is an error at the servo, where the check
let it through and the run quietly hopped in place with its sideways goal never reached."""

from __future__ import annotations

from pathlib import Path

import pytest

from legdsl.check.source import check_model
from legdsl.lang.errors import LegError

ROOT = Path(__file__).resolve().parents[2]
MONOPOD = ROOT / "tests" / "good" / "outside" / "monopod_3d.leg"


def _check(tmp_path: Path, text: str) -> None:
    path = tmp_path / "monopod_3d.leg"
    path.write_text(text, encoding="utf-8")
    check_model(path)


def test_the_monopod_with_a_servo_per_coordinate_checks(tmp_path: Path) -> None:
    _check(tmp_path, MONOPOD.read_text(encoding="utf-8"))


def test_a_roll_alias_naming_the_pitch_servo_is_told_at_the_library_place(
    tmp_path: Path,
) -> None:
    text = MONOPOD.read_text(encoding="utf-8")
    assert "roll_servo = hip_roll," in text
    with pytest.raises(LegError) as caught:
        _check(tmp_path, text.replace("roll_servo = hip_roll,", "roll_servo = hip_pitch,"))
    (d,) = caught.value.diagnostics
    assert "'place' moves the foot of leg 'main' with 'leg.roll_servo'" in d.message
    assert "(servo 'hip_pitch', on coordinate 'hip_y'), which 'leg.hip_servo'" in d.message
    assert "make the alias 'roll_servo' of leg 'main' name a servo on another" in d.message
    assert "in action 'place_foot_3d'" in d.message


def test_a_servo_named_twice_is_told_at_the_second(tmp_path: Path) -> None:
    text = MONOPOD.read_text(encoding="utf-8")
    line = "  state LOADING     on touchdown(active):       free_hip_3d(active)"
    assert line in text
    place = "; place active at (x = 0 m, y = 0 m) using hip_pitch, hip_pitch"
    with pytest.raises(LegError) as caught:
        _check(tmp_path, text.replace(line, line + place))
    (d,) = caught.value.diagnostics
    assert "with 'hip_pitch' (servo 'hip_pitch', on coordinate 'hip_y')" in d.message
    assert "name a servo on another of the leg's coordinates" in d.message
    col = text.replace(line, line + place).splitlines()[d.span.line - 1].rindex("hip_pitch")
    assert d.span.col == col + 1
