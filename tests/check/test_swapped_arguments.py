"""Two arguments of a call given in each other's places (kp and kv) are told as swapped, at
the call, and a dimension no kind names is told in newtons as people write it (N*m*s)."""

from __future__ import annotations

from pathlib import Path

import pytest

from legdsl.check.source import check_model
from legdsl.lang.errors import LegError
from legdsl.lang.units import describe

ROOT = Path(__file__).resolve().parents[2]
HOPPER = (ROOT / "creatures" / "hopper.leg").read_text()
SERVO = "servo_pitch(active, body, 0 deg, kp, kv)"


def _messages(tmp_path: Path, text: str) -> list[tuple[int, int, str]]:
    path = tmp_path / "hopper.leg"
    path.write_text(text)
    with pytest.raises(LegError) as info:
        check_model(path)
    return [(d.span.line, d.span.col, d.message) for d in info.value.diagnostics]


def test_kp_and_kv_given_in_each_others_places_are_told_as_swapped(tmp_path: Path) -> None:
    """Told as 'both sides of '+' must have one dimension, but they are a quantity in
    kg*m^2*s^-1 and a quantity in kg*m^2*s^-3', inside the action."""
    assert HOPPER.count(SERVO) == 2
    messages = _messages(
        tmp_path, HOPPER.replace(SERVO, "servo_pitch(active, body, 0 deg, kv, kp)")
    )
    told = (
        "arguments 'kp' (4th) and 'kv' (5th) of action 'servo_pitch' look swapped: 'kv' is "
        "an angular damping (N*m*s/rad) and 'kp' an angular stiffness (N*m/rad), but the "
        "action uses 'kp' as an angular stiffness (N*m/rad) and 'kv' as an angular damping "
        "(N*m*s/rad) (stdlib/raibert.leg:86:25); write them the other way round: 'kp, kv'"
    )
    assert messages == [(84, 82, told), (85, 145, told)]


def test_two_arguments_whose_swap_does_not_help_are_not_told_as_swapped(tmp_path: Path) -> None:
    """kv for kp and a torque for kv: no exchange fits, the mistake is told in the action,
    its dimensions in newtons."""
    messages = _messages(
        tmp_path, HOPPER.replace(SERVO, "servo_pitch(active, body, 0 deg, kv, 1 N*m)")
    )
    assert {m for _, _, m in messages} == {
        "both sides of '+' must have one dimension, but they are a quantity in N*m*s and a "
        "quantity in N*m*rad/s; write like with like, both in N*m*s or both in N*m*rad/s: one "
        "of them is not the value meant (in action 'servo_pitch', stdlib/raibert.leg:86:25, "
        "called here)"
    }


def test_a_dimension_no_kind_names_is_told_in_newtons() -> None:
    assert describe((1, 2, -1, 0)) == "N*m*s"
    assert describe((1, 2, -3, 0)) == "N*m/s"
    assert describe((1, 0, -1, -1)) == "N*s/m/rad"
    assert describe((1, -1, 0, 0)) == "kg*m^-1"  # no time in it: no newton
