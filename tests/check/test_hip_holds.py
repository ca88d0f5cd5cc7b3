"""A servo that turns a body through a hip is given the body the hip holds (hip_holds)."""

from __future__ import annotations

from pathlib import Path

import pytest

from legdsl.check.source import check_model
from legdsl.lang.errors import LegError

ROOT = Path(__file__).resolve().parents[2]
BAD = (ROOT / "tests" / "bad" / "ctl_servo_body_hip_does_not_hold.leg").read_text()
HEAD = "  body head on trunk via fixed neck { mass 0.5 kg  inertia 0.001 kg*m^2 }\n"


def _check(tmp_path: Path, text: str) -> None:
    path = tmp_path / "hopper.leg"
    path.write_text(text)
    check_model(path)


def test_the_body_the_hip_holds_checks(tmp_path: Path) -> None:
    _check(tmp_path, BAD.replace("servo_pitch(main, thigh", "servo_pitch(main, trunk"))


def test_a_body_welded_to_it_is_held_too(tmp_path: Path) -> None:
    text = BAD.replace("  contact toe", HEAD + "  contact toe")
    _check(tmp_path, text.replace("servo_pitch(main, thigh", "servo_pitch(main, head"))


def test_a_body_of_the_leg_is_told_at_the_argument(tmp_path: Path) -> None:
    with pytest.raises(LegError) as caught:
        _check(tmp_path, BAD)
    (d,) = caught.value.diagnostics
    assert (d.span.line, d.span.col) == (18, 56)
    assert "the hip of leg 'main' holds body 'trunk'; did you mean 'trunk'?" in d.message
