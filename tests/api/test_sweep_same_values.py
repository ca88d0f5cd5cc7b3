"""A sweep's values written in other units are the same sweep, and a grid's values are the
numbers written: an outside user's `--grid speed=29cm/s,57cm/s` (0.5700000000000001 m/s) after
`speed=0.29,0.57`, and `--set height=57cm` after `height=0.57m`, were refused as 'another
sweep'; `--grid speed=0.3:0.9:3` stored 0.6000000000000001, and its resume written
`speed=0.3,0.6,0.9` was refused too."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from legdsl.api.sweep import parse_axis
from legdsl.cli import main
from legdsl.lang.units import parse_unit
from legdsl.pipeline.settings import parse_given

ROOT = Path(__file__).resolve().parents[2]
HOPPER = ROOT / "creatures" / "hopper.leg"
DIMS = {"speed": parse_unit("m/s")[1], "tilt": parse_unit("deg")[1]}

pytestmark = pytest.mark.usefixtures("hopper_modules")


def test_a_grids_values_are_the_numbers_written() -> None:
    assert parse_axis("grid", "speed=0.3:0.9:3", DIMS).values == (0.3, 0.6, 0.9)
    assert parse_axis("grid", "speed=0.1:0.7:7", DIMS).values == (0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7)
    assert parse_axis("grid", "speed=30cm/s:90cm/s:3", DIMS).values == (0.3, 0.6, 0.9)
    # LO and HI as `legdsl run --set` reads them: a row runs again as --set of the value written
    ends = parse_axis("grid", "speed=57cm/s:1m/s:2", DIMS).values
    assert ends == (parse_given("57cm/s", "--set").value, 1.0)
    assert parse_axis("grid", "speed=1:1:1", DIMS).values == (1.0,)


def sweep(tmp_path: Path, *given: str) -> int:
    return main(["sweep", str(HOPPER), "--controller", "hop", *given, "--time", "0.3",
                 "--from", "0.1", "--jobs", "1", "--out", str(tmp_path / "out"),
                 "--generated", str(tmp_path / "generated")])  # fmt: skip


def test_the_same_values_in_other_units_are_the_same_sweep(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert sweep(tmp_path, "--grid", "speed=0.29,0.57", "--set", "height=0.57m") == 0
    plan = (tmp_path / "out" / "sweep.json").read_text()
    capsys.readouterr()
    assert sweep(tmp_path, "--grid", "speed=29cm/s,57cm/s", "--set", "height=57cm") == 0
    said = capsys.readouterr()
    assert "2 runs, 2 of them from before" in said.out, said.err
    # the plan as first run, to the bit: its runs take the values its rows were run with
    assert (tmp_path / "out" / "sweep.json").read_text() == plan
    assert json.loads(plan)["runs"][1]["speed"] == 0.57


def test_a_range_resumed_as_its_list(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert sweep(tmp_path, "--grid", "speed=0.3:0.9:3") == 0
    runs = json.loads((tmp_path / "out" / "sweep.json").read_text())["runs"]
    assert [r["speed"] for r in runs] == [0.3, 0.6, 0.9]
    assert ",0.6," in (tmp_path / "out" / "sweep.csv").read_text()
    capsys.readouterr()
    assert sweep(tmp_path, "--grid", "speed=0.3,0.6,0.9") == 0
    assert "3 runs, 3 of them from before" in capsys.readouterr().out
