"""legdsl tune of a controller without an input 'speed': the refusal said what was missing
("controller 'hop' has no input 'speed' to command") and not what to do (an outside user's
hopper, its 'speed' renamed 'vel')."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from test_tune import NO_PARAMS

from legdsl.cli import main

ROOT = Path(__file__).resolve().parents[2]

ARM = (
    NO_PARAMS
    + """
controller swing {
  param amp = 30 deg
  table {
    state A on time_in_state > 0.2 s: s.setpoint = amp
    state B on time_in_state > 0.2 s: s.setpoint = -amp
  }
}
"""
)


def tune(source: Path, controller: str, param: str, out: Path) -> int:
    return main(["tune", str(source), "--controller", controller, "--param", param, "--speeds",
                 "1", "--out", str(out), "--generated", str(out.parent / "generated")])  # fmt: skip


def test_a_controller_without_speed_is_told_to_declare_one_or_which_has_one(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    (tmp_path / "arm.leg").write_text(ARM)
    assert tune(tmp_path / "arm.leg", "swing", "amp=10deg:40deg", tmp_path / "t") == 2
    err = capsys.readouterr().err
    assert "controller 'swing' has no input 'speed' to command (the objective is the running " in (
        err
    )
    assert "declare one in it, 'input speed = 1 m/s', and steer its gait by it" in err
    assert "or tune a controller of the file that has one (hold)" in err
    assert not (tmp_path / "t").exists()


def test_an_input_in_m_s_of_another_name_is_told_to_be_renamed(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    text = (ROOT / "creatures" / "hopper.leg").read_text()
    (tmp_path / "vel.leg").write_text(re.sub(r"\bspeed\b", "vel", text))
    assert tune(tmp_path / "vel.leg", "hop", "kp=50:300", tmp_path / "t") == 2
    err = capsys.readouterr().err
    assert "controller 'hop' has no input 'speed' to command" in err
    assert "rename its input 'vel' (a speed in m/s) to 'speed'" in err
