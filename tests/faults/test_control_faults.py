"""A control law that fails at run time points home (issue 18, item 4): the run stops with the
.leg file:line:col of the statement, the controller state, the time and the values it read,
and what was recorded up to then is written."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

from legdsl.cli import main

ROOT = Path(__file__).resolve().parents[2]
ROW = "state COMPRESSION on active.rate < 0:       servo_pitch(active, body, 0 deg, kp, kv)"

CASES = {
    # an apex speed sqrt(2 g (height - com.z)), here made negative mid-run
    "sqrt": ("hip_motor.force = 0.001 N*m*s/m * sqrt(2 * g * (height - com.z) - 20 m^2/s^2)",
             "sqrt(-15.39) has no real value", "com.z = 0.7651 m, input height = 1 m"),
    "asin": ("hip_servo.setpoint = asin(com.z / 0.5 m)",
             "asin(1.53) is undefined", "com.z = 0.7651 m"),
    # a comparison with a select() in a condition is sympy's ITE: the explanation stopped on it
    # with an internal error (BooleanFalse has no evalf)
    "ite": ("hip_servo.setpoint = select(select(com.z > 0 m, 1 s, 2 s) == time or com.z > 9 m, "
            "1 deg, 2 deg) + asin(com.z / 0.5 m)", "asin(1.53) is undefined", "com.z = 0.7651 m"),
    # sympy carries sqrt into the select (select(c, I, 1)): the file was refused as having "no
    # finite real number, whatever the state", though the branch may never be taken
    "select": ("hip_servo.setpoint = 1 deg * sqrt(select(com.z > 0.7 m, -1, 1))",
               "sqrt(-1) has no real value", "com.z = 0.7651 m"),
    # an overflow said "is undefined ((34, 'Numerical result out of range'))", Python's words
    "power": ("hip_servo.setpoint = 1 deg * (com.z / 1 m + 10) ^ 400",
              "x^y(10.77, 400) overflows a double (it would be about 1e413, past the largest, "
              "1.8e308); bound what it reads, as in clamp(..., low, high)", "com.z = 0.7651 m"),
    "exp": ("hip_servo.setpoint = 1 deg * exp(com.z / 1 m * 1000)",
            "exp(765.1) overflows a double (it would be about 1e332", "com.z = 0.7651 m"),
    "division": ("hip_motor.force = 1 N*m*s / time_in_state",
                 "a division by 0: its divisor 'time_in_state' is 0 here; give a value to use "
                 "while it is, as in select(time_in_state != 0, ..., ...)", "time_in_state = 0 s"),
    # sign() of a NaN is NaN: it was 1 (math.copysign), a full deflection from a stance time
    # not measured yet
    "sign": ("hip_servo.setpoint = 10 deg * sign(active.stance_time)",
             "the value is nan", "leg.main.stance_time = nan"),
    # min, max and clamp of a NaN are NaN, whichever argument it is: min kept its first
    # argument, in the order sympy sorts them, so one of these ran on at 10 deg
    "min": ("hip_servo.setpoint = min(active.stance_time * 1 rad/s, 10 deg)",
            "the value is nan", "leg.main.stance_time = nan"),
    "max": ("hip_servo.setpoint = max(-10 deg, active.stance_time * 1 rad/s)",
            "the value is nan", "leg.main.stance_time = nan"),
    "clamp": ("hip_servo.setpoint = clamp(active.stance_time * 1 rad/s, -10 deg, 10 deg)",
              "the value is nan", "leg.main.stance_time = nan"),
    # a stiffness or damping a law makes negative: it ran on and diverged, blamed on the step
    "negative": ("leg_spring.k = 3000 N/m - 10000 N/m * com.z / 1 m",
                 "it sets leg_spring.k = -4651 N/m, and k must not be negative", ""),
    "damping": ("hip_servo.kv = -1 N*m*s/rad * com.z / 1 m",
                "it sets hip_servo.kv = -0.7651 N*m*s/rad, and kv must not be negative", ""),
}  # fmt: skip
ADVICE = "leg.main.stance_time is NaN (not measured yet): give a time to use until it is, as in "
ADVICE += "select(main.stance_time > 0 s, main.stance_time, 0.3 s)"


@pytest.mark.parametrize(
    ("case", "backend"),
    [(c, "c") for c in CASES] + [("min", "python"), ("negative", "python"), ("power", "python")],
)
def test_a_failing_control_law_names_its_statement(
    capsys: pytest.CaptureFixture[str], generated: Path, tmp_path: Path, case: str, backend: str
) -> None:
    statement, what, read = CASES[case]
    text = (ROOT / "creatures" / "hopper.leg").read_text()
    assert ROW in text
    leg = tmp_path / "hopper.leg"
    leg.write_text(text.replace(ROW, f"{ROW}; {statement}"))
    column = text.split("\n")[text[: text.index(ROW)].count("\n")].index(ROW) + len(ROW) + 3
    out = tmp_path / "run"
    argv = ["run", str(leg), "--controller", "hop", "--time", "2", "--generated", str(generated),
            "--out", str(out), "--backend", backend]  # fmt: skip
    assert main(argv) == 3
    err = capsys.readouterr().err
    assert "internal error" not in err
    line = text[: text.index(ROW)].count("\n") + 1
    assert (
        f"{leg}:{line}:{column}: the control law failed in state COMPRESSION at t = 0.1800 s" in err
    )
    assert what in err and read in err
    assert (ADVICE in err) == (read == "leg.main.stance_time = nan")
    info = json.loads((out / "run.json").read_text())
    assert info["status"] == "diverged" and info["ended_at"] == pytest.approx(0.18)
    assert info["samples"] == 35 and what in info["cause"]  # every 5.2 ms until 0.18 s


def test_a_division_by_0_in_a_signal_is_told_at_the_signal(
    capsys: pytest.CaptureFixture[str], generated: Path, tmp_path: Path
) -> None:
    """A division written in a signal, read through another by the statement that fails: it
    was told at the statement, as Python's '0.0 cannot be raised to a negative power', the
    signals between never named."""
    text = (ROOT / "creatures" / "hopper.leg").read_text()
    head = "controller hop {\n"
    signals = "  signal inverse = 1 N*m*s / time_in_state\n  signal twice = 2 * inverse\n"
    leg = tmp_path / "hopper.leg"
    leg.write_text(
        text.replace(head, head + signals).replace(ROW, f"{ROW}; hip_motor.force = twice")
    )
    out = tmp_path / "run"
    argv = ["run", str(leg), "--controller", "hop", "--time", "2", "--generated", str(generated),
            "--out", str(out), "--backend", "c"]  # fmt: skip
    assert main(argv) == 3
    err = capsys.readouterr().err
    line = text[: text.index(head)].count("\n") + 2  # the signal inverse
    row = text[: text.index(ROW)].count("\n") + 3
    assert (
        f"{leg}:{line}:3: the control law failed in state COMPRESSION at t = 0.1800 s: in " in err
    )
    assert f"signal inverse (read by hip_motor.force = ... at {leg}:{row}:" in err
    assert "its divisor 'time_in_state' is 0 here" in err and "negative power" not in err


ARM = """creature arms2 {
  planar
  body base fixed at (0 m, 2 m) { mass 1 kg  inertia 0.01 kg*m^2 }
  body arm2 on base via revolute el at (0.5 m, 0 m) {
    length 1 m  com 0.5 m  mass 1 kg  inertia 0.05 kg*m^2
  }
  actuator elsp on el spring(k = 200 N*m/rad, b = 2 N*m*s/rad, rest = 0 deg)
}
controller bad {
  param tscale = 1000 ms
  table {
    state GO on time >= 0 s: elsp.rest = LAW
  }
}
"""


@pytest.mark.parametrize(
    ("law", "told"),
    [("asin(time / tscale - 0.5)", "asin(1.002)"), ("asin(2*(time/tscale) - 1)", "asin(1.004)"),
     ("asin(-(time/tscale))", "asin(-1.002)"), ("atan(1) + asin(0.5 - time / tscale)",
                                                "asin(-1.002)")],
)  # fmt: skip
def test_a_failed_law_tells_its_operands_as_written_with_units_and_its_line(
    capsys: pytest.CaptureFixture[str], generated: Path, tmp_path: Path, law: str, told: str
) -> None:
    """sympy keeps asin(x - 0.5) as -asin(0.5 - x): the fault told asin(-1.002) of a law whose
    argument was +1.002; the values it read had no units ('param tscale = 1'), and the law's
    line was not shown."""
    leg = tmp_path / "arm.leg"
    leg.write_text(ARM.replace("LAW", law))
    argv = ["run", str(leg), "--controller", "bad", "--time", "2", "--generated", str(generated),
            "--out", str(tmp_path / "run")]  # fmt: skip
    assert main(argv) == 3
    err = capsys.readouterr().err
    assert f"{told} is undefined" in err
    assert "param tscale = 1000 ms" in err and re.search(r"time = 1\.\d+ s\n", err)
    line = f"    state GO on time >= 0 s: elsp.rest = {law}\n"
    assert line + " " * 33 + "^~~~" in err
