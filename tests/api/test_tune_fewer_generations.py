"""A finished tune run again with fewer --generations: refused, its files and its journal's
later generations kept (it overwrote the tuned file and tune.json with the last asked
generation's result and cut the journal to it, without a word)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from legdsl.api.tune_journal import JOURNAL
from legdsl.cli import main

ROOT = Path(__file__).resolve().parents[2]

pytestmark = pytest.mark.usefixtures("hopper_modules")


def tune(out: Path, generated: Path, generations: int) -> int:
    return main([
        "tune", str(ROOT / "creatures" / "hopper.leg"), "--controller", "hop",
        "--param", "k_speed=0.02:0.2", "--speeds", "1", "--time", "1.5", "--from", "0.3",
        "--generations", str(generations), "--popsize", "2", "--jobs", "1", "--out", str(out),
        "--generated", str(generated),
    ])  # fmt: skip


def test_fewer_generations_than_the_journal_holds_are_refused(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out, generated = tmp_path / "t", tmp_path / "generated"
    assert tune(out, generated, 3) == 0
    files = {p.name: p.read_bytes() for p in out.iterdir()}
    capsys.readouterr()
    assert tune(out, generated, 1) == 2
    err = capsys.readouterr().err
    assert f"--generations 1: {out / JOURNAL} holds 3 generations of this tune" in err
    assert "give --generations 3 or more" in err
    assert {p.name: p.read_bytes() for p in out.iterdir()} == files  # nothing written over
    assert len(json.loads((out / JOURNAL).read_text())["generations"]) == 3
