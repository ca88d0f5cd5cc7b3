"""A mistake in a ``--grid``, ``--random``, ``--param`` or ``--speeds`` value is echoed with a
caret under its fault, saying what to write (docs/api.md). An outside user's
`--grid 'tilt=-3deg:1:3'` ran tilt 1 rad (57 deg; the run fell) without a word, where the
whole-bare range had a note; `--grid speed=1:1:3` and `speed=1m/s,1m/s` ran identical runs;
`speed=1:2:0`, `1:2:2.5` and `1:2` were told only `write NAME=LO:HI:N (N values) or
NAME=A,B,C`; `--samples 0` and `--jobs 0` 'sweep: --samples, --jobs and --time must be
positive'; `--param k_speed=60ms:100ms` and `--random speed=2:1` had no caret."""

from __future__ import annotations

from pathlib import Path

import pytest

from legdsl.api.sweep import parse_axis
from legdsl.cli import main
from legdsl.lang.units import parse_unit

HOPPER = str(Path(__file__).resolve().parents[2] / "creatures" / "hopper.leg")
DIMS = {"speed": parse_unit("m/s")[1], "k_speed": parse_unit("s")[1]}


def _told(argv: list[str], capsys: pytest.CaptureFixture[str]) -> list[str]:
    assert main(argv) == 2
    return capsys.readouterr().err.splitlines()


@pytest.mark.parametrize(
    ("option", "value", "fault", "words"),
    [
        ("--grid", "hip_servo.setpoint=-3deg:1:3", "1", "1 has no unit, beside -3deg"),
        ("--grid", "hip_servo.setpoint=1,5deg", "1", "write its unit (1deg, if that"),
        ("--random", "speed=50cm/s:3", "3", "a bare number is in m/s"),
        ("--grid", "speed=1:1:3", "1", "3 values from 1 to 1 are one value 3 times"),
        ("--grid", "speed=1m/s,100cm/s", "100cm/s", "100cm/s is given twice"),
        ("--grid", "speed=1,2,1", "1", "1 is given twice"),
        ("--grid", "speed=1:2:0", "0", "N, the number of values from LO to HI, is a whole"),
        ("--grid", "speed=1:2:2.5", "2.5", "2.5 is not"),
        ("--grid", "speed=1:2", "", "its number of values: write speed=1:2:N"),
        ("--random", "speed=2:1", "2:1", "the range needs LO < HI; write speed=1:2"),
        ("--samples", "0", "0", "--samples 0: must be more than zero"),
        ("--jobs", "0", "0", "--jobs 0: must be more than zero"),
    ],
)  # fmt: skip
def test_a_sweep_values_mistake_is_pointed_at(
    option: str,
    value: str,
    fault: str,
    words: str,
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
) -> None:
    extra = ["--random", "speed=1:2"] if option in ("--samples", "--jobs") else []
    lines = _told(["sweep", HOPPER, "--controller", "hop", option, value, *extra,
                   "--out", str(tmp_path / "o")], capsys)  # fmt: skip
    assert words in lines[0], lines
    assert lines[1] == f"    {option} {value}"
    at = value.rfind(fault) if fault else len(value)
    assert lines[2] == " " * (4 + len(option) + 1 + at) + "^" + "~" * (len(fault) - 1), lines
    assert not (tmp_path / "o").exists()


def test_a_tunes_values_are_pointed_at(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    tune = ["tune", HOPPER, "--controller", "hop", "--out", str(tmp_path / "t")]
    lines = _told([*tune, "--param", "k_speed=70ms:100ms", "--speeds", "1"], capsys)
    assert "the file's value 0.06 s is outside the bounds (0.07 to 0.1 s)" in lines[0]
    assert lines[1:] == ["    --param k_speed=70ms:100ms", "                    ^~~~"]
    lines = _told([*tune, "--param", "k_speed=10ms:50ms", "--speeds", "1"], capsys)
    assert lines[1:] == ["    --param k_speed=10ms:50ms", "                         ^~~~"]
    lines = _told([*tune, "--param", "k_speed=10ms:0.1", "--speeds", "1"], capsys)
    assert lines[1:] == ["    --param k_speed=10ms:0.1", "                         ^~~"]
    lines = _told([*tune, "--param", "k_speed=10ms:100ms", "--speeds", "1m/s,2m/s,100cm/s"], capsys)
    assert "100cm/s is given twice (1m/s before it is the same value" in lines[0]
    assert lines[0].endswith("give each speed once")
    assert lines[1:] == ["    --speeds 1m/s,2m/s,100cm/s", "                       ^~~~~~~"]
    lines = _told([*tune, "--param", "k_speed=10ms:100ms", "--speeds", "1", "--jobs", "0"], capsys)
    assert lines[0] == "legdsl: --jobs 0: must be more than zero; give 1 or more"


def test_a_bare_zero_is_zero_in_every_unit() -> None:
    assert parse_axis("grid", "speed=0,50cm/s", DIMS).values == (0.0, 0.5)
    assert parse_axis("random", "k_speed=0:100ms", DIMS).values == (0.0, 0.1)
