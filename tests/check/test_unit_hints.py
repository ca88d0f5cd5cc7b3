"""Each mistake of units in a controller says what to write, and what it says checks.

An outside user's: ``clamp(ramp, -1, 1 rad)`` (min() said to write the unit, clamp() with a
negative number did not), ``w > 1 Hz`` against rad/s, ``sqrt(1 rad)``, ``sin()`` of a length,
a member of a number, ``g(1)`` ("unknown function 'g'") all stopped at the mistake."""

from __future__ import annotations

from pathlib import Path

import pytest

from legdsl.check.source import check_file
from legdsl.lang.errors import LegError

CREATURE = """
creature arms {
  planar
  gravity 0 m/s^2
  body base fixed at (0 m, 2 m) { mass 1 kg  inertia 0.1 kg*m^2  length 0.1 m }
  body a on base via revolute j { length 0.5 m  com 0.25 m  mass 1 kg  inertia 0.02 kg*m^2 }
  actuator sa on j servo(kp = 2000 N*m/rad, kv = 60 N*m*s/rad)
}
controller c {
  input w = 30 deg/s
  param p = 2 deg
  signal ramp = integral(w)
  table { state A on time >= 0 s: sa.setpoint = VALUE }
}
"""


def messages(tmp_path: Path, value: str) -> list[str]:
    path = tmp_path / "arms.leg"
    path.write_text(CREATURE.replace("VALUE", value))
    try:
        check_file(path)
    except LegError as e:
        return [d.message for d in e.diagnostics]
    return []


@pytest.mark.parametrize(
    ("value", "told", "fixed"),
    [
        (
            "clamp(ramp, -1, 1 rad)",
            "; write the number with its unit, as in '-1 deg'",
            "clamp(ramp, -1 deg, 1 rad)",
        ),
        (
            "select(w > 1 Hz, 1 rad, 0 rad)",
            "; Hz counts cycles per second, with no angle in it: write a turning rate as an "
            "angle per second, 1 Hz being '1 rev/s' (= '360 deg/s' = '2 * pi * 1 rad/s')",
            "select(w > 1 rev/s, 1 rad, 0 rad) + select(w > 360 deg/s, 1 rad, 0 rad)"
            " + select(w > 2 * pi * 1 rad/s, 1 rad, 0 rad)",
        ),
        (
            "1 rad * sqrt(p)",
            "; take it of a plain number, as in 'sqrt(p / (1 deg))', or of a square, as in "
            "'sqrt(x ^ 2)'",
            "1 rad * sqrt(p / (1 deg))",
        ),
        (
            "1 rad * sin(a.length)",
            "; make it an angle or a plain number (read as radians), as in 'sin(a.length / (1 m))'",
            "1 rad * sin(a.length / (1 m))",
        ),
        (
            "1 rad * exp(a.length)",
            "; make it a plain number, as in 'exp(a.length / (1 m))'",
            "1 rad * exp(a.length / (1 m))",
        ),
        (
            "select(a.x > 1 s, 1 deg, 0 deg)",
            "; a time (s) times a velocity (m/s) (as '1 m/s') makes a length (m): multiply by "
            "what relates them, or write like with like",
            "select(a.x > 1 s * 1 m/s, 1 deg, 0 deg)",
        ),
        (
            "p.x",
            "a number has no member 'x': members are read of the creature's parts, legs, roles, "
            "com, terrain and paths, as in 'com.x' (docs/language.md lists each one's)",
            "com.x * 1 deg/m",
        ),
        (
            "p * g(1)",
            ": 'g' is a built-in value, not a function; to multiply by it, write 'g * (...)'",
            "p * g * (1 s^2/m)",
        ),
    ],
)
def test_a_unit_mistake_says_what_to_write(
    tmp_path: Path, value: str, told: str, fixed: str
) -> None:
    (message,) = messages(tmp_path, value)
    assert message.endswith(told)
    assert messages(tmp_path, fixed) == []  # what it says to write checks


def test_a_creatures_value_given_as_a_name_says_to_write_the_number(tmp_path: Path) -> None:
    path = tmp_path / "arms.leg"
    path.write_text(
        CREATURE.replace("VALUE", "p").replace("revolute j {", "revolute j { initial j = pi ")
    )
    with pytest.raises(LegError) as info:
        check_file(path)
    (told,) = [d.message for d in info.value.diagnostics]
    assert told == (
        "the initial j must be a number with a unit of deg: write the one number itself, as in "
        "'0.5 deg'"
    )
