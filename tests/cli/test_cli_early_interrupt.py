"""A Ctrl-C while the command line's modules are still loading is one line and exit 130,
as a Ctrl-C later is (it was a traceback of the import, exit status -2)."""

from __future__ import annotations

import builtins
import signal
import sys

import pytest

import legdsl.__main__ as entry


def test_ctrl_c_while_importing_the_command_line(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    real_import = builtins.__import__

    def interrupted(name: str, *args: object, **kwargs: object) -> object:
        if name == "legdsl.cli":
            raise KeyboardInterrupt
        return real_import(name, *args, **kwargs)  # type: ignore[arg-type]

    monkeypatch.delitem(sys.modules, "legdsl.cli", raising=False)
    monkeypatch.setattr(builtins, "__import__", interrupted)
    handler = signal.getsignal(signal.SIGINT)
    try:
        assert entry.main() == 130
    finally:  # main left its Ctrl-C handler, as the console script's process ends after it
        signal.signal(signal.SIGINT, handler)
    assert capsys.readouterr().err == "legdsl: interrupted\n"


def test_the_console_script_is_this_entry_point() -> None:
    from importlib.metadata import entry_points

    (script,) = [e for e in entry_points(group="console_scripts") if e.name == "legdsl"]
    assert script.value == "legdsl.__main__:main"


def test_ctrl_c_while_the_parsers_import_their_commands(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    import legdsl.cli as cli

    def interrupted() -> object:
        raise KeyboardInterrupt

    monkeypatch.setattr(cli, "_parser", interrupted)
    assert cli.main(["check", "creatures/hopper.leg"]) == 130
    assert capsys.readouterr().err == "legdsl: interrupted\n"
