"""``Run.metrics()`` reports the paths a run followed, as ``legdsl metrics`` does.

Its docstring said "as legdsl metrics --from START --to END", but the command printed a "path
following" report and the API had none. The top view of the same window names it in its
title's laps and marks where the track ended."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import legdsl
from legdsl.analysis.plot import plot_top
from legdsl.pipeline.measure import measure_run

ROOT = Path(__file__).resolve().parents[2]
PATH = "polyline((0, 0) m, (8, 0) m)"


def test_run_metrics_has_the_commands_path_report(
    generated: Path, tmp_path: Path, drawn: list[Any]
) -> None:
    run = legdsl.load(ROOT / "creatures" / "biped.leg", generated=generated).run(
        controller="run", set={"speed": "1.5 m/s"}, time=5, path=PATH
    )
    metrics = run.metrics(start=2, end=4)
    (report,) = metrics.path_reports
    assert (report["from"], report["to"], report["progress_from"]) == (2.0, 4.0, 2.0)
    assert 0 < report["path_speed"] <= 2.0 and report["note"] is None
    table = metrics.path_table()
    assert table.startswith("path following:\n  path") and PATH in table
    assert "progress along the path (from 2 s to 4 s)" in table
    assert metrics.to_dict()["path_reports"] == [report]
    saved = run.save(tmp_path / "run")
    _, printed = measure_run(saved, 2.0, 4.0)
    assert printed == [report]  # legdsl metrics DIR --from 2 --to 4
    assert run.metrics().path_reports[0]["progress_from"] == 0.0  # from the start, untold
    plot_top(saved, tmp_path / "top.png", 2.0, 4.0)
    (ax,) = drawn[-1].axes
    assert "(from 2 s to 4 s)" in ax.get_title().replace("\xa0", " ")
    assert ax.get_legend_handles_labels()[1][-1] == "end, 4.0 s"
