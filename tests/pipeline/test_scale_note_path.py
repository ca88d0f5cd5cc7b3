"""`legdsl scale`'s note on a used file that is not scaled names it as a user reads it."""

from __future__ import annotations

from pathlib import Path

import pytest

from legdsl.cli import main

ROOT = Path(__file__).resolve().parents[2]


def _note(tmp_path: Path, capsys: pytest.CaptureFixture[str], given: str) -> str:
    out = tmp_path / "x2.leg"
    assert main(["scale", given, "--by", "2", "-o", str(out)]) == 0
    (note,) = [line for line in capsys.readouterr().err.splitlines() if "note:" in line]
    return note


def test_a_use_followed_from_another_folder_is_named_resolved(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    # tests/good/outside/tripod_hexapod.leg uses "../../../creatures/quadruped.leg"
    monkeypatch.chdir(ROOT)
    note = _note(tmp_path, capsys, "tests/good/outside/tripod_hexapod.leg")
    assert note.startswith("legdsl: note: creatures/quadruped.leg, which it uses,")
    assert "(legdsl scale creatures/quadruped.leg --by 2 -o OUT.leg)" in note


def test_relative_to_the_current_folder_when_shorter(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(ROOT / "tests" / "good")
    note = _note(tmp_path, capsys, "outside/tripod_hexapod.leg")
    assert note.startswith("legdsl: note: ../../creatures/quadruped.leg, which it uses,")
    assert "outside" not in note  # not the path as the use was written from its file


@pytest.mark.parametrize(
    ("given", "said"),
    [
        ("/dev/stdout", "legdsl scale writes a .leg file and checks it there"),
        ("scaled", "this writes a .leg file; name it"),
    ],
)
def test_the_output_is_a_leg_file(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], given: str, said: str
) -> None:
    # a stream cannot be read back to check, and a name without .leg is not a .leg file
    target = given if given.startswith("/dev") else str(tmp_path / given)
    assert main(["scale", str(ROOT / "creatures" / "hopper.leg"), "--by", "2", "-o", target]) == 2
    assert said in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == []
