"""A tune larger than it takes is refused, naming the option: --popsize 100000000 ran out of
memory ('ask for less (a shorter --time, fewer --jobs)', never --popsize), --popsize 10000000
ran minutes with no line, --generations 1000000000 told 'about 122240633 s left'. Long times
left are written as a sweep writes them."""

from __future__ import annotations

from pathlib import Path

import pytest

from legdsl.api.tune_pace import wall
from legdsl.cli import main

ROOT = Path(__file__).resolve().parents[2]


@pytest.mark.parametrize(
    ("extra", "said"),
    [
        (["--popsize", "100000000"], "--popsize 100000000: more than a tune takes (10,000); "
                                     "give --popsize 10000 or fewer"),
        (["--generations", "1000000000"], "--generations 1000000000: more than a tune takes "
                                          "(100,000); give --generations 100000 or fewer"),
        (["--generations", "50000", "--popsize", "100"],
         "50,000 generations of 100 candidates at 2 speeds are 10,000,000 runs, more than a "
         "tune takes (1,000,000)"),
    ],
)  # fmt: skip
def test_a_tune_too_large_is_refused_naming_the_option(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], extra: list[str], said: str
) -> None:
    code = main([
        "tune", str(ROOT / "creatures" / "hopper.leg"), "--controller", "hop",
        "--param", "kp=50:600", "--speeds", "1,2", "--time", "1", "--from", "0",
        "--out", str(tmp_path / "t"), "--generated", str(tmp_path / "g"), *extra,
    ])  # fmt: skip
    assert code == 2
    assert said in capsys.readouterr().err
    assert not (tmp_path / "t").exists()


def test_long_times_left_are_written_as_a_sweep_writes_them() -> None:
    assert wall(0.3) == "0 s"
    assert wall(59.4) == "59 s"
    assert wall(65) == "1m05s"
    assert wall(50000) == "13h53m"
    assert wall(122240633) == "1414d19h"


@pytest.mark.parametrize(
    ("time", "t_from", "said"),
    [
        ("1e300", "1", "--time '1e300': the closing runs, twice --time, would be 5e+303 steps "
                       "(dt 0.0004 s, "),
        ("1e-9", "0", "--time '1e-9': a run shorter than one step (dt 0.0004 s, "),
    ],
)  # fmt: skip
def test_a_time_the_runs_cannot_take_is_told_in_tunes_options(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], time: str, t_from: str, said: str
) -> None:
    """It was told in the Python API's words, 'run_many(): runs[0]: time=1e+300 is ... give
    time=3.6e+12 or less, or a longer step (dt=, ...)', after the start's runs began."""
    code = main([
        "tune", str(ROOT / "creatures" / "hopper.leg"), "--controller", "hop",
        "--param", "kp=50:600", "--speeds", "1", "--time", time, "--from", t_from,
        "--out", str(tmp_path / "t"), "--generated", str(tmp_path / "g"),
    ])  # fmt: skip
    assert code == 2
    err = capsys.readouterr().err
    assert said in err
    assert f"\n    --time {time}\n           ^{'~' * (len(time) - 1)}\n" in err
    assert "run_many" not in err and "dt=" not in err and "--dt " not in err
    assert not (tmp_path / "t").exists()
