"""Every command has --help with an example; the list of commands is read from the parser,
so a command added later is covered too."""

from __future__ import annotations

import argparse

import pytest

from legdsl.cli import _parser, main


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
