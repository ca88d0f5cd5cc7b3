"""A parameter the compiled controller never reads is refused before the tune (a tune of one
ended with "the candidates' objectives no longer differ", unexplained); one it reads where the
runs never go is said to have changed nothing."""

from __future__ import annotations

from pathlib import Path

import pytest

from legdsl.api.tune import why_stopped
from legdsl.cli import main

ROOT = Path(__file__).resolve().parents[2]


def test_a_parameter_the_controller_never_reads_is_refused(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """The hopper's hop declares k_height and no state of it reads it."""
    out = tmp_path / "t"
    code = main(["tune", str(ROOT / "creatures" / "hopper.leg"), "--controller", "hop",
                 "--param", "kp=50:300", "--param", "k_height=0:1", "--speeds", "1",
                 "--out", str(out), "--generated", str(tmp_path / "generated")])  # fmt: skip
    err = capsys.readouterr().err
    assert code == 2, err
    assert "--param k_height: controller 'hop' never reads k_height" in err
    assert "tune parameters it reads (" in err and "kp" in err.rpartition("(")[2]
    assert not out.exists()


def test_candidates_all_scoring_as_the_start_are_said_to_change_nothing() -> None:
    """stroke=1cm:5cm of a hopper whose thrust never reaches its stroke limit: every
    candidate scored the start's 0.006381."""
    said = why_stopped({"tolflatfitness": 1}, 0.006381)
    assert said.startswith("every candidate scored 0.006381, as the file's own values did: ")
    assert "changed nothing in these runs" in said
    assert "no longer differ" in why_stopped({"tolflatfitness": 1})
