"""A numeric option's or ``--set``'s unknown unit is told as a file's is, with the unit to
write where there is one; it said only "unknown unit 'hz'", and a '°' or 'MS' got no help."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from legdsl.cli import _parser, main
from legdsl.cli.common import negative_values_joined

HOPPER = str(Path(__file__).resolve().parents[2] / "creatures" / "hopper.leg")


@pytest.mark.parametrize(
    ("args", "told"),
    [
        (["--record-rate", "1000hz"], "--record-rate 1000hz: 'hz' is not a unit legdsl knows"),
        (["--record-rate", "1000hz"], "; did you mean 'Hz'?"),
        (["--dt", "0.4MS"], "; did you mean 'ms'?"),
        (["--fall-tilt", "45°"], "; did you mean 'deg'?"),
        (["--set", "speed=1m/sec"], "; did you mean 'm/s'?"),
        # another system's unit: the value to write, as a file's gets (it said only "write
        # the value in m/s", and for km/h listed legdsl's unit symbols)
        (
            ["--set", "speed=2mph"],
            "--set 'speed=2mph': 'mph' is not a unit legdsl knows: write '0.89408 m/s'",
        ),
        (["--set", "speed=9km/h"], "write '2.5 m/s' or '0.15 km/min'"),
        (
            ["--drop", "5%"],
            "--drop 5%: a percentage is written as a plain number: '0.05', not '5%'",
        ),
        (
            ["--set", "k=30%"],  # the user's own number, as language.md says
            "--set 'k=30%': a percentage is written as a plain number: '0.3', not '30%'",
        ),
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


def test_a_unit_apart_from_its_number_is_read_with_it() -> None:
    """'--time 2 s' reads as '--time 2s', as '2 s' does in a file (argparse said
    "unrecognized arguments: s"); a word that is no unit is left to argparse."""
    parser = _parser()
    argv = ["run", "f.leg", "--time", "2", "s", "--dt=0.4", "ms", "--set", "speed=2", "m/s"]
    assert negative_values_joined(argv, parser) == [
        "run", "f.leg", "--time", "2s", "--dt=0.4ms", "--set", "speed=2m/s"
    ]  # fmt: skip
    assert negative_values_joined(["run", "f.leg", "--animate", "s"], parser)[-1] == "s"
    assert negative_values_joined(["metrics", "--from", "3", "runs"], parser)[-1] == "runs"


def test_a_word_meant_as_a_unit_apart_from_its_number_is_told_as_one(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """'--fps 30 fps', '--time 1 sec', '--drop 3 feet': argparse said only "unrecognized
    arguments: fps"; read with the number, the option's own check names the unit to write.
    A word that names a file is left alone (a run directory called 'min')."""
    parser = _parser()
    joined = negative_values_joined(["run", "f.leg", "--time", "1", "sec"], parser)
    assert joined[-1] == "1sec"
    assert negative_values_joined(["run", "f.leg", "--drop", "3", "feet"], parser)[-1] == "3feet"
    assert (
        negative_values_joined(["export-motion", "r", "--fps", "30", "fps"], parser)[-1] == "30fps"
    )
    monkeypatch.chdir(tmp_path)
    (tmp_path / "mins").mkdir()
    assert negative_values_joined(["metrics", "--from", "3", "mins"], parser)[-1] == "mins"


@pytest.mark.parametrize(
    ("args", "told"),
    [
        (["--time", "1", "sec"], "--time 1sec: 'sec' is not a unit legdsl knows"),
        (["--drop", "3", "feet"], "--drop 3feet: 'feet' is not a unit legdsl knows"),
    ],
)
def test_a_run_given_a_word_meant_as_a_unit_says_what_to_write(
    args: list[str], told: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(["run", HOPPER, *args, "--out", str(tmp_path / "run")]) == 2
    assert told in capsys.readouterr().err


def test_a_run_given_a_unit_apart_reads_it(tmp_path: Path) -> None:
    out = tmp_path / "run"
    args = ["--time", "20", "ms", "--dt", "0.4", "ms", "--drop", "1", "cm", "--out", str(out)]
    assert main(["run", HOPPER, *args]) == 0
    options = json.loads((out / "run.json").read_text())["options"]
    assert (options["duration"], options["dt"], options["drop"]) == (0.02, 0.0004, 0.01)


@pytest.mark.parametrize(
    ("args", "told"),
    [
        (["--control-dt", "500Hz"], "write e.g. --control-dt 0.002s (1/500Hz)"),
        (["--record-rate", "5ms"], "write e.g. --record-rate 200Hz (1/5ms)"),
        (["--controller", "hop", "--set", "k_speed=16Hz"], "write e.g. k_speed=0.0625s (1/16Hz)"),
        (["--controller", "hop", "--set", "speed=2m"], "write e.g. speed=2m/s"),
    ],
)
def test_a_frequency_given_for_a_time_is_told_its_inverse(
    args: list[str], told: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    # it said "write e.g. --control-dt 500s", a value 250000 times the one meant
    assert main(["run", HOPPER, *args, "--out", str(tmp_path / "run")]) == 2
    assert told in capsys.readouterr().err


@pytest.mark.parametrize(
    ("value", "told"),
    [
        ("kp=150 N m/rad", "write e.g. 150N*m/rad"),
        ("speed=1 m / s", "write e.g. 1m/s"),
        ("speed=", "'' is not a number with an optional unit"),
        ("speed=one m/s", "'one m/s' is not a number with an optional unit"),
    ],
)
def test_a_unit_with_spaces_in_a_set_value_is_told_how_to_join_it(
    value: str, told: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    # '150 N m/rad' was "not a number with an optional unit", with nothing to write
    argv = ["run", HOPPER, "--controller", "hop", "--set", value, "--out", str(tmp_path / "r")]
    assert main(argv) == 2
    assert told in capsys.readouterr().err


@pytest.mark.parametrize("argv", [["run", HOPPER, "--scale", "2m"], ["scale", HOPPER, "--by", "2m",
                                  "-o", "unused.leg"]])  # fmt: skip
def test_a_length_given_for_the_scale_factor_is_told_what_l_is(
    argv: list[str], capsys: pytest.CaptureFixture[str]
) -> None:
    # it was argparse's "invalid float value: '2m'"
    with pytest.raises(SystemExit) as stop:
        main(argv)
    assert stop.value.code == 2
    err = capsys.readouterr().err
    assert "the scale factor L is a plain number" in err and "not '2m': write 2" in err


@pytest.mark.parametrize(
    ("given", "told"),
    [
        (["--time", "1s"], "in a run of 1s its step 0.0004s becomes 12.6s, longer than the run; "
         "its recording rate 200Hz becomes 0.00632Hz, which records the start alone; give a "
         "--time of 158s or more, or --dt and --record-rate"),
        (["--time", "20s", "--dt", "1ms"], "its recording rate 200Hz becomes 0.00632Hz"),
        (["--time", "1s", "--record-rate", "10Hz"], "give a --time of 12.6s or more, or --dt"),
    ],
)  # fmt: skip
def test_a_step_or_rate_the_scale_stretched_is_told_as_the_scales(
    given: list[str], told: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    # it was "--record-rate 0.00632456Hz records only the start ..." or "--dt 12.6491s is
    # longer than the run": values the user never wrote
    out = tmp_path / "run"
    assert (
        main(["run", HOPPER, "--controller", "hop", "--scale", "1e9", *given, "-o", str(out)]) == 2
    )
    err = capsys.readouterr().err
    assert "--scale 1e+09 stretches the creature's times by sqrt(L) = 3.162e+04" in err
    assert told in err
    assert not out.exists()


def test_a_frequency_given_for_a_turning_rate_is_told_in_turns(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """'--set turn_rate=1Hz' for a rate in deg/s was told 'write e.g. turn_rate=1deg/s', 360
    times slower than the turn a second meant (a scene's '1 Hz' is told so too)."""
    biped = str(Path(HOPPER).with_name("biped.leg"))
    args = ["run", biped, "--controller", "run", "--set", "turn_rate=0.5Hz"]
    assert main([*args, "--out", str(tmp_path / "run")]) == 2
    assert "write e.g. turn_rate=180deg/s (0.5Hz is 0.5 turns a second)" in capsys.readouterr().err
