"""A run that fell measured nothing in a sweep's table: an outside user's row read 'fell at
1.044 s, strides 1, running_speed 2.73, ...' (its strides before the fall), where docs/api.md
says a metric a run did not measure (it fell ...) is an empty cell, and pandas averaged those
with the runs that lasted. The metrics of a fall are empty cells now, also in a table from
before when the sweep resumes (its rows rewritten); ``legdsl metrics`` of a kept run's
directory still measures it up to the fall."""

from __future__ import annotations

import contextlib
import csv
import math
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from legdsl.api import sweep
from legdsl.cli import main

HOPPER = Path(__file__).resolve().parents[2] / "creatures" / "hopper.leg"
pytestmark = pytest.mark.usefixtures("hopper_modules")


def table(out: Path) -> list[dict[str, str]]:
    with (out / "sweep.csv").open(newline="") as f:
        return list(csv.DictReader(f))


def test_a_fall_has_no_metrics_in_the_table(tmp_path: Path) -> None:
    out = tmp_path / "s"
    assert main(["sweep", str(HOPPER), "--controller", "hop", "--grid", "speed=0.7,1.5",
                 "--grid", "k_speed=0.088", "--time", "2", "--from", "0.5", "--jobs", "1",
                 "--out", str(out), "--generated", str(tmp_path / "generated")]) == 0  # fmt: skip
    ok, fell = table(out)
    assert ok["outcome"] == "ok" and fell["outcome"].startswith("fell at ")
    assert float(ok["running_speed"]) > 0
    assert all(fell[m] == "" for m in sweep.METRICS)
    assert float(fell["simulated"]) < 2.0


def jobs(n: int) -> list[sweep.Job]:
    return [sweep.Job(k, "h.leg", None, "hop", {"kp": 100.0 + k}, {"kp": "N*m/rad"}, (),
                      4.0, 2.0, "g", None) for k in range(n)]  # fmt: skip


def test_a_table_from_before_loses_its_falls_metrics_when_resumed(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    out = tmp_path / "sweep.csv"
    columns = ["run", "kp", "outcome", "simulated", "strides", *sweep.METRICS]
    old = [
        {"run": 0, "kp": 100.0, "outcome": "ok", "simulated": 4.0, "strides": 3},
        {"run": 1, "kp": 101.0, "outcome": "fell at 1.044 s", "simulated": 1.044, "strides": 1},
    ]
    with out.open("w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=columns)
        writer.writeheader()
        for r in old:
            writer.writerow({**r, **dict.fromkeys(sweep.METRICS, 2.73)})

    def rows(todo: list[sweep.Job], _: object) -> Iterator[dict[str, Any]]:
        for job in todo:
            yield {"run": job.index, **job.values, "outcome": "ok", "simulated": 4.0,
                   "strides": 3, **dict.fromkeys(sweep.METRICS, 1.0)}  # fmt: skip

    monkeypatch.setattr(sweep, "run_jobs", rows)
    monkeypatch.setattr(sweep, "Workers", lambda *a: contextlib.nullcontext())
    got = sweep.run_sweep(jobs(3), out, 1)
    assert [r["outcome"] for r in got] == ["ok", "fell at 1.044 s", "ok"]
    assert got[0]["running_speed"] == 2.73 and got[2]["running_speed"] == 1.0
    assert all(math.isnan(got[1][m]) for m in sweep.METRICS)
    assert got[1]["strides"] == 1  # how far it got, kept
