"""What sympy's folding of a control law hides or makes, told at the signal it is in, truly.

``0 * (x / zero)`` is 0 to sympy: the generated code left out a division that a run makes
without the ``0 *`` and refuses (``zero`` declared 0), and ran on with no fault. A product
whose numbers pass a double once gathered (``x * 1e200 * 1e200`` is ``1e400*x`` to sympy) was
said to give no finite number 'whatever the creature's state' (false as written: 0 at x = 0)
with the caret on the action call that used the signal, not on the signal.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from legdsl.cli import main

CREATURE = """creature a {
  planar
  body trunk free { mass 1 kg  inertia 0.03 kg*m^2 }
  body leg on trunk via revolute hip { mass 1 kg  inertia 0.01 kg*m^2  length 0.5 m }
  actuator hip_servo on hip servo(kp = 10 N*m/rad)
}
controller c {
  param zero = ZERO
  signal s = SIGNAL
  table {
    state A on time > 0 s: hip_servo.setpoint = s
  }
}
"""


def _check(
    tmp_path: Path, signal: str, zero: str, capsys: pytest.CaptureFixture[str]
) -> tuple[int, str]:
    path = tmp_path / "c.leg"
    path.write_text(CREATURE.replace("SIGNAL", signal).replace("ZERO", zero))
    code = main(["check", str(path)])
    return code, capsys.readouterr().err


@pytest.mark.parametrize(
    "signal",
    [
        "1 rad * 0 * (trunk.z / zero)",
        "1 rad * (0 m / zero) / (1 s)",
        "1 rad * 0 * sqrt(zero / (1 m)) * trunk.z / (1 m)",
    ],
)
def test_a_fold_that_drops_a_part_with_no_value_is_told_at_the_signal(
    tmp_path: Path, signal: str, capsys: pytest.CaptureFixture[str]
) -> None:
    unit = "m" if "sqrt" in signal else "m/s"
    zero = f"-1 {unit}" if "sqrt" in signal else f"0 {unit}"
    code, err = _check(tmp_path, signal, zero, capsys)
    assert code == 2
    assert ":9:3: error: a part of this gives no finite real number with 'zero' as declared" in err
    assert "the compiled code leaves it out: this is always 0 as compiled" in err
    assert "; remove that part, or give 'zero' a value" in err
    assert "Traceback" not in err


def test_a_fold_that_drops_a_part_with_a_value_is_taken(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    code, err = _check(tmp_path, "1 rad * 0 * (trunk.z / zero)", "2 m", capsys)
    assert code == 0, err


def test_numbers_past_a_double_once_gathered_are_told_as_such_at_the_signal(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    code, err = _check(tmp_path, "1 rad * (trunk.z / (1 m)) * 1e200 * 1e200", "1 m", capsys)
    assert code == 2
    assert ":9:3: error: this gives no finite real number as compiled" in err
    assert "(1e+200, 1e+200 make 1.00e+400), past a double" in err
    assert "; write it with smaller numbers" in err
    assert "sympy makes an infinity" not in err  # 'whatever the state' of what is written: false
