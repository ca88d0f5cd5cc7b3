"""A starting controller's input default given beside a command of that input from the start."""

from __future__ import annotations

from pathlib import Path

import pytest

from legdsl.cli import main

HOPPER = str(Path(__file__).resolve().parents[2] / "creatures" / "hopper.leg")


@pytest.mark.parametrize(
    ("sets", "noted"),
    [
        (["hop.speed=1m/s", "speed=2m/s"], True),
        (["hop.speed=1m/s", "speed=2m/s@0.05s"], False),  # the default holds until then
        (["hop.speed=1m/s"], False),
    ],
)
def test_a_default_under_a_command_from_the_start_is_noted(
    sets: list[str], noted: bool, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """'--set hop.speed=1m/s --set speed=2m/s' ran at 2 m/s (the command over the default,
    as documented) and said nothing of the first, which changed nothing."""
    args = ["run", HOPPER, "--controller", "hop", "--time", "0.1", "-o", str(tmp_path / "r"),
            "--generated", str(tmp_path / "generated")]  # fmt: skip
    for text in sets:
        args += ["--set", text]
    assert main(args) == 0
    said = "--set hop.speed=1m/s: --set speed=2m/s commands speed from the start"
    assert (said in capsys.readouterr().err) == noted
