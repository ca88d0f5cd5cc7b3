"""Faults of the fault hunt of the newest features (faults24): a sweep resumed from a
damaged sweep.csv."""

from __future__ import annotations

from pathlib import Path

import pytest

from legdsl.api.sweep import read_table
from legdsl.lang.errors import UsageError

HEADER = "run,speed,outcome,simulated,strides,running_speed\n"
ROW = "{},1.0,ok,3.0,2,1.13\n"


@pytest.mark.parametrize(("garbage", "many"), [("garbage", "few"), ("1,zz", "few"),
                                               ("x,y,z,w,v,u,t,s", "many")])  # fmt: skip
def test_a_row_of_garbage_inside_the_table_is_named_not_an_internal_error(
    garbage: str, many: str, tmp_path: Path
) -> None:
    """A row of too few or too many cells before the last one (which DictReader fills with
    None) was an internal error, int(None); it is a damaged table, told at its line."""
    table = tmp_path / "sweep.csv"
    table.write_text(HEADER + ROW.format(0) + garbage + "\n" + ROW.format(2))
    with pytest.raises(
        UsageError, match=f"sweep.csv is damaged at line 3: it has too {many} cells"
    ):
        read_table(table)


def test_a_line_cut_short_at_the_end_is_still_dropped(tmp_path: Path) -> None:
    """As after a power cut: the last line half-written is no run's, and is run again."""
    table = tmp_path / "sweep.csv"
    table.write_text(HEADER + ROW.format(0) + ROW.format(1)[:6])
    assert [r["run"] for r in read_table(table)] == [0]
