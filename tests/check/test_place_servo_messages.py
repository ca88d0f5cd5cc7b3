"""What ``place ... using`` is told when its servos are wrong, from an outside user's hexapod:
a spring given as a servo was told only "'m.spring' is not a servo actuator", naming none of
the servos the leg has; three goals with two servos were told to write one goal and one servo
or two and two, though the message itself took a z goal. Now the first names the leg's other
servo on its joints (or says the leg has none, and how to declare one), the second the statement
that pairs each goal with a servo, or, the leg having no other servo, the goal to leave out."""

from __future__ import annotations

from pathlib import Path

import pytest

from legdsl.check.source import check_file
from legdsl.lang.errors import LegError

HEXAPOD_LIKE = """creature two {
  spatial
  body trunk free {
    mass 8 kg  inertia (0.08, 0.3, 0.35) kg*m^2  shape box(0.6 m, 0.25 m, 0.1 m)
    initial z = 0.53 m
  }
  template leg(S, HIP) {
    body thigh_S on trunk via gimbal hip_S at HIP {
      length 0.2 m  com 0.1 m  mass 0.6 kg  inertia (0.003, 0.003, 0.0001) kg*m^2
    }
    body shank_S on thigh_S via prismatic leg_S at tip {
      length 0.3 m  com 0.15 m  mass 0.3 kg  inertia (0.0025, 0.0025, 0.00002) kg*m^2
    }
    contact toe_S on shank_S at tip
    leg S {
      joints hip_S, leg_S
      foot toe_S
      alias spring = leg_S_spring, hip_servo = hip_S_pitch, roll_servo = hip_S_roll
    }
    actuator leg_S_spring on leg_S spring(k = 4000 N/m, b = 20 N*s/m, rest = 0 m)
    actuator hip_S_roll on hip_S_x servo(kp = 150 N*m/rad, kv = 5 N*m*s/rad)
    actuator hip_S_pitch on hip_S_y servo(kp = 150 N*m/rad, kv = 5 N*m*s/rad)
  }
  instance lf = leg(S = lf, HIP = (0.25 m, 0.1 m, 0 m))
  instance rr = leg(S = rr, HIP = (-0.25 m, -0.1 m, 0 m))
  ground { normal spring(k = 2e4 N/m, b = 250 N*s/m)  tangent spring(k = 1.2e4 N/m) }
}
controller walk {
  roles active = (lf), idle = (rr)
  action aim(t) {
    each m in t {
      PLACE
    }
  }
  table {
    state FLIGHT on liftoff(active): swap active idle; aim(active)
    state STANCE on touchdown(active): active.spring.rest = 0 m
  }
}
"""


def _told(tmp_path: Path, place: str) -> str:
    leg = tmp_path / "two.leg"
    leg.write_text(HEXAPOD_LIKE.replace("PLACE", place), encoding="utf-8")
    with pytest.raises(LegError) as caught:
        check_file(leg)
    return str(caught.value)


def test_the_place_as_written_passes(tmp_path: Path) -> None:
    leg = tmp_path / "two.leg"
    place = "place m at (x = 0.1 m, y = 0 m) using m.hip_servo, m.roll_servo"
    leg.write_text(HEXAPOD_LIKE.replace("PLACE", place), encoding="utf-8")
    assert check_file(leg)


def test_a_spring_for_a_servo_is_told_the_legs_other_servo(tmp_path: Path) -> None:
    told = _told(tmp_path, "place m at (x = 0.1 m, y = 0 m) using m.hip_servo, m.spring")
    assert (
        "'m.spring' is a spring actuator, not a servo; name the leg's other servo on its "
        "joints, m.roll_servo, instead"
    ) in told


def test_a_body_for_both_servos_is_told_the_legs_servos(tmp_path: Path) -> None:
    told = _told(tmp_path, "place m at (x = 0.1 m) using trunk")
    assert (
        "'trunk' is a body, not a servo; name one of the leg's other servos on its joints "
        "(m.hip_servo, m.roll_servo)"
    ) in told


def test_a_leg_with_no_servo_is_told_how_to_declare_one(tmp_path: Path) -> None:
    text = HEXAPOD_LIKE.replace(
        "hip_S_pitch on hip_S_y servo(kp = 150 N*m/rad, kv = 5 N*m*s/rad)",
        "hip_S_pitch on hip_S_y torque(max = 80 N*m)",
    )
    text = text.replace(
        "hip_S_roll on hip_S_x servo(kp = 150 N*m/rad, kv = 5 N*m*s/rad)",
        "hip_S_roll on hip_S_x torque(max = 80 N*m)",
    )
    leg = tmp_path / "two.leg"
    leg.write_text(text.replace("PLACE", "place m at (x = 0.1 m) using m.hip_servo"), "utf-8")
    with pytest.raises(LegError) as caught:
        check_file(leg)
    assert (
        "'m.hip_servo' is a torque actuator, not a servo; leg 'lf' has no servo on its joints "
        "(hip_lf, leg_lf): declare one on a coordinate of them, as in 'actuator hip_lf_x_servo "
        "on hip_lf_x servo(kp = ..., kv = ...)'"
    ) in str(caught.value)


def test_three_goals_two_servos_is_told_the_goal_to_leave_out(tmp_path: Path) -> None:
    told = _told(
        tmp_path, "place m at (x = 0.1 m, y = 0 m, z = -0.4 m) using m.hip_servo, m.roll_servo"
    )
    assert (
        "'place' needs one servo per goal, in the goals' order: 3 goals (x, y, z) and 2 servos "
        "(m.hip_servo, m.roll_servo); the leg has no other servo for z on its joints: leave "
        "out the goal z, 'place m at (x = ..., y = ...) using m.hip_servo, m.roll_servo'"
    ) in told


def test_two_goals_one_servo_is_told_the_servo_to_add(tmp_path: Path) -> None:
    told = _told(tmp_path, "place m at (x = 0.1 m, y = 0 m) using m.hip_servo")
    assert (
        "2 goals (x, y) and 1 servo (m.hip_servo); name a servo for y too, 'place m at "
        "(x = ..., y = ...) using m.hip_servo, m.roll_servo', or leave out the goal y, "
        "'place m at (x = ...) using m.hip_servo'"
    ) in told


def test_one_goal_two_servos_is_told_both_ways(tmp_path: Path) -> None:
    told = _told(tmp_path, "place m at (x = 0.1 m) using m.hip_servo, m.roll_servo")
    assert (
        "1 goal (x) and 2 servos (m.hip_servo, m.roll_servo); give each servo a goal, "
        "'place m at (x = ..., y = ...) using m.hip_servo, m.roll_servo', or leave out "
        "m.roll_servo, 'place m at (x = ...) using m.hip_servo'"
    ) in told


def test_more_servos_than_axes_is_told_the_most_goals(tmp_path: Path) -> None:
    told = _told(
        tmp_path,
        "place m at (x = 0.1 m) using m.hip_servo, m.roll_servo, m.hip_servo, m.roll_servo",
    )
    assert "(a place sets at most 3 goals, x, y, z)" in told
