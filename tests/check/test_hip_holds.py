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


def test_a_neck_may_level_the_head_from_the_heads_own_pitch(tmp_path: Path) -> None:
    """The rule is the hips': a hip holds the body its leg hangs from because the foot is
    planted, but a neck or a tail holds its free end, so a neck motor reading the head it
    turns is right (run 8 s, this kangaroo's head stays within 5 deg of level, as the
    shipped neck servo keeps it)."""
    text = (ROOT / "creatures" / "kangaroo.leg").read_text(encoding="utf-8")
    servo = "  actuator neck_servo on neck servo("
    level = "    neck_servo.setpoint = -trunk.pitch\n"
    assert servo in text and level in text
    text = text.replace(servo, "  actuator neck_motor on neck torque(max = 5 N*m)\n" + servo)
    text = text.replace(
        level,
        "    neck_servo.kp = 0 N*m/rad; neck_servo.kv = 0 N*m*s/rad;\n"
        "    neck_motor.force = -10 N*m/rad * head.pitch - 0.3 N*m*s/rad * head.pitch_rate\n",
    )
    _check(tmp_path, text)


SPINE = (
    "  body rear on trunk via revolute spine at (-0.2 m, 0 m) { mass 1 kg  inertia 0.01 kg*m^2 }\n"
)


def _on_a_spine(servoed: str) -> str:
    """The hopper's leg hung from a rear half on a spine hinge, the root being the front half."""
    text = BAD.replace("  body thigh on trunk", SPINE + "  body thigh on rear")
    return text.replace("servo_pitch(main, thigh", f"servo_pitch(main, {servoed}")


def test_a_trunk_in_two_halves_is_held_by_the_hips_of_either(tmp_path: Path) -> None:
    """A spine: the hip on the rear half turns the front half (the root) through the spine's
    joint, so eq. (4) from the root's pitch is the shipped gaits' posture servo for a creature
    whose rear legs hang from a rear half; it was told "cannot hold ... holds body 'rear'"."""
    _check(tmp_path, _on_a_spine("trunk"))
    _check(tmp_path, _on_a_spine("rear"))


def test_a_body_below_the_hip_is_still_told_on_a_spine(tmp_path: Path) -> None:
    with pytest.raises(LegError) as caught:
        _check(tmp_path, _on_a_spine("shank"))
    (d,) = caught.value.diagnostics
    assert "the hip of leg 'main' holds body 'rear'; did you mean 'rear'?" in d.message
