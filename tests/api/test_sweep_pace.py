"""A sweep's time left: an outside user's bar read 21, 18, 16, 14 and 13 s left within one
batch (its rows come back within 20 ms), and later went back up from 8 to 12 s. The pace is
now by arrival of a batch, in simulated seconds, smoothed, and counts down between batches;
and a log says how far the sweep is every 10 s from its start, a stall included (its first
line came with the first rows, 20 s in)."""

from __future__ import annotations

import contextlib
import math
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from legdsl.api import sweep
from legdsl.api.sweep_pace import SweepPace
from legdsl.pipeline import report
from legdsl.pipeline.report import ProgressLog


def batches(workers: int, batch: int, runs: int, seconds: float) -> list[tuple[float, float]]:
    """(wall time, simulated s) of each row: ``workers`` workers, each taking ``batch`` runs
    of 10 s at a time, ``seconds`` of wall time a batch (a little more on one worker), the
    rows of a batch 3 ms apart; one run in five falls at once."""
    rows, clock, k = [], [2.0 + 0.7 * w for w in range(workers)], 0
    while k < runs:
        w = min(range(workers), key=clock.__getitem__)
        clock[w] += seconds * (1.1 if w else 1.0)
        for j in range(min(batch, runs - k)):
            rows.append((clock[w] + 0.003 * j, 0.5 if (k + j) % 5 == 3 else 10.0))
        k += batch
    return sorted(rows)


@pytest.mark.parametrize("workers", [1, 2, 4])
def test_the_time_left_holds_within_a_batch_and_is_near_the_truth(workers: int) -> None:
    rows = batches(workers, 8, 160, 3.0)
    pace = SweepPace(len(rows), workers, 8)
    end, said = rows[-1][0], []
    ticks = [(0.5 * k, None) for k in range(int(end / 0.5))]  # the waits' calls between rows
    for t, sim in sorted([*rows, *ticks], key=lambda e: e[0]):
        if sim is not None:
            pace.row(sim, t)
        said.append((t, pace.left(t)))
    said.sort(key=lambda p: p[0])
    known = [(t, left) for t, left in said if left is not None]
    assert known and known[0][0] < rows[len(rows) // 4][0]  # known within the first quarter
    for (t0, a), (t1, b) in zip(known, known[1:], strict=False):
        if t1 - t0 < 0.1:  # rows of one batch: counting down with the clock, never jumping
            assert a - (t1 - t0) - 1e-9 <= b <= a + 1e-9
    late = [(t, left) for t, left in known if t > rows[len(rows) // 3][0]]
    for t, left in late:  # within a third (and 3 s) of the truth, once a few waves are in
        assert abs(left - (end - t)) <= max(3.0, 0.34 * (end - t)), (t, left, end - t)
    rises = [b - a for (_, a), (_, b) in zip(late, late[1:], strict=False) if b > a]
    assert max(rises, default=0.0) <= 0.25 * late[0][1]  # no lurch back up


def test_a_log_says_how_far_from_the_start_and_during_a_stall(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    clock = [0.0]
    monkeypatch.setattr(report.time, "monotonic", lambda: clock[0])
    monkeypatch.setattr(sweep.time, "monotonic", lambda: clock[0])

    class Pool:
        waiting: Any = None

    pool = Pool()

    def rows(todo: list[sweep.Job], _: object) -> Iterator[dict[str, Any]]:
        for _ in range(25):  # 25 s of starting workers, nothing back, the pool waiting
            clock[0] += 1.0
            pool.waiting()
        for job in todo:
            clock[0] += 1.0
            pool.waiting()
            clock[0] += 1.0
            yield {"run": job.index, **job.values, "outcome": "ok", "simulated": 4.0,
                   "strides": 2, **dict.fromkeys(sweep.METRICS, 1.0)}  # fmt: skip

    monkeypatch.setattr(sweep, "run_jobs", rows)
    monkeypatch.setattr(sweep, "Workers", lambda *a: contextlib.nullcontext(pool))
    jobs = [sweep.Job(k, "h.leg", None, "hop", {"kp": 100.0 + k}, {"kp": "N*m/rad"}, (),
                      4.0, 2.0, "g", None) for k in range(8)]  # fmt: skip
    sweep.run_sweep(jobs, tmp_path / "sweep.csv", 1, ProgressLog("sweep", "runs"))
    lines = capsys.readouterr().err.splitlines()
    assert lines[:2] == [
        "legdsl: sweep: 0 of 8 runs, time left not yet known",
        "legdsl: sweep: 0 of 8 runs, time left not yet known",
    ]
    assert lines[-1] == "legdsl: sweep: 8 of 8 runs"
    assert any("left" in line and "about" in line for line in lines[2:-1])


def test_nothing_before_the_second_batch() -> None:
    pace = SweepPace(16, 1)
    for j in range(8):
        pace.row(10.0, 5.0 + 0.001 * j)
    assert pace.left(6.0) is None and math.isnan(pace.pace)


@pytest.mark.parametrize(
    ("workers", "batch", "seconds"),
    [(2, 8, 0.4), (2, 1, 0.04), (8, 8, 0.3), (1, 1, 0.01), (4, 2, 0.15)],
)
def test_rows_coming_back_steadily_still_tell_the_time_left(
    workers: int, batch: int, seconds: float
) -> None:
    """An outside user's sweep of 400 runs on 2 workers (11 s), and one of 10,000 runs of
    0.5 s (90 s), said 'time left not yet known' to their ends: their rows came back less than
    0.5 s apart, so every row joined one arrival, and a pace needs two. Now, whatever the rows'
    rate, an estimate comes within the first tenth (or 2.5 s of rows), and is near the truth
    after a third."""
    rows = batches(workers, batch, 2000, seconds)
    pace = SweepPace(len(rows), workers, batch)
    end, said = rows[-1][0], []
    for t, sim in rows:
        pace.row(sim, t)
        said.append((t, pace.left(t)))
    known = [(t, left) for t, left in said if left is not None]
    soon = max(rows[len(rows) // 10][0], rows[0][0] + 2.5)
    assert known and known[0][0] < soon, (known[:1], soon)
    assert all(left is not None for t, left in said if soon < t < end - 1)
    for t, left in known:
        if t > rows[len(rows) // 3][0]:  # within a third (and 1 s) of the truth
            assert abs(left - (end - t)) <= max(1.0, 0.34 * (end - t)), (t, left)
