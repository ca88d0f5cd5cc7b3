"""An empty argument, mostly an unset shell variable (``--out "$DIR"``), is said before
anything is done: ``--out ''`` wrote into the default runs/CREATURE, a sweep's into the
current directory, and ``legdsl run ''`` said "cannot read .: Is a directory"."""

from __future__ import annotations

from pathlib import Path

import pytest
from conftest import CREATURES

from legdsl.cli import main

HOPPER = str(CREATURES / "hopper.leg")
RUN = ["run", HOPPER, "--controller", "hop", "--time", "0.1"]
SWEEP = ["sweep", HOPPER, "--controller", "hop", "--grid", "speed=0.5:1:2", "--time", "0.2"]


@pytest.mark.parametrize(
    ("argv", "said"),
    [
        ([*RUN, "--out", ""], "--out was given an empty value"),
        ([*RUN, "-o", ""], "-o was given an empty value"),
        ([*RUN, "--out="], "--out was given an empty value"),
        (["run", HOPPER, "--controller", "", "--time", "0.1"], "--controller was given an empty"),
        ([*SWEEP, "--from", "0.1", "--out", ""], "--out was given an empty value"),
        (["run", "", "--controller", "hop"], "an argument is empty"),
    ],
)
def test_an_empty_argument_is_said_and_nothing_is_written(
    argv: list[str],
    said: str,
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    capsys: pytest.CaptureFixture[str],
) -> None:
    monkeypatch.chdir(tmp_path)
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"legdsl: {said}") and "(an unset shell variable?)" in err, err
    assert list(tmp_path.iterdir()) == []
