"""An outside user's sweep refusals that named nothing or advised what a sweep has not:
`--grid speed=1:2:3 --grid speed=3:4:2` was 'sweep: each name is swept once' (no name, no
caret); `--grid speed=1:2:1e9` said 1e9 is not a whole number; `--time 1e-9` advised 'a
--dt of 1e-09s or less', an option legdsl sweep does not have."""

from __future__ import annotations

from pathlib import Path

import pytest

from legdsl.cli import main

ROOT = Path(__file__).resolve().parents[2]
HOPPER = ROOT / "creatures" / "hopper.leg"

pytestmark = pytest.mark.usefixtures("hopper_modules")


def refusal(tmp_path: Path, capsys: pytest.CaptureFixture[str], *given: str) -> str:
    code = main(["sweep", str(HOPPER), "--controller", "hop", *given, "--jobs", "1",
                 "--out", str(tmp_path / "out"), "--generated", str(tmp_path / "generated")])  # fmt: skip
    err = capsys.readouterr().err
    assert code == 2, err
    assert "internal error" not in err and "Traceback" not in err
    assert not (tmp_path / "out").exists()
    return err


def test_a_name_swept_twice_is_named_with_a_caret_under_the_second(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    err = refusal(tmp_path, capsys, "--grid", "speed=1:2:3", "--grid", "speed=3:4:2")
    assert "--grid 'speed=3:4:2': speed is swept twice (--grid speed=1:2:3 sweeps it" in err
    assert "    --grid speed=3:4:2\n           ^~~~~" in err


def test_a_grids_count_written_as_1e9_is_whole_and_refused_for_its_size(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    err = refusal(tmp_path, capsys, "--grid", "speed=1:2:1e9")
    assert "is 1e9: 1,000,000,000 values, more than a sweep takes (1,000,000)" in err
    assert "is not" not in err
    err = refusal(tmp_path, capsys, "--grid", "speed=1:2:3.0")
    assert "write N in digits: speed=1:2:3" in err


def test_a_time_shorter_than_a_step_is_told_in_the_sweeps_words(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    err = refusal(tmp_path, capsys, "--grid", "speed=1:2:2", "--time", "1e-9", "--from", "0")
    assert "sweep: --time 1e-09s is shorter than one step (dt " in err
    assert "a smaller dt in the file's simulation block (a sweep has no --dt)" in err
    assert "a --dt of" not in err
