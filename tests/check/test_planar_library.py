"""The library's planar runner actions (the end of stdlib/raibert.leg): a planar creature calls
them with a group role or a single leg, where their 3D counterparts read the yaw or a roll
servo and are refused (tests/bad/ctl_planar_calls_trim_step_speed.leg names the planar one)."""

from __future__ import annotations

from pathlib import Path

import pytest

from legdsl.check.source import check_model
from legdsl.lang.errors import LegError
from legdsl.lower.control import lower_controller

ROOT = Path(__file__).resolve().parents[2]
# a planar walker with two telescoping legs, `left` and `right`
WALKER = (ROOT / "tests" / "bad" / "ctl_one_leg_torque_on_group.leg").read_text()
CREATURE = WALKER.split("use raibert")[0]
TRIMS = (
    "trim_step_speed_planar(1 m/s, 0.5, 0.3 m/s); "
    "trim_step_speed_planar_from(1 m/s, 0.5, 0.3 m/s, 0 m/s); stride_speed_planar(1, 1 m/s)"
)
SWING = "50 N*m/rad, 2 N*m*s/rad"


def _lowered(tmp_path: Path, flight: str, stance: str):  # type: ignore[no-untyped-def]
    path = tmp_path / "walker.leg"
    path.write_text(
        f"{CREATURE}use raibert\ncontroller run {{\n  roles pair = (left, right)\n  table {{\n"
        f"    state FLIGHT on liftoff(pair): {flight}\n"
        f"    state STANCE on touchdown(pair): {stance}\n  }}\n}}\n"
    )
    model = check_model(path)
    return lower_controller(model, model.controller("run"))


@pytest.mark.parametrize("leg", ["pair", "left"])
def test_a_planar_creature_calls_the_planar_runner_actions(tmp_path: Path, leg: str) -> None:
    for servo in (
        f"servo_pitch_shared({leg}, trunk, 0 deg, 150 N*m/rad, 10 N*m*s/rad, {SWING})",
        f"servo_pitch_rate_shared({leg}, trunk, -2 rad/s, 10 N*m*s/rad, {SWING})",
    ):
        low = _lowered(tmp_path, f"{TRIMS}; place_feet_planar({leg}, 1 m/s, 0.05 s, 0.2 s)", servo)
        records = {name for name, _ in low.bodies[(0, 0)].records}
        assert {"step_speed", "speed_trim", "lifted", "lifted_x", "stride_speed"} <= records
        assert not records & {"lifted_y", "stride_y0", "stride_y1"}  # no sideways travel


def test_the_shared_servo_splits_the_torque_among_the_feet_down(tmp_path: Path) -> None:
    stance = f"servo_pitch_shared(pair, trunk, 0 deg, 150 N*m/rad, 10 N*m*s/rad, {SWING})"
    low = _lowered(tmp_path, "swing(pair, 50 N*m/rad, 2 N*m*s/rad)", stance)
    settings = {(s.actuator, s.key): str(s.value) for s in low.bodies[(0, 1)].settings}
    share = "leg_left_touching/Max(1.0, leg_left_touching + leg_right_touching)"
    assert settings[("left_motor", "force")] == (
        f"150.0*body_trunk_pitch*{share} + 10.0*body_trunk_pitch_rate*{share}"
    )
    assert settings[("left_servo", "kp")] == "50.0 - 50.0*leg_left_touching"  # swing in the air


def test_the_3d_step_trim_names_the_planar_one(tmp_path: Path) -> None:
    with pytest.raises(LegError) as caught:
        _lowered(tmp_path, "trim_step_speed(trunk, 1 m/s, 0.5, 0.3 m/s)", "free_hip(pair)")
    (d,) = caught.value.diagnostics
    assert "a planar creature's is 'trim_step_speed_planar'" in d.message
