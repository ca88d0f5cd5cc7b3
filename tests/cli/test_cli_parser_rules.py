"""argparse's ways, changed for every command (``legdsl.cli.parser``): an option of one value
given two was silently the last (``--time 0.1 --time 0.3`` ran 0.3 s, ``-o gen2 --generated
gen3`` wrote gen3); abbreviations were taken (``--tim 0.3``) and unknown options told without
the name meant; '-inf' after an option was "expected one argument"; '2s' for a factor was
"invalid float value"; each was told after a usage dump."""

from __future__ import annotations

from pathlib import Path

import pytest

from legdsl.cli import _parser, main
from legdsl.cli.common import negative_values_joined

HOPPER = str(Path(__file__).resolve().parents[2] / "creatures" / "hopper.leg")


@pytest.fixture(autouse=True)
def _elsewhere(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)  # what a parser that took the option would write, not here


def _refused(argv: list[str], capsys: pytest.CaptureFixture[str]) -> str:
    with pytest.raises(SystemExit) as info:
        main(argv)
    assert info.value.code == 2
    err = capsys.readouterr().err
    assert "usage:" not in err and "Traceback" not in err
    # one line, and for a value a quantity's echo with its caret (tests/cli/test_cli_carets.py)
    assert all(line.startswith("    ") for line in err.splitlines()[1:])
    return err.strip()


@pytest.mark.parametrize(
    ("argv", "told"),
    [
        (["run", HOPPER, "--time", "0.1", "--time", "0.3"],
         "legdsl: --time is given twice (0.1 and 0.3): give it once"),
        (["run", HOPPER, "--drop", "1cm", "--drop=2cm"], "--drop is given twice (1cm and 2cm)"),
        (["run", HOPPER, "--scene", "A", "--scene", "B"], "--scene is given twice (A and B)"),
        (["metrics", "r", "--from", "1", "--from", "2"], "--from is given twice (1 and 2)"),
        (["scale", HOPPER, "--by", "2", "--by", "3"], "--by is given twice (2 and 3)"),
        (["export", HOPPER, "--format", "mjcf", "--anchor-pads", "--no-anchor-pads"],
         "--anchor-pads and --no-anchor-pads say the opposite: give one of them"),
        (["compile", HOPPER, "-o", "gen2", "--generated", "gen3"],
         "-o and --generated are one option, given twice (gen2 and gen3): give it once"),
    ],
)  # fmt: skip
def test_an_option_of_one_value_given_two_is_refused(
    argv: list[str], told: str, capsys: pytest.CaptureFixture[str]
) -> None:
    assert told in _refused(argv, capsys)


def test_the_same_value_twice_is_no_contradiction() -> None:
    args = _parser().parse_args(["run", "f.leg", "--backend", "python", "--backend", "python"])
    assert args.backend == "python"
    assert not hasattr(args, "_legdsl_given")


@pytest.mark.parametrize(
    ("argv", "told"),
    [
        (["run", HOPPER, "--tme", "1"],
         "legdsl: --tme is not an option of legdsl run: did you mean --time"),
        (["run", HOPPER, "--tim", "0.3"], "--tim is not an option of legdsl run: did you mean --time?"),
        (["run", HOPPER, "--con", "x"], "did you mean --controller or --control-dt?"),
        (["run", HOPPER, "--zzzz"], "--zzzz is not an option of legdsl run; 'legdsl run --help'"),
        (["animate", "r", "--slow-motion", "2s"],
         "--slow-motion 2s: --slow-motion takes a plain number, without a unit: write e.g. "
         "--slow-motion 2 (the video 2 times slower than real time)"),
        (["sweep", HOPPER, "--samples", "2.5"],
         "--samples 2.5: --samples takes a whole number, without a unit: write e.g. --samples 2"),
        (["sweep", HOPPER, "--jobs", "2x"], "--jobs 2x: --jobs takes a whole number"),
        (["run", HOPPER, "--integrator", "x"], "--integrator x: choose one of 'euler', 'rk4'"),
        (["run", HOPPER, "--time"], "--time needs a value after it"),
        (["rn", HOPPER], "'rn' is not a command of legdsl (did you mean run?): choose one of"),
    ],
)  # fmt: skip
def test_argparses_mistakes_are_one_line_saying_what_to_write(
    argv: list[str], told: str, capsys: pytest.CaptureFixture[str]
) -> None:
    assert told in _refused(argv, capsys)


def test_minus_infinity_is_a_value_not_an_option(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert negative_values_joined(["run", "f.leg", "--time", "-inf"], _parser())[-1] == (
        "--time=-inf"
    )
    assert main(["run", HOPPER, "--time", "-inf", "--out", str(tmp_path / "r")]) == 2
    err = capsys.readouterr().err
    assert err.startswith("legdsl: --time -inf:") and "expected one argument" not in err


def test_debug_is_taken_after_the_command_too(tmp_path: Path) -> None:
    """'legdsl run --debug FILE' was told '--debug is not an option of legdsl run: did you
    mean --debug?': the whole program's flag, it counts wherever it is given."""
    out, gen = str(tmp_path / "run"), str(tmp_path / "generated")
    assert main(["run", HOPPER, "--debug", "--time", "0.05", "-o", out, "--generated", gen]) == 0
    assert (tmp_path / "run" / "run.json").is_file()
