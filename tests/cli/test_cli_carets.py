"""A command-line quantity's mistake points at its fault as ``--path`` does: the option and
its value echoed, a caret under the unit (or the number, or the value) at fault. It was one
line (``legdsl: --time 0.2kg: --time is a time (s), but ...``), with no caret."""

from __future__ import annotations

from pathlib import Path

import pytest

from legdsl.cli import main
from legdsl.cli.pointed import pointed

HOPPER = str(Path(__file__).resolve().parents[2] / "creatures" / "hopper.leg")


def _told(argv: list[str], capsys: pytest.CaptureFixture[str]) -> list[str]:
    try:
        code = main(argv)
    except SystemExit as stop:  # argparse's own (a type= function's) mistakes
        code = int(stop.code or 0)
    assert code == 2
    return capsys.readouterr().err.splitlines()


@pytest.mark.parametrize(
    ("args", "echo", "caret"),
    [
        (["run", HOPPER, "--time", "0.2kg"], "    --time 0.2kg", "              ^~"),
        (["run", HOPPER, "--drop", "3feet"], "    --drop 3feet", "            ^~~~"),
        (["run", HOPPER, "--dt", "-1ms"], "    --dt -1ms", "         ^~"),
        (["run", HOPPER, "--record-rate", "2s"], "    --record-rate 2s", "                   ^"),
        (["run", HOPPER, "--scale", "2m"], "    --scale 2m", "             ^"),
        (["metrics", "r", "--from", "1kg"], "    --from 1kg", "            ^~"),
    ],
)  # fmt: skip
def test_a_quantitys_mistake_has_a_caret_under_its_fault(
    args: list[str],
    echo: str,
    caret: str,
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    capsys: pytest.CaptureFixture[str],
) -> None:
    monkeypatch.chdir(tmp_path)
    lines = _told(args, capsys)
    assert lines[0].startswith(f"legdsl: {args[2]}")
    assert lines[1:] == [echo, caret]


def test_the_caret_finds_the_part_of_a_compound_value() -> None:
    takes = {"--set", "--grid", "--switch"}
    said = pointed(
        "--set speed=2m/s@1kg: the time after '@' is in seconds, but 1kg is a mass (kg)",
        ["run", "f.leg", "--set", "speed=1kg@2s", "--set", "speed=2m/s@1kg"],
        takes,
    )
    assert said.splitlines()[1:] == ["    --set speed=2m/s@1kg", "                      ^~"]
    said = pointed(
        "--grid speed: speed is a velocity (m/s), but '1kg' is a mass (kg); give it in m/s",
        ["sweep", "f.leg", "--grid", "speed=1kg:2m/s:3"],
        takes,
    )
    assert said.splitlines()[1:] == ["    --grid speed=1kg:2m/s:3", "                  ^~"]
    # a path's or a name's mistake is not a quantity's; a message with its caret keeps it
    assert pointed("--out x: is a file", ["run", "--out", "x"], {"--out"}) == "--out x: is a file"
    assert (
        pointed("--set a=1kg: but 1kg is a mass\n    x\n    ^", ["--set", "a=1kg"], takes).count(
            "\n"
        )
        == 2
    )


KANGAROO = str(Path(__file__).resolve().parents[2] / "creatures" / "kangaroo.leg")


@pytest.mark.parametrize(
    ("value", "words", "caret"),
    [
        ("speed=4m/s@-1s", "0 or more", "                     ^^^"),
        ("speed=4m/s@", "no time after '@'", "                    ^"),
        ("speed=4m/s@1e999s", "too large to be a number", "                     ^~~~~"),
        ("speed=4m/s@nans", "'nans' is not a number", "                     ^~~~"),
        ("jump_height=1e-999m", "too small to be a number", "                      ^~~~~~"),
        ("jump_at=8m@4s@5s", "one '@' to a --set", "                       ^^^"),
        ("hop.speed=4m/s", "controller 'hop' does not run here", "          ^^^"),
    ],
)  # fmt: skip
def test_a_set_values_mistake_echoes_the_option_with_a_caret(
    value: str,
    words: str,
    caret: str,
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    capsys: pytest.CaptureFixture[str],
) -> None:
    """They were one line (``--set ...@: '' is not a number``, the value unechoed), or the
    second '@' was read as the value's unit ('m@4s' is not a unit), or the echo dropped --set."""
    monkeypatch.chdir(tmp_path)
    lines = _told(["run", KANGAROO, "--controller", "jump", "--set", value, "--time", "1"], capsys)
    at = next(i for i, line in enumerate(lines) if line.startswith("legdsl: --set "))
    assert words in lines[at] and "is not a unit" not in lines[at], lines
    assert lines[at + 1 :] == [f"    --set {value}", caret]


def test_a_length_for_a_time_is_advised_in_seconds_first(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """``--time 5m`` advised only 5ms: 1000 times off if seconds were meant."""
    monkeypatch.chdir(tmp_path)
    lines = _told(["run", HOPPER, "--time", "5m"], capsys)
    assert lines[0].endswith("write e.g. --time 5s, or 5ms if the m meant milli"), lines


def test_a_switchs_bare_time_has_the_caret_under_the_time() -> None:
    """``--switch 6=bound`` had its caret under ``bound``, where a --set's value would be."""
    said = pointed(
        "--switch 6=bound: the time before '=' is in seconds; give its unit, e.g. --switch 6s=bound",
        ["run", "f.leg", "--switch", "6=bound"],
        {"--switch"},
    )
    assert said.splitlines()[1:] == ["    --switch 6=bound", "             ^"]
    said = pointed(
        "--switch 6.25=bound: the time before '=' is in seconds; give its unit, e.g. --switch 6.25s=bound",
        ["run", "f.leg", "--switch", "6.25=bound"],
        {"--switch"},
    )
    assert said.splitlines()[2] == "             ^~~~"
