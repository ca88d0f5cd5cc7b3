"""A sweep table from before a metric was a column (``running_speed_std``), or whose header was
edited (``speed_error`` renamed), drawn: ``--plot running_speed_std`` was an internal error
(KeyError in sweep_plot.py) for an outside user, where docs/api.md says such rows are kept with
that cell empty. The picture is drawn from what there is, and a note says the column is
missing."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

import pytest

from legdsl.analysis.sweep_plot import plot_sweep
from legdsl.api.sweep_cli import _say_unmeasured


def old_rows(n: int, lacking: str) -> list[dict[str, Any]]:
    rows = []
    for k in range(n * n):
        row = {"run": k, "speed": 0.5 + k // n, "k_speed": 0.04 + 0.01 * (k % n),
               "outcome": "ok" if k != 2 else "fell at 1.000 s", "running_speed": 1.0 + k,
               "running_speed_std": 0.1 * k, "speed_error": 0.2 * k}  # fmt: skip
        del row[lacking]
        rows.append(row)
    return rows


@pytest.mark.parametrize("lacking", ["running_speed_std", "speed_error"])
@pytest.mark.parametrize("names", [["speed"], ["speed", "k_speed"]])
def test_a_column_the_table_lacks_is_drawn_empty_and_said(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], lacking: str, names: list[str]
) -> None:
    rows = old_rows(3, lacking)
    if len(names) == 1:
        rows = rows[:3]
    picture = plot_sweep(rows, names, lacking, tmp_path / "s.png")
    assert picture.stat().st_size > 5_000
    args = argparse.Namespace(out=str(tmp_path), controller="hop", t_from=2.0)
    _say_unmeasured(rows, lacking, args, None, picture)
    err = capsys.readouterr().err
    assert f"sweep.csv has no column {lacking}" in err and "shows none" in err
    assert "Traceback" not in err


def test_rows_from_before_beside_new_ones_are_told_by_number(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    rows = old_rows(2, "running_speed_std") + [
        {**r, "run": r["run"] + 4, "running_speed_std": 0.3} for r in old_rows(2, "speed_error")
    ]
    for r in rows[4:]:
        r["speed"] += 5
    plot_sweep(rows, ["speed", "k_speed"], "running_speed_std", tmp_path / "s.png")
    args = argparse.Namespace(out=str(tmp_path), controller="hop", t_from=2.0)
    _say_unmeasured(rows, "running_speed_std", args, None, tmp_path / "s.png")
    assert "4 of its rows have that cell empty" in capsys.readouterr().err
