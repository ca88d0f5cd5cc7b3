"""--path of a directory was told "unexpected '/'", --path 'circle(' "unexpected end of the
file" (no file was given), and --set hip_motor.torque=... of a torque(...) actuator "a
force's settings are force". Each now says what it is and what to write."""

from __future__ import annotations

from pathlib import Path

import pytest
from conftest import CREATURES

from legdsl.lang.errors import LegError, UsageError
from legdsl.pipeline.path_option import parse_path_option
from legdsl.pipeline.session import RunSession
from legdsl.pipeline.settings import sort_settings


def test_a_directory_given_as_the_path_is_said_to_be_one(tmp_path: Path) -> None:
    with pytest.raises(UsageError, match=r"is a directory; give a file of 'x,y' lines, or a shape"):
        parse_path_option(str(tmp_path))


def test_a_shape_cut_short_ends_the_path_value_not_a_file() -> None:
    with pytest.raises(LegError) as e:
        parse_path_option("circle(")
    assert "unexpected end of the --path value" in str(e.value)
    assert "end of the file" not in str(e.value)


def test_a_torque_actuators_setting_is_named_for_a_torque(generated: Path) -> None:
    model = RunSession.from_file(CREATURES / "hopper.leg", generated=generated).model
    with pytest.raises(UsageError) as e:
        sort_settings(["hip_motor.torque=1N*m"], model, None)
    said = str(e.value)
    assert "a torque actuator's one setting is its torque, named 'force'" in said
    assert "write --set hip_motor.force=VALUE (N*m)" in said
