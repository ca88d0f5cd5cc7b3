"""An unknown name given to an action is told as what the action reads it as: a body the
creature lacks ("creature 'hopper' has no body 'torso' (its bodies: ...)"), a path to declare
with 'path NAME', not a parameter to declare (a number cannot stand for a body or a path)."""

from __future__ import annotations

from pathlib import Path

import pytest

from legdsl.check.source import check_file
from legdsl.lang.errors import LegError

ROOT = Path(__file__).resolve().parents[2]
CREATURE = (ROOT / "tests" / "bad" / "ctl_dim_comparison.leg").read_text().split("controller")[0]
ACTIONS = """action lean(leg, body) { leg.hip_servo.setpoint = body.pitch }
action lean_on(leg, b) { lean(leg, b) }
action follow(leg, route) { leg.hip_servo.setpoint = route.lateral * 1 rad/m }
action stiffen(leg, k) { leg.hip_servo.kp = k }
"""


def _messages(tmp_path: Path, row: str, declared: str = "") -> list[str]:
    path = tmp_path / "f.leg"
    path.write_text(
        CREATURE + ACTIONS + "controller hop {\n" + declared + "  table {\n"
        f"    state FLIGHT on liftoff(main): {row}\n  }}\n}}\n"
    )
    with pytest.raises(LegError) as info:
        check_file(path)
    return [d.message for d in info.value.diagnostics]


BODY = "creature 'hopper' has no body 'torso' (its bodies: trunk, thigh, shank)"


@pytest.mark.parametrize("row", ["lean(main, torso)", "lean_on(main, torso)"])
def test_a_body_given_to_an_action(tmp_path: Path, row: str) -> None:
    """Read by the action, or by one it passes it on to; was: declare it, as in 'param
    torso = ...'."""
    assert _messages(tmp_path, row) == [BODY]


def test_a_body_near_one_of_the_creatures(tmp_path: Path) -> None:
    assert _messages(tmp_path, "lean(main, trunks)") == [
        "creature 'hopper' has no body 'trunks' (its bodies: trunk, thigh, shank); "
        "did you mean 'trunk'?"
    ]


def test_a_path_given_to_an_action(tmp_path: Path) -> None:
    assert _messages(tmp_path, "follow(main, track)") == [
        "unknown name 'track': action 'follow' takes a path there (it reads its lateral); "
        "declare one with 'path track'"
    ]


def test_a_misspelt_path_is_told_the_one_declared(tmp_path: Path) -> None:
    messages = _messages(tmp_path, "follow(main, rout)", "  path route\n")
    assert messages == ["unknown name 'rout'; did you mean 'route'?"]


def test_a_number_given_to_an_action_is_still_a_parameter_to_declare(tmp_path: Path) -> None:
    assert _messages(tmp_path, "stiffen(main, kq)") == [
        "unknown name 'kq': not a part of the creature, nor an input, parameter, signal, role, "
        "path or record of the controller; declare it, as in 'param kq = ...'"
    ]
