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
