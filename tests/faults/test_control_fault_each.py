"""Where a control-law fault came through: the action calls it was inlined from, and the pass
of an each block it failed in (it was told "(inlined from the action called at pair.leg:23:37)",
the word 'each', where no action is called)."""

from __future__ import annotations

from pathlib import Path

import pytest

from legdsl.cli import main
from legdsl.lang.errors import Span
from legdsl.lower.control import EachPass
from legdsl.sim.control_faults import _where

DATA = Path(__file__).parent / "data"


def test_a_fault_in_an_each_block_names_the_member(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    args = ["run", str(DATA / "each_pair.leg"), "--controller", "hold", "--time", "0.3",
            "--set", "gain=-1@0.1s", "--out", str(tmp_path / "run"),
            "--generated", str(tmp_path / "generated")]  # fmt: skip
    assert main(args) == 3
    err = capsys.readouterr().err
    assert "each_pair.leg:23:54 (for m = a in the each at " in err, err
    assert "each_pair.leg:23:37): the control law failed in state STAND" in err
    assert "inlined" not in err


def test_action_calls_and_each_passes_are_told_innermost_first() -> None:
    def at(line: int) -> Span:
        return Span("c.leg", line, 3, line, 9)

    assert _where((at(1),)) == "c.leg:1:3"
    assert _where((at(1), at(2), at(3))) == (
        "c.leg:1:3 (inlined from the action called at c.leg:2:3, called at c.leg:3:3)"
    )
    assert _where((at(1), EachPass(at(2), "m#1", "fl"), at(3))) == (
        "c.leg:1:3 (for m = fl in the each at c.leg:2:3; inlined from the action called at "
        "c.leg:3:3)"
    )
