"""The path report past an open path's end, and the window its rows name.

A runner goes on along an open path's last side past its end (docs/biped.md): its lateral
deviation was measured from that side's line while its speed along the path came from the
tracker's progress, which stops at the end (1.455 m/s reported as 0.202 m/s). And ``legdsl
metrics --to 5`` labelled a 3 to 5 s window "from 3 s", as if it ran to the run's end."""

from __future__ import annotations

from types import SimpleNamespace
from typing import Any

import numpy as np
import pytest

from legdsl.analysis.path_report import path_report
from legdsl.analysis.path_rows import path_rows
from legdsl.analysis.plot import path_title
from legdsl.ir.paths import PathSpec


def _line(points: list[tuple[float, float]], closed: bool = False) -> PathSpec:
    return PathSpec(name="route", shape="polyline", points=tuple(points), closed=closed)


def _run(xs: np.ndarray, ys: np.ndarray, dt: float = 0.01) -> Any:
    """A run's trajectory as the report reads it: times and the centre of mass."""
    t = np.arange(len(xs)) * dt
    return SimpleNamespace(t=t, com=np.column_stack([xs, ys, np.full(len(xs), 0.8)]))


def _rows(report: dict[str, Any]) -> dict[str, str]:
    return dict(path_rows(report))


def test_speed_along_an_open_path_goes_on_past_its_end() -> None:
    """1.5 m/s along x for 10 s on a 5 m line: 1.5 m/s from 3 s, though the line ends at 3.33 s
    (it said 0.071 m/s: 0.5 m over 7 s); the progress row says how far on it ran."""
    t = np.arange(1001) * 0.01
    tr = _run(1.5 * t, 0.02 * np.ones_like(t))
    report = path_report(tr, _line([(0.0, 0.0), (5.0, 0.0)]), 3.0)
    assert report["path_speed"] == pytest.approx(1.5)
    assert report["lateral_rms"] == pytest.approx(0.02)  # from the last side's line, as before
    assert report["progress"] == pytest.approx(5.0)  # the path itself: all of it
    assert report["laps"] == pytest.approx(1.0)
    assert report["past_end"] == pytest.approx(10.0)  # at x = 15 m
    rows = _rows(report)
    assert rows["progress along the path (from 0 s)"] == (
        "5.000 m (1.000 of its 5.000 m), then 10.000 m on past its end along its last side"
    )
    label = "speed along the path (from 3 s; on past its end)"
    assert rows[label] == "1.500 m/s"


def test_past_a_bent_paths_end_along_its_last_side_only() -> None:
    """An L: along x to (4, 0), up y to (4, 3), then on up y: the way on is along the last side
    (y), not the first; a window wholly before the end says nothing of it."""
    xs = np.concatenate([np.linspace(0.0, 4.0, 401), np.full(600, 4.0)])
    ys = np.concatenate([np.zeros(401), np.linspace(0.01, 6.0, 600)])
    tr = _run(xs, ys)  # 1 m/s along x for 4 s, then 1 m/s up y for 6 s: past the end from 7 s
    spec = _line([(0.0, 0.0), (4.0, 0.0), (4.0, 3.0)])
    on = path_report(tr, spec, 5.0)
    assert on["path_speed"] == pytest.approx(1.0)
    assert on["past_end"] == pytest.approx(3.0)
    before = path_report(tr, spec, 0.5, 3.0)
    assert before["path_speed"] == pytest.approx(1.0)
    assert "speed_past_end" not in before
    assert "speed along the path (from 0.5 s to 3 s)" in _rows(before)


def test_before_an_open_paths_start_along_its_first_side() -> None:
    """A runner coming up to the start from 2 m behind it: its speed is counted along the
    first side's line, as its lateral deviation is measured from it."""
    t = np.arange(401) * 0.01
    tr = _run(-2.0 + 1.0 * t, np.zeros_like(t))
    report = path_report(tr, _line([(0.0, 0.0), (5.0, 0.0)]), 0.5, 1.5)
    assert report["path_speed"] == pytest.approx(1.0)
    label = "speed along the path (from 0.5 s to 1.5 s; from before its start)"
    assert _rows(report)[label] == "1.000 m/s"


def test_a_closed_path_has_no_end_to_run_past() -> None:
    t = np.arange(1001) * 0.01
    tr = _run(1.5 * t, np.zeros_like(t))
    square = _line([(0.0, 0.0), (5.0, 0.0), (5.0, 5.0), (0.0, 5.0)], closed=True)
    report = path_report(tr, square, 3.0)
    assert "past_end" not in report and "speed_past_end" not in report


def test_a_window_that_ends_before_the_run_says_so() -> None:
    """``legdsl metrics --from 3 --to 5`` measures 3 to 5 s: its rows and the top view's title
    say "from 3 s to 5 s", as ``legdsl run``'s do for a span a switch ends; to the run's end
    (or past it) they say "from 3 s" alone."""
    t = np.arange(1001) * 0.01
    tr = _run(1.5 * t, 0.1 * np.sin(t))
    spec = _line([(0.0, 0.0), (20.0, 0.0)])
    window = path_report(tr, spec, 3.0, 5.0)
    rows = _rows(window)
    by_hand = np.sqrt(np.mean((0.1 * np.sin(t[300:501])) ** 2))  # 3 to 5 s: 0.073 m
    assert rows["lateral deviation RMS (from 3 s to 5 s)"] == f"{by_hand:.3f} m"
    assert window["lateral_rms"] == pytest.approx(by_hand)
    assert "speed along the path (from 3 s to 5 s)" in rows
    assert "(from 3 s to 5 s)" in path_title("route", window)
    for t_to in (None, 10.0, 12.0):
        assert "lateral deviation RMS (from 3 s)" in _rows(path_report(tr, spec, 3.0, t_to))
