"""``legdsl show`` gives each leg's hip point, and notes legs that hang from one point: the
right leg of a mirrored template given the right side's point (mirrored back onto the left)
was well-formed, shown without a word, and ran with two legs in one place."""

from __future__ import annotations

from pathlib import Path

import pytest
from conftest import CREATURES

from legdsl.cli import main

RIGHT = "instance fr = leg(S = fr, HIP = (0.39 m, 0.12 m, 0 m)) mirror sagittal"


def test_show_gives_each_hip_point(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["show", str(CREATURES / "quadruped.leg")]) == 0
    out = capsys.readouterr().out
    assert "fl: joints hip_fl, leg_fl; foot toe_fl; hip at (0.390, 0.120, 0.000) m;" in out
    assert "fr: joints hip_fr, leg_fr; foot toe_fr; hip at (0.390, -0.120, 0.000) m;" in out
    assert "same point" not in out


def test_a_mirrored_leg_given_the_mirrored_point_is_noted(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    text = (CREATURES / "quadruped.leg").read_text()
    assert RIGHT in text
    source = tmp_path / "quadruped.leg"
    source.write_text(text.replace(RIGHT, RIGHT.replace("0.12 m", "-0.12 m")))
    assert main(["show", str(source)]) == 0
    out = capsys.readouterr().out
    assert "fr: joints hip_fr, leg_fr; foot toe_fr; hip at (0.390, 0.120, 0.000) m;" in out
    assert "note: legs fl, fr hang from the same point;" in out
    assert "'mirror sagittal' turns y into -y" in out


def test_a_planar_creatures_legs_on_one_hip_are_not_noted(
    capsys: pytest.CaptureFixture[str],
) -> None:
    runner = CREATURES.parent / "tests" / "good" / "outside" / "knee_runner.leg"
    assert main(["show", str(runner)]) == 0
    out = capsys.readouterr().out
    assert "left: joints hip_l, knee_l; foot toe_l; hip at (0.000, 0.000) m;" in out
    assert "same point" not in out
