"""A compile says how far it is and how long it has left: its sympy lowering and printing take
seconds for the shipped creatures and minutes for large ones, and said one line meanwhile
(``legdsl compile``, and ``legdsl run`` compiling a creature whose modules are missing)."""

from __future__ import annotations

import io
import sys
from pathlib import Path

import pytest
from conftest import CREATURES

from legdsl.cli import main
from legdsl.pipeline.compile import compile_file


class Terminal(io.StringIO):
    def isatty(self) -> bool:
        return True


def test_a_compile_tells_the_share_of_each_creature_done() -> None:
    told: list[tuple[str, float]] = []
    compile_file(CREATURES / "kangaroo.leg", done=lambda name, share: told.append((name, share)))
    shares = [share for _, share in told]
    assert {name for name, _ in told} == {"kangaroo"} and len(shares) >= 14
    assert shares == sorted(shares) and 0 < shares[0] and shares[-1] == 1.0


@pytest.mark.parametrize("terminal", [True, False])
def test_a_terminal_sees_a_bar_with_the_time_left(
    terminal: bool, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    said = Terminal() if terminal else io.StringIO()
    monkeypatch.setattr(sys, "stderr", said)
    assert main(["compile", str(CREATURES / "hopper.leg"), "--out", str(tmp_path)]) == 0
    text = said.getvalue()
    assert "legdsl: hopper: wrote" in text
    if not terminal:  # a log gets the lines alone
        assert "%" not in text and "\r" not in text
        return
    assert "s left" in text and text.count("100%, done") == 1
    # each line written over the bar, not after it on its line
    assert "\r\033[Klegdsl: hopper: printed" in text
