"""Every command has --help with an example; the list of commands is read from the parser,
so a command added later is covered too."""

from __future__ import annotations

import argparse
import shutil
from pathlib import Path

import pytest

from legdsl.cli import _parser, main

ROOT = Path(__file__).resolve().parents[2]


def subcommands() -> list[str]:
    (action,) = [a for a in _parser()._actions if isinstance(a, argparse._SubParsersAction)]
    return sorted(action.choices)


def test_the_known_commands_are_there() -> None:
    assert {"check", "show"} <= set(subcommands())


@pytest.mark.parametrize("argv", [[], *([c] for c in subcommands())])
def test_help_exits_0_with_an_example(argv: list[str], capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as info:
        main([*argv, "--help"])
    assert info.value.code == 0
    out = capsys.readouterr().out
    assert "Example" in out
    assert out.startswith("usage: legdsl")


def test_a_file_named_like_an_option_says_how_to_name_it(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """argparse reads -hop.leg as -h given 'op.leg' ("ignored explicit argument")."""
    monkeypatch.chdir(tmp_path)
    shutil.copy(ROOT / "creatures" / "hopper.leg", "-hop.leg")
    assert main(["check", "-hop.leg"]) == 2
    assert "write ./-hop.leg (or put -- before it)" in capsys.readouterr().err
    assert main(["check", "./-hop.leg"]) == 0
    assert main(["check", "--", "-hop.leg"]) == 0
