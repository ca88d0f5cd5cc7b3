"""``legdsl run`` and ``legdsl metrics`` note a path the run missed by more than half its size.

An outside user's biped on a 5 cm circle kept 0.58 m off it (RMS) and was told nothing: the
note's limit was 1 m whatever the path's size."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from conftest import CREATURES

from legdsl.cli import main

TINY = "circle(center = (0, 0.05) m, radius = 0.05 m, lookahead = 0.05 m)"


def test_a_tiny_circle_missed_is_noted(
    generated: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "run"
    args = ["run", str(CREATURES / "biped.leg"), "--controller", "run", "--set", "speed=1.5m/s",
            "--path", TINY, "--time", "5", "--generated", str(generated), "--out", str(out)]  # fmt: skip
    assert main(args) == 0
    said = capsys.readouterr().err
    (report,) = json.loads((out / "run.json").read_text())["path_reports"]
    assert 0.05 < report["lateral_rms"] < 1.0 and report["size"] == 0.05
    assert "legdsl: note: the centre of mass kept" in said
    assert "more than half the path's spread (0.050 m" in said
    assert "its progress and laps are those of the path's point nearest" in said
    assert main(["metrics", str(out), "--generated", str(generated)]) == 0
    assert report["note"] in capsys.readouterr().err
