"""``legdsl run --set``: each value is checked against the dimension its .leg file declares.

Through the command line (exit status 2, a message naming the unit to write, no traceback) and
through ``legdsl.pipeline.settings`` for the cases that need no simulation.
"""

from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import pytest
from conftest import CREATURES, ROOT, shipped_model

from legdsl.cli import main
from legdsl.lang.errors import UsageError
from legdsl.lang.units import KINDS, a_kind, parse_unit, si_unit, unit_for
from legdsl.pipeline.settings import sort_settings

KANGAROO = str(CREATURES / "kangaroo.leg")


def _run(argv: list[str], generated: Path, out: Path) -> list[str]:
    return [
        "run",
        KANGAROO,
        "--controller",
        "hop",
        *argv,
        "--time",
        "0.2",
        "--generated",
        str(generated),
        "--out",
        str(out),
    ]


@pytest.mark.parametrize(
    ("setting", "says"),
    [
        ("speed=2kg", "speed is a velocity (m/s), but 2kg is a mass (kg); write e.g. speed=2m/s"),
        ("speed=2", "speed is a velocity (m/s); give its unit, e.g. speed=2m/s"),
        ("speed=5deg", "speed is a velocity (m/s), but 5deg is an angle (deg)"),
        ("speed=3m/s@4", "the time after '@' is in seconds; give its unit, e.g. @4s"),
        ("speed=3m/s@4kg", "the time after '@' is in seconds, but 4kg is a mass (kg)"),
        ("k_trim=0.1m", "k_trim is dimensionless, but 0.1m is a length (m); write a bare number"),
        ("stroke=10", "stroke is an angle (deg); give its unit, e.g. stroke=10deg"),
        ("hip_servo.setpoint=10kg", "hip_servo.setpoint is an angle (deg), but 10kg is a mass"),
        ("hip_servo.setpoint=10", "hip_servo.setpoint is an angle (deg); give its unit"),
        # the user's unit per second, not rad/s (57 times as fast)
        (
            "ramp=60deg",
            "ramp is an angular velocity (deg/s), but 60deg is an angle (deg); write e.g. ramp=60deg/s",
        ),
        ("speed=2cm", "speed is a velocity (m/s), but 2cm is a length (m); write e.g. speed=2cm/s"),
        (
            "accel=2m/s",
            "accel is an acceleration (m/s^2), but 2m/s is a velocity (m/s); write e.g. accel=2m/s^2",
        ),
    ],
)
def test_a_value_in_the_wrong_unit_exits_2_naming_the_unit(
    setting: str,
    says: str,
    generated: Path,
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
) -> None:
    assert main(_run(["--set", setting], generated, tmp_path / "run")) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"legdsl: --set {setting}: {says}")
    assert err.count("\n") == 3  # the line, the option echoed and its caret; no traceback
    assert not (tmp_path / "run").exists()  # nothing simulated, nothing written


def test_no_traceback_from_the_installed_command(generated: Path, tmp_path: Path) -> None:
    argv = _run(["--set", "speed=2kg"], generated, tmp_path / "run")
    done = subprocess.run(
        [sys.executable, "-m", "legdsl", *argv], capture_output=True, text=True, cwd=ROOT
    )
    assert done.returncode == 2
    assert "Traceback" not in done.stderr + done.stdout
    assert "speed is a velocity (m/s)" in done.stderr and "write e.g. speed=2m/s" in done.stderr


def test_right_units_run_and_are_stored_in_si(
    generated: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    argv = ["--set", "speed=3m/s", "--set", "speed=4m/s@1s", "--set", "k_trim=0.1"]
    argv += ["--set", "stroke=9deg", "--set", "hip_servo.kp=0"]
    assert main(_run(argv, generated, tmp_path / "run")) == 0
    assert "Traceback" not in capsys.readouterr().err
    info = json.loads((tmp_path / "run" / "run.json").read_text())
    assert info["settings"]["inputs"] == {"speed": 3.0}
    assert info["settings"]["schedule"] == [{"t": 1.0, "input": "speed", "value": 4.0}]
    assert info["settings"]["params"]["k_trim"] == 0.1
    assert info["params"]["stroke"] == pytest.approx(0.15707963267948966)
    assert info["settings"]["actuators"] == {"hip_servo.kp": 0.0}


def test_a_declared_zero_with_a_unit_is_dimensioned() -> None:
    biped = shipped_model("biped")  # input heading = 0 deg
    (heading,) = [c for c in biped.controller("run").inputs if c.name == "heading"]
    assert heading.value == 0.0 and heading.dim == KINDS["angle"][0]
    with pytest.raises(UsageError, match=r"heading is an angle \(deg\); give its unit"):
        sort_settings(["heading=5"], biped, "run")
    assert sort_settings(["heading=90deg"], biped, "run").inputs["heading"] == pytest.approx(
        1.5707963267948966
    )


def test_a_bare_zero_is_taken_for_any_dimension() -> None:
    kangaroo = shipped_model("kangaroo")
    got = sort_settings(["speed=0", "hip_servo.setpoint=0", "speed=0@0"], kangaroo, "hop")
    assert got.inputs == {"speed": 0.0} and got.actuators == {"hip_servo.setpoint": 0.0}
    assert [(c.t, c.value) for c in got.schedule] == [(0.0, 0.0)]


def test_a_dimensionless_parameter_takes_a_bare_number() -> None:
    kangaroo = shipped_model("kangaroo")  # param k_trim = 0.05: no unit in the file
    (k_trim,) = [c for c in kangaroo.controller("hop").params if c.name == "k_trim"]
    assert k_trim.dim == (0, 0, 0, 0)
    assert sort_settings(["k_trim=0.2"], kangaroo, "hop").params == {"k_trim": 0.2}


def test_a_parameter_does_not_change_during_a_run() -> None:
    with pytest.raises(UsageError, match="k_trim is a parameter; only controller inputs change"):
        sort_settings(["k_trim=0.2@1s"], shipped_model("kangaroo"), "hop")


def test_a_setting_without_a_controller_names_the_controllers_that_have_it() -> None:
    """Without --controller, a name some controller declares says which one to choose; a
    misspelt name is not called a controller input, but corrected."""
    quadruped = shipped_model("quadruped")
    with pytest.raises(UsageError, match=r"'speed' is a controller input \(of trot, pace"):
        sort_settings(["speed=1m/s"], quadruped, None)
    with pytest.raises(UsageError, match=r"'kp_roll' is a controller parameter .* --controller"):
        sort_settings(["kp_roll=400N*m/rad"], quadruped, None)
    with pytest.raises(
        UsageError,
        match="no controller of creature 'quadruped' has an input or parameter 'sped'; "
        "did you mean 'speed'",
    ):
        sort_settings(["sped=1m/s"], quadruped, None)


def test_units_are_converted_to_si() -> None:
    got = sort_settings(["height=46cm", "speed=3.6km/s@500ms"], shipped_model("kangaroo"), "hop")
    assert got.inputs["height"] == pytest.approx(0.46)
    assert (got.schedule[0].t, got.schedule[0].value) == (pytest.approx(0.5), 3600.0)


def test_the_unit_to_write_for_every_dimension_parses_back() -> None:
    for dim, _ in list(KINDS.values())[1:]:  # all but "dimensionless", which has no unit
        assert parse_unit(si_unit(dim)) == (1.0, dim)
        assert parse_unit(unit_for(dim))[1] == dim
    assert si_unit((0, 0, 0, 0)) == unit_for((0, 0, 0, 0)) == ""
    odd = (0, -1, 0, 1)  # the kangaroo's k_height: rad per metre
    assert si_unit(odd) == unit_for(odd) == "rad/m"
    assert a_kind(odd) == "a quantity in rad/m"
    assert si_unit((1, 2, -2, -1)) == "kg*m^2/s^2/rad"
    assert si_unit((0, -1, 0, 0)) == "m^-1"
    assert a_kind(KINDS["angular velocity"][0]) == "an angular velocity (rad/s)"


def test_the_named_si_unit_reads_back_as_its_dimension() -> None:
    """``N*m/rad`` rather than ``kg*m^2/s^2/rad`` in reports, the same dimension and factor 1."""
    import itertools

    from legdsl.lang.units import named_si_unit, parse_unit

    assert named_si_unit((1, 2, -2, -1)) == "N*m/rad"
    assert named_si_unit((1, 0, -1, 0)) == "N*s/m"
    assert named_si_unit((1, 2, 0, 0)) == "kg*m^2"
    for dim in itertools.product((0, 1), (-2, -1, 0, 1, 2), (-3, -2, -1, 0, 1), (-1, 0, 1)):
        if any(dim):
            assert parse_unit(named_si_unit(dim)) == (1.0, dim), dim


@pytest.mark.parametrize(
    ("setting", "says"),
    [
        # as a file's '6 /s' is told: the unit opened by '/' (it got the list of unit symbols)
        ("--set=speed=6/s", "a unit starts with a symbol, not '/': write '6 s^-1' or '6 Hz'"),
        # a servo has a max, which only the file gives ('a servo has kp, kv, setpoint')
        ("--set=neck_servo.max=5N*m", "'max' is the .leg file's alone (change it there); a "
         "servo's settings are kp, kv, setpoint"),
    ],
)  # fmt: skip
def test_a_setting_written_as_elsewhere_is_told_how(
    setting: str, says: str, generated: Path, tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
) -> None:  # fmt: skip
    assert main(_run([setting], generated, tmp_path / "run")) == 2
    err = capsys.readouterr().err
    assert says in err and err.count("\n") == 1, err


# A parameter declared in radians, a gain in deg/m (an outside user's slips, repro 3).
_DECLARED = """\
creature c {
  planar
  body trunk free { mass 1 kg  inertia 0.01 kg*m^2  initial x = 0 m, z = 1 m }
  body leg on trunk via revolute hip { mass 1 kg  inertia 0.01 kg*m^2  length 0.5 m }
  actuator hip_servo on hip servo(kp = 10 N*m/rad)
}
controller hold {
  param bend = 0.7 rad
  param k_lean = 60 deg/m
  table { state A on time > 0 s: hip_servo.setpoint = bend + k_lean * trunk.z }
}
"""


@pytest.mark.parametrize(
    ("setting", "advice", "si"),
    [
        # a bare number is told in the unit the file declares it in, not deg (57 times off)
        ("bend=0.75", "give its unit, e.g. bend=0.75rad", 0.75),
        ("hold.bend=0.75", "give its unit, e.g. hold.bend=0.75rad", 0.75),
        # the user's unit over what it lacks of the declared one: 60deg/m, not 60rad/m
        ("k_lean=60deg", "write e.g. k_lean=60deg/m", math.radians(60)),
        ("k_lean=1rad", "write e.g. k_lean=1rad/m", 1.0),
        ("k_lean=2N", "write e.g. k_lean=2deg/m", math.radians(2)),
        # no declared unit for an actuator's setting: the usual one, and SI's
        ("hip_servo.setpoint=0.5", "hip_servo.setpoint=0.5deg or hip_servo.setpoint=0.5rad", 0.5),
    ],
)
def test_advice_keeps_the_unit_the_value_was_declared_in(
    setting: str, advice: str, si: float, tmp_path: Path
) -> None:
    from legdsl.check.source import check_model

    path = tmp_path / "c.leg"
    path.write_text(_DECLARED, encoding="utf-8")
    model = check_model(path)
    with pytest.raises(UsageError) as told:
        sort_settings([setting], model, "hold")
    assert str(told.value).endswith(advice)
    got = sort_settings([advice.rpartition(" ")[2]], model, "hold")  # the advice, followed
    own = [v for values in got.by_controller.values() for v in values.values()]
    assert [*got.params.values(), *got.actuators.values(), *own] == [pytest.approx(si)]


def test_the_kind_is_told_in_the_unit_the_file_declared(tmp_path: Path) -> None:
    """'bend is an angle (deg); give its unit, e.g. bend=0.75rad' named two units."""
    from legdsl.check.source import check_model

    path = tmp_path / "c.leg"
    path.write_text(_DECLARED, encoding="utf-8")
    model = check_model(path)
    with pytest.raises(UsageError, match=r"bend is an angle \(rad\); give its unit"):
        sort_settings(["bend=0.75"], model, "hold")
    with pytest.raises(UsageError, match=r"k_lean is a quantity in deg/m, but 60deg is an angle"):
        sort_settings(["k_lean=60deg"], model, "hold")


def test_a_negative_gain_without_its_unit_is_told_negative_first() -> None:
    """'hip_servo.kp=-5' was advised 'e.g. hip_servo.kp=-5N*m/rad', which was then refused as
    negative."""
    from legdsl.check.source import check_model

    model = check_model(Path(__file__).resolve().parents[2] / "creatures" / "hopper.leg")
    with pytest.raises(UsageError, match="'kp' must not be negative") as told:
        sort_settings(["hip_servo.kp=-5"], model, "hop")
    assert "-5N*m/rad" not in str(told.value)
