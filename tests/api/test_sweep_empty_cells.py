"""A metric a sweep's run did not measure is an empty cell of sweep.csv: docs/controllers.md
says a controller without an input 'speed' has its `speed_error` empty, and the table held
'nan' (an outside user's hopper, its 'speed' renamed 'vel'). The table reads back as before:
an empty cell is NaN, for the picture, the resume and the Parquet copy."""

from __future__ import annotations

import contextlib
import csv
import math
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from legdsl.analysis.sweep_plot import plot_sweep
from legdsl.api import sweep


def jobs(n: int) -> list[sweep.Job]:
    return [sweep.Job(k, "vel.leg", None, "hop", {"kp": 100.0 + 50 * k}, {"kp": "N*m/rad"}, (),
                      4.0, 2.0, "g", None) for k in range(n)]  # fmt: skip


@pytest.fixture
def unmeasured(monkeypatch: pytest.MonkeyPatch) -> None:
    """Runs that measured all but the speed error (no commanded speed), and one that fell."""

    def rows(todo: list[sweep.Job], pool: object) -> Iterator[dict[str, Any]]:
        for job in todo:
            fell = job.index == 2
            metrics = {m: (math.nan if fell else 1.0 + job.index) for m in sweep.METRICS}
            yield {"run": job.index, **job.values, "outcome": "fell at 1.000 s" if fell else "ok",
                   "simulated": 1.0 if fell else 4.0, "strides": 0 if fell else 2,
                   **metrics, "speed_error": math.nan}  # fmt: skip

    monkeypatch.setattr(sweep, "run_jobs", rows)
    monkeypatch.setattr(sweep, "Workers", lambda *a: contextlib.nullcontext())


@pytest.mark.usefixtures("unmeasured")
def test_an_unmeasured_metric_is_an_empty_cell_read_back_as_nan(tmp_path: Path) -> None:
    table = tmp_path / "sweep.csv"
    rows = sweep.run_sweep(jobs(3), table, 1)
    assert "nan" not in table.read_text().lower()
    with table.open(newline="") as f:
        cells = list(csv.DictReader(f))
    assert [c["speed_error"] for c in cells] == ["", "", ""]
    assert cells[0]["running_speed"] == "1.0" and cells[2]["running_speed"] == ""
    assert all(math.isnan(r["speed_error"]) for r in rows)  # read back: NaN, as 'nan' was
    assert rows[0]["running_speed"] == 1.0 and math.isnan(rows[2]["running_speed"])
    picture = plot_sweep(rows, ["kp"], "running_speed", tmp_path / "s.png")
    assert picture.stat().st_size > 5_000
    again = sweep.run_sweep(jobs(4), table, 1)  # resumed: the 3 rows kept, rewritten
    assert len(again) == 4 and math.isnan(again[1]["speed_error"])
    assert again[:3] == rows or all(map(math.isnan, (r["speed_error"] for r in again)))
    assert "nan" not in table.read_text().lower()  # the rows kept rewritten empty too
