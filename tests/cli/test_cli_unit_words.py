"""A numeric option's or ``--set``'s unknown unit is told as a file's is, with the unit to
write where there is one; it said only "unknown unit 'hz'", and a '°' or 'MS' got no help."""

from __future__ import annotations

from pathlib import Path

import pytest

from legdsl.cli import main

HOPPER = str(Path(__file__).resolve().parents[2] / "creatures" / "hopper.leg")


@pytest.mark.parametrize(
    ("args", "told"),
    [
        (["--record-rate", "1000hz"], "--record-rate 1000hz: 'hz' is not a unit legdsl knows"),
        (["--record-rate", "1000hz"], "; did you mean 'Hz'?"),
        (["--dt", "0.4MS"], "; did you mean 'ms'?"),
        (["--fall-tilt", "45°"], "; did you mean 'deg'?"),
        (["--set", "speed=1m/sec"], "; did you mean 'm/s'?"),
    ],
)
def test_an_unknown_unit_on_the_command_line_says_what_to_write(
    args: list[str], told: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(["run", HOPPER, *args, "--out", str(tmp_path / "run")]) == 2
    err = capsys.readouterr().err
    assert told in err
    assert "Traceback" not in err
    assert not (tmp_path / "run").exists()
