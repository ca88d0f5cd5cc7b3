"""A frequency where an angular velocity is asked for ('set w = 1 Hz' for an input in
deg/s) is told as turns a second, converted, not as '1 deg/s', 360 times too slow
(lang.turning, for the scene's and --set's messages)."""

from __future__ import annotations

import math

import pytest

from legdsl.lang.turning import ANGULAR_VELOCITY, FREQUENCY, as_turning
from legdsl.lang.units import KINDS


@pytest.mark.parametrize(
    ("written", "hertz", "unit", "told"),
    [
        ("1 Hz", 1.0, "deg/s", "1 Hz is one turn a second: write 360 deg/s (or 1 rev/s)"),
        ("2.5 Hz", 2.5, "rad/s", "2.5 Hz is 2.5 turns a second: write 15.708 rad/s (or 2.5 rev/s)"),
        ("1 Hz", 1.0, "rev/s", "1 Hz is one turn a second: write 1 rev/s"),
    ],
)
def test_a_frequency_for_an_angular_velocity_is_converted(
    written: str, hertz: float, unit: str, told: str
) -> None:
    assert as_turning(written, hertz, FREQUENCY, ANGULAR_VELOCITY, unit) == told


def test_an_angular_velocity_for_a_frequency_is_converted() -> None:
    told = as_turning("360 deg/s", 2 * math.pi, ANGULAR_VELOCITY, FREQUENCY, "Hz")
    assert told == "360 deg/s is one turn a second: write 1 Hz"


def test_other_dimensions_are_not_turning() -> None:
    angle, time = KINDS["angle"][0], KINDS["time"][0]
    assert as_turning("1 rad", 1.0, angle, ANGULAR_VELOCITY, "rad/s") is None
    assert as_turning("1 Hz", 1.0, FREQUENCY, time, "s") is None
    assert as_turning("1 Hz", 1.0, FREQUENCY, ANGULAR_VELOCITY, "m/s") is None
