"""An outside user's literal audit found stale digits: kangaroo.md's ground-speed-matching
table gave the hop's running speed as 5.06 (the run and the table of commands: 5.068),
scaling.md gave kangaroo_x2's speed as 7.448 m/s where its hand-run commands print 7.447, and
kangaroo.md's kangaroo_3d_fast at 4 m/s 3.964 ± 0.047 m/s where `legdsl metrics
runs/roo3d_fast --from 8` prints 3.963. Each is checked against what the commands print."""

from __future__ import annotations

import re
import shutil
from pathlib import Path

import pytest
from conftest import CREATURES

from legdsl.cli import main

ROOT = Path(__file__).resolve().parents[2]


def _doc(name: str) -> str:
    return " ".join(ROOT.joinpath("docs", name).read_text(encoding="utf-8").split())


def _speed(run: Path, start: str, capsys: pytest.CaptureFixture[str], *more: str) -> str:
    capsys.readouterr()
    assert main(["metrics", str(run), "--from", start, *more]) == 0
    found = re.search(r"running speed \(m/s\)\s+(\S+)\s+(\S+)", capsys.readouterr().out)
    assert found is not None
    return f"{found.group(1)} ± {found.group(2)}"


def test_the_matching_tables_hop_speed_is_the_commands_tables() -> None:
    text = _doc("kangaroo.md")
    main_row = re.search(r"\| 5 m/s \| yes \| (\d\.\d+) m/s \|", text)
    matching = re.search(r"\| running speed \(m/s\) \| (\S+) \| 4\.78", text)
    assert main_row is not None and matching is not None
    assert matching.group(1) == main_row.group(1) == "5.068"


def test_kangaroo_x2_speed_is_what_the_hand_run_prints(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.chdir(tmp_path)
    gen = ["--generated", str(tmp_path / "gen"), "--backend", "c"]
    assert (
        main(["scale", str(CREATURES / "kangaroo.leg"), "--by", "2", "-o", "kangaroo_x2.leg"]) == 0
    )
    argv = ["run", "kangaroo_x2.leg", "--controller", "hop", "--time", "14.142135623730951"]
    assert main([*argv, *gen, "--out", "runs/kangaroo_x2"]) == 0
    speed = _speed(Path("runs/kangaroo_x2"), "7.0710678118654755", capsys, *gen[:2])
    said = re.search(r"kangaroo_x2 to [\d.]+ m, [\d.]+ s, ([\d.]+) m/s", _doc("scaling.md"))
    assert said is not None and said.group(1) == speed.split(" ")[0]


def test_kangaroo_3d_fast_at_4_m_s_is_what_metrics_prints(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.chdir(tmp_path)
    leg = tmp_path / "tests" / "good" / "outside" / "kangaroo_3d_fast.leg"
    leg.parent.mkdir(parents=True)
    shutil.copy(ROOT / "tests" / "good" / "outside" / "kangaroo_3d_fast.leg", leg)
    argv = ["run", str(leg.relative_to(tmp_path)), "--controller", "hop", "--set", "speed=4m/s"]
    more = ["--time", "20", "--backend", "c", "--generated", str(tmp_path / "gen")]
    assert main([*argv, *more, "--out", "runs/roo3d_fast"]) == 0
    speed = _speed(Path("runs/roo3d_fast"), "8", capsys, "--generated", str(tmp_path / "gen"))
    row = re.search(
        r"\| 4 m/s \| fell at [\d.]+ s \| \| ([\d.]+ ± [\d.]+) m/s", _doc("kangaroo.md")
    )
    assert row is not None and row.group(1) == speed
