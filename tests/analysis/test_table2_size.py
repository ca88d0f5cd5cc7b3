"""``legdsl metrics --table2`` on a run of a creature of another size than the one Table 2's
gait is for says so: a kangaroo scaled by 10 compared its 1.2 s stride with the animal's
0.35 s without a word about its size."""

from __future__ import annotations

import math
from pathlib import Path

import pytest
from conftest import CREATURES

from legdsl.analysis.table2 import TABLE2, TIME_UNIT, size_note
from legdsl.cli import main


def test_every_gait_of_table_2_knows_the_size_it_is_for() -> None:
    assert set(TIME_UNIT) == set(TABLE2)
    assert size_note("kangaroo hop", TIME_UNIT["kangaroo hop"]) is None
    assert size_note("kangaroo hop", TIME_UNIT["kangaroo hop"] * 1.02) is None  # 4% larger
    said = size_note("kangaroo hop", TIME_UNIT["kangaroo hop"] * math.sqrt(10))
    assert said is not None and "10 times the size" in said and "3.16 times as large" in said
    small = size_note("quadruped trot", 0.1)  # a quadruped scaled by 0.01
    assert small is not None and "0.01 times the size" in small


@pytest.mark.parametrize(("scale", "noted"), [(None, False), ("10", True)])
def test_metrics_notes_a_run_of_another_size(
    scale: str | None,
    noted: bool,
    generated: Path,
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
) -> None:
    out = tmp_path / "run"
    sized = (
        ["--scale", scale, "--set", "speed=15.8m/s", "--time", "3.2"] if scale else ["--time", "1"]
    )
    args = ["run", str(CREATURES / "kangaroo.leg"), "--controller", "hop", *sized,
            "--generated", str(generated), "--out", str(out)]  # fmt: skip
    assert main(args) == 0
    capsys.readouterr()
    assert (
        main(["metrics", str(out), "--table2", "kangaroo hop", "--generated", str(generated)]) == 0
    )
    err = capsys.readouterr().err
    assert ("times the size of the one Table 2's kangaroo hop is for" in err) == noted, err
    if noted:
        assert "this creature is 10 times the size" in err
