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


def test_a_used_file_is_noted_only_where_scaling_changes_it_and_with_the_file_that_uses_it(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    """A used file whose numbers with units are all 0 was told to be scaled too (the copy is
    the file again), and one reached through another used file was told as FILE's own use."""
    good = ROOT / "tests" / "good"
    hopper = (good / "hopper.leg").read_text()
    assert 'use "actions.leg"' in hopper
    (tmp_path / "hopper.leg").write_text(hopper.replace('use "actions.leg"', 'use "lib/mid.leg"'))
    (tmp_path / "lib").mkdir()
    actions = (good / "actions.leg").read_text().replace("+ amount", "+ amount + 2 cm")
    (tmp_path / "lib" / "actions.leg").write_text(actions)
    mid = 'use "actions.leg"\naction rest(leg) { relax(leg, 0 m) }\n'  # zeros alone
    (tmp_path / "lib" / "mid.leg").write_text(mid)
    monkeypatch.chdir(tmp_path)
    assert main(["scale", "hopper.leg", "--by", "2", "-o", "x2.leg"]) == 0
    (note,) = [line for line in capsys.readouterr().err.splitlines() if "note:" in line]
    assert note.startswith("legdsl: note: lib/actions.leg, which lib/mid.leg uses, is not scaled")
    assert "point the 'use' in lib/mid.leg at it (a copy, for OUT)" in note
    assert "mid.leg, which it uses" not in note
