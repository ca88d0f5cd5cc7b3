"""A run made with a relative .leg path, measured from another folder: run.json names the
file from the folder the run was made in, and the note said the file was gone."""

from __future__ import annotations

from pathlib import Path

import pytest

from legdsl.cli import main

ROOT = Path(__file__).resolve().parents[2]


def test_a_relative_source_not_found_from_here_says_where_to_measure_from(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    made_in = tmp_path / "work"
    made_in.mkdir()
    (made_in / "hopper.leg").write_text((ROOT / "creatures" / "hopper.leg").read_text("utf-8"))
    monkeypatch.chdir(made_in)
    argv = ["run", "hopper.leg", "--controller", "hop", "--time", "0.5", "--backend", "python",
            "--generated", str(ROOT / "generated"), "--out", "run"]  # fmt: skip
    assert main(argv) == 0
    monkeypatch.chdir(tmp_path)
    assert main(["metrics", "work/run"]) == 0
    err = capsys.readouterr().err
    assert "'hopper.leg' that work/run/run.json names is not found from here" in err
    assert "run legdsl metrics from the folder the run was made in" in err
    assert "is gone" not in err  # it is where it was
    monkeypatch.chdir(made_in)
    assert main(["metrics", "run"]) == 0
    assert "note" not in capsys.readouterr().err
