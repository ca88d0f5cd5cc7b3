"""legdsl tune --param with a name the controller lacks: the names it can tune."""

from __future__ import annotations

from pathlib import Path

import pytest

from legdsl.cli import main

ROOT = Path(__file__).resolve().parents[2]
KNEE = ROOT / "tests" / "good" / "outside" / "knee_biped.leg"


def test_an_unknown_parameter_lists_only_those_the_file_declares(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """The list named k_trim and yaw_lead too, from the used creatures/biped.leg, which a tune
    then refuses: the user picked from a list half of which could not be tuned."""
    code = main(["tune", str(KNEE), "--controller", "run", "--param", "k_sepd=0.05:0.2",
                 "--speeds", "1", "--out", str(tmp_path / "t")])  # fmt: skip
    assert code == 2
    err = capsys.readouterr().err
    assert "--param k_sepd: not a parameter of the controller (k_speed, stance_guess, kp," in err
    assert "k_trim" not in err and "yaw_lead" not in err
    assert f"those declared in {KNEE}, which the tuned file can change" in err
    assert not (tmp_path / "t").exists()
