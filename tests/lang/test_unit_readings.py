"""'--set kp=150mN/rad' was told only "it has no prefix 'm' (milli) ... write '0.15 N/rad'"
(kp is N*m/rad: the suggestion then failed, and its own fix was 1000 times weaker than the
metre-newton meant); an 'm' run into a symbol is read both ways, and only the way of the
dimension wanted where that is known. 'm*s^(-1)' was told its power is not whole."""

from __future__ import annotations

import pytest

from legdsl.lang.errors import LegError
from legdsl.lang.parser import parse
from legdsl.lang.units import KINDS, unknown_unit
from legdsl.pipeline.settings import UsageError, parse_given

CREATURE = """\
creature a {
  planar
  gravity 9.81 m/s^2
  body trunk free { mass 5 kg  inertia 0.03 kg*m^2 }
  body leg on trunk via revolute hip { mass 1 kg  inertia 0.01 kg*m^2 }
  actuator hip_servo on hip servo(kp = 150 N*m/rad, kv = 6 N*m*s/rad)
}
"""


def _file_error(old: str, new: str) -> str:
    with pytest.raises(LegError) as caught:
        parse(CREATURE.replace(old, new), "a.leg")
    return caught.value.diagnostics[0].message


def _option_error(value: str) -> str:
    with pytest.raises(UsageError) as caught:
        parse_given(value, "--set")
    return str(caught.value)


def test_an_m_run_into_a_symbol_is_read_as_milli_and_as_metres() -> None:
    both = "write '0.15 N/rad', or '150 N*m/rad' if the 'm' meant metres"
    assert both in unknown_unit("mN/rad", "150")
    assert both in _option_error("150mN/rad")
    assert both in _file_error("kp = 150 N*m/rad", "kp = 150 mN/rad")
    assert "(or in N*m/rad if the 'm' meant metres)" in unknown_unit("mN/rad")


def test_the_wanted_dimension_keeps_only_its_reading() -> None:
    torque_gain = unknown_unit("mN/rad", "150", KINDS["angular stiffness"][0])
    assert torque_gain.endswith(": write '150 N*m/rad'")
    assert "0.15" not in torque_gain
    force = unknown_unit("mN", "5", KINDS["force"][0])
    assert force.endswith(": write '0.005 N'")
    assert "metres" not in force


def test_a_whole_power_in_parentheses_is_told_the_parentheses() -> None:
    said = "a unit takes no parentheses, around a power neither: write"
    assert f"{said} 'm*s^-1', not 'm*s^(-1)'" in _option_error("1m*s^(-1)")
    assert f"{said} 'm/s^2', not 'm/s^(2)'" in _file_error("m/s^2", "m/s^(2)")
    assert "not a whole number" in unknown_unit("m^(1/2)")


def test_an_option_that_knows_its_dimension_suggests_only_its_reading() -> None:
    with pytest.raises(UsageError) as caught:
        parse_given("150mN/rad", "--set kp", KINDS["angular stiffness"][0])
    assert str(caught.value).endswith(": write '150 N*m/rad'")
