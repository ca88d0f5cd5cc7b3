"""Long work whose standard error is no terminal (a sweep into a log) says how far it is: a
600-run sweep was silent for 23 s in an outside user's log, where a terminal shows a bar."""

from __future__ import annotations

import pytest

from legdsl.pipeline import report
from legdsl.pipeline.report import ProgressLog


def test_a_line_every_ten_seconds_and_one_at_the_end(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    clock = iter([0.0, 4.0, 10.5, 12.0, 21.0, 23.0])
    monkeypatch.setattr(report.time, "monotonic", lambda: next(clock))
    log = ProgressLog("sweep", "runs")
    for done in (0, 100, 260, 300, 520, 600):
        log(done, 600, 20.0 if done < 600 else 0.0)
    assert capsys.readouterr().err.splitlines() == [
        "legdsl: sweep: 260 of 600 runs, about 0m20s left",
        "legdsl: sweep: 520 of 600 runs, about 0m20s left",
        "legdsl: sweep: 600 of 600 runs",
    ]


def test_work_shorter_than_that_says_nothing(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    clock = iter([0.0, 1.0, 2.0])
    monkeypatch.setattr(report.time, "monotonic", lambda: next(clock))
    log = ProgressLog("sweep", "runs")
    for done in (0, 1, 2):
        log(done, 2, None)
    assert capsys.readouterr().err == ""


def test_a_large_count_is_written_in_digits(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """A sweep of a million runs read 'sweep: 1 of 1e+06 runs' (and its bar '1/1e+06')."""
    clock = iter([0.0, 11.0])
    monkeypatch.setattr(report.time, "monotonic", lambda: next(clock))
    log = ProgressLog("sweep", "runs")
    for done in (0.0, 1.0):
        log(done, 1e6, None)
    report.progress_line(2500.0, 1e6, "runs", None)
    err = capsys.readouterr().err
    assert "legdsl: sweep: 1 of 1,000,000 runs, time left not yet known" in err.splitlines()
    assert "2,500/1,000,000 runs" in err
