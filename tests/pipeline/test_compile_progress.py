"""A compile says how far it is and how long it has left: its sympy lowering and printing take
seconds for the shipped creatures and minutes for large ones, and said one line meanwhile
(``legdsl compile``, and ``legdsl run`` compiling a creature whose modules are missing)."""

from __future__ import annotations

import io
import sys
from pathlib import Path

import pytest
from conftest import CREATURES
from runtime_helpers import needs_c_compiler

from legdsl.cli import main
from legdsl.pipeline.compile import compile_file
from legdsl.sim import c_library


class Terminal(io.StringIO):
    def isatty(self) -> bool:
        return True


def test_a_compile_tells_the_share_of_each_creature_done() -> None:
    told: list[tuple[str, float]] = []
    compile_file(CREATURES / "kangaroo.leg", done=lambda name, share: told.append((name, share)))
    shares = [share for _, share in told]
    assert {name for name, _ in told} == {"kangaroo"} and len(shares) >= 14
    assert shares == sorted(shares) and shares[0] > 0 and shares[-1] == 1.0


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


@needs_c_compiler
def test_a_run_says_it_builds_the_c_library_before_the_compiler_runs(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The kangaroo's library takes gcc 3 s, a hexapod's 5 s, a large creature's a minute: the
    run said nothing until it was built."""
    monkeypatch.setenv("LEGDSL_CACHE", str(tmp_path / "cache"))
    monkeypatch.setattr(c_library, "_BY_STAT", {})  # this process may hold it from another test
    monkeypatch.setattr(c_library, "_TRUSTED", {})
    said = Terminal()  # a log keeps to one line for a build that fails
    monkeypatch.setattr(sys, "stderr", said)
    argv = ["run", str(CREATURES / "hopper.leg"), "--controller", "hop", "--time", "0.01"]
    argv += ["--backend", "c", "--out", str(tmp_path / "run")]
    assert main(argv) == 0
    lines = said.getvalue().splitlines()
    building = next(i for i, line in enumerate(lines) if "building the C library of hop" in line)
    assert "lines of C; kept in" in lines[building] and "built" in lines[building + 1]
    assert main(argv) == 0  # from the cache: nothing to say
    assert said.getvalue().count("building the C library") == 1
