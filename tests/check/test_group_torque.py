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
