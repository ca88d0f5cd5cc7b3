"""A one-leg library torque given a group role is told; shared per member it checks."""

from __future__ import annotations

from pathlib import Path

import pytest

from legdsl.check.source import check_model
from legdsl.lang.errors import LegError

ROOT = Path(__file__).resolve().parents[2]
BAD = (ROOT / "tests" / "bad" / "ctl_one_leg_torque_on_group.leg").read_text()
CALL = "servo_pitch(pair, trunk, 0 deg, 150 N*m/rad, 10 N*m*s/rad)"


def _check(tmp_path: Path, call: str) -> None:
    path = tmp_path / "walker.leg"
    path.write_text(BAD.replace(CALL, call))
    check_model(path)


def test_the_group_is_told_at_the_argument(tmp_path: Path) -> None:
    with pytest.raises(LegError) as caught:
        _check(tmp_path, CALL)
    (d,) = caught.value.diagnostics
    assert (d.span.line, d.span.col) == (26, 50)
    assert "each member's 'hip_motor' would apply the whole torque, 2 times" in d.message


def test_the_torque_shared_per_member_checks(tmp_path: Path) -> None:
    share = "max(pair.feet_down, 1)"
    _check(
        tmp_path,
        f"each m in pair {{ servo_pitch(m, trunk, 0 deg, 150 N*m/rad / {share}, "
        f"10 N*m*s/rad / {share}) }}",
    )


def test_a_group_set_to_no_torque_checks(tmp_path: Path) -> None:
    _check(tmp_path, "free_hip(pair)")  # the same (zero) torque on every member is meant


def test_the_users_own_assignment_through_the_group_checks(tmp_path: Path) -> None:
    # documented: assigning through a group sets every member's (language.md, Virtual legs)
    _check(tmp_path, "pair.hip_motor.force = 50 N*m/rad * trunk.pitch")


@pytest.mark.parametrize(
    "call",
    ["hop_apex(pair, 0 m, 1 m, 0 m, 5 cm, 1)", "hop_height(pair, 0 m, 1 m, 2 cm, 0.2)"],
)
def test_one_legs_spring_energy_given_a_group_is_told(tmp_path: Path, call: str) -> None:
    # the apex predicted from one spring's energy: a pair asked for 0.85 m rose to 1.02 m
    with pytest.raises(LegError) as caught:
        _check(tmp_path, call)
    (d,) = caught.value.diagnostics
    assert (d.span.line, d.span.col) == (26, 38 + call.index("pair"))
    assert "'pair' is a group of 2 legs (left, right)" in d.message
    assert "the 2 members' store 2 times it" in d.message
    assert "'hop_height_virtual'" in d.message


@pytest.mark.parametrize(
    "call",
    [
        "hop_apex(left, 0 m, 1 m, 0 m, 5 cm, 1)",  # one leg: what it is for
        "hop_height_virtual(pair, 0 m, 1 m, 2 cm, 0.2, 0 m, 5 cm)",  # counts feet_down
        "hop_height_apex(1 m, 2 cm, 0.2, 0.05, 0 m, 5 cm); relax(pair, thrust_stroke)",
    ],
)
def test_spring_energy_counted_per_member_checks(tmp_path: Path, call: str) -> None:
    _check(tmp_path, call)
