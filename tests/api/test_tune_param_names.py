"""legdsl tune --param with a name the controller lacks: the names it can tune."""

from __future__ import annotations

from pathlib import Path

import pytest

from legdsl.cli import main

ROOT = Path(__file__).resolve().parents[2]
KNEE = ROOT / "tests" / "good" / "outside" / "knee_biped.leg"


def test_an_unknown_parameter_is_told_the_nearest_name_and_the_list(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """Every parameter of the controller can be tuned (one of a used file is overridden in the
    tuned controller), so the list names those of creatures/biped.leg too."""
    code = main(["tune", str(KNEE), "--controller", "run", "--param", "k_sepd=0.05:0.2",
                 "--speeds", "1", "--out", str(tmp_path / "t")])  # fmt: skip
    assert code == 2
    err = capsys.readouterr().err
    assert (
        "--param k_sepd: not a parameter of the controller; did you mean 'k_speed'? (it has " in err
    )
    assert "k_trim" in err and "yaw_lead" in err
    assert not (tmp_path / "t").exists()
