"""Two creatures of one name in one `legdsl compile` (the hopper and a copy weighing 12 kg,
still `creature hopper`): the second silently replaced the first, 'wrote gen/hopper/' told
twice, exit 0. They are refused before anything is written, at both declarations, saying to
rename one or to compile them into different --out folders. A file given twice (by two paths)
is compiled once."""

from __future__ import annotations

from pathlib import Path

import pytest

from legdsl.cli import main

TINY = """
creature tiny {
  planar
  gravity 9.81 m/s^2
  body base free { mass MASS kg  inertia 0.01 kg*m^2 }
  contact foot on base
}
"""


def test_two_creatures_of_one_name_are_refused_before_writing(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    (tmp_path / "a").mkdir()
    (tmp_path / "a" / "tiny.leg").write_text(TINY.replace("MASS", "1"), encoding="utf-8")
    (tmp_path / "heavy.leg").write_text(TINY.replace("MASS", "2"), encoding="utf-8")
    monkeypatch.chdir(tmp_path)
    assert main(["compile", "a/tiny.leg", "heavy.leg", "-o", "gen"]) == 2
    err = capsys.readouterr().err
    assert not (tmp_path / "gen").exists()
    assert "wrote" not in err
    assert "a/tiny.leg:2:1: error: creature 'tiny' is also defined at heavy.leg:2:1" in err
    assert "heavy.leg:2:1: error: creature 'tiny' is already defined at a/tiny.leg:2:1" in err
    assert "rename one of them, or compile them into different --out folders" in err
    assert err.count("    creature tiny {\n    ^") == 2  # the line and a caret, each file


def test_one_file_given_twice_is_compiled_once(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    (tmp_path / "tiny.leg").write_text(TINY.replace("MASS", "1"), encoding="utf-8")
    monkeypatch.chdir(tmp_path)
    assert main(["compile", "tiny.leg", str(tmp_path / "tiny.leg"), "-o", "gen"]) == 0
    assert capsys.readouterr().err.count("tiny: wrote gen/tiny/") == 1
