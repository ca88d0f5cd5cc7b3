"""`--controller` beside a scene that chooses its gait by speed: it may repeat the controller the
gait table starts with (docs/language.md, "Scenes"), and the message for another names that one."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from legdsl.cli import main

BIPED = Path(__file__).resolve().parents[2] / "creatures" / "biped.leg"


def test_controller_may_repeat_the_gait_tables_first_band(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "run"
    args = ["run", str(BIPED), "--scene", "by_speed", "--time", "0.01", "--out", str(out)]
    assert main([*args, "--controller", "gallop"]) == 0  # 1.5 m/s: the gallop's band
    assert json.loads((out / "run.json").read_text())["controller"] == "gallop"
    capsys.readouterr()
    # 2 m/s first: only the run's band holds it, so the run starts, whatever the scene's order
    assert main([*args, "--set", "speed=2m/s", "--controller", "gallop"]) == 2
    err = capsys.readouterr().err
    assert "starts with controller run" in err and "leave out --controller" in err
