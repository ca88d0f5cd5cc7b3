"""The path report's figures over the asked window, and honest when the runner cuts inside.

An outside user's biped runs: ``legdsl metrics --from 5 --to 8`` printed the progress and laps
made by the run's end (16.9 m where 3 s of running made 4.4 m), and "8.770 m on past its end"
though at 4 s the runner had not reached it; the speed along the path was the pace of the
path's nearest point, 4.333 m/s for a runner spiralling inside a circle at 1.44 m/s, 1.593 m/s
round a square whose corners it cut at 1.516 m/s; and a path missed by less than 1 m got no
note however small it was (0.58 m off a 5 cm circle, 0.41 m off hairpins 0.3 m apart)."""

from __future__ import annotations

from types import SimpleNamespace
from typing import Any

import numpy as np
import pytest

from legdsl.analysis.path_report import followed_reports, path_report, path_size
from legdsl.analysis.path_rows import path_rows
from legdsl.analysis.plot import path_title
from legdsl.ir.paths import PathSpec
from legdsl.sim.path_tracking import PathGeometry


def _line(points: list[tuple[float, float]], closed: bool = False) -> PathSpec:
    return PathSpec(name="route", shape="polyline", points=tuple(points), closed=closed)


def _circle(radius: float, centre: tuple[float, float]) -> PathSpec:
    return PathSpec(name="route", shape="circle", center=centre, radius=radius, turn=1)


def _run(xs: np.ndarray, ys: np.ndarray, dt: float = 0.01) -> Any:
    """A run's trajectory as the report reads it: times and the centre of mass."""
    t = np.arange(len(xs)) * dt
    return SimpleNamespace(t=t, com=np.column_stack([xs, ys, np.full(len(xs), 0.8)]))


def _on_circle(radius: float, speed: float, seconds: float, centre: tuple[float, float]) -> Any:
    """A runner going left round a circle about ``centre`` from straight below it."""
    t = np.arange(int(round(seconds / 0.01)) + 1) * 0.01
    angle = -np.pi / 2 + speed * t / radius
    return _run(centre[0] + radius * np.cos(angle), centre[1] + radius * np.sin(angle))


def _horizontal_speed(tr: Any, t_from: float) -> float:
    at = tr.t >= t_from - 1e-9
    steps = np.diff(tr.com[at, :2], axis=0)
    return float(np.hypot(*steps.T).sum() / (tr.t[at][-1] - tr.t[at][0]))


def test_the_progress_and_laps_are_the_windows() -> None:
    """Round a 5 m circle at 1.5 m/s for 12 s, from 5 to 8 s: 4.5 m, 0.143 laps (it said the
    16.9 m made by 12 s); the rows and the top view's title name that window."""
    spec = _circle(5.0, (0.0, 5.0))
    tr = _on_circle(5.0, 1.5, 12.0, (0.0, 5.0))
    ((_, report),) = followed_reports(tr, [(spec, None)], 5.0, 8.0)
    assert report["progress"] == pytest.approx(4.5, abs=1e-6)
    assert report["laps"] == pytest.approx(4.5 / (10 * np.pi), abs=1e-6)
    rows = dict(path_rows(report))
    assert rows["progress along the path (from 5 s to 8 s)"].startswith("4.500 m (0.143 laps")
    assert path_title("route", report).endswith("0.14 laps (from 5 s to 8 s)")
    # without a window asked, from the start as the summary says, and labelled so
    ((_, whole),) = followed_reports(tr, [(spec, None)], None, None)
    assert whole["progress"] == pytest.approx(18.0, abs=1e-6)
    assert "progress along the path (from 0 s)" in dict(path_rows(whole))


def test_an_open_paths_end_is_where_the_window_ends() -> None:
    """A runner at 1.2 m/s on a 5 m line for 10 s, from 2 to 4 s: at 4 s it is at 4.8 m, short
    of the end: no "on past its end" (it said 8.770 m on, the run's end's)."""
    t = np.arange(1001) * 0.01
    tr = _run(1.2 * t, np.zeros_like(t))
    ((_, report),) = followed_reports(tr, [(_line([(0.0, 0.0), (5.0, 0.0)]), None)], 2.0, 4.0)
    assert report["past_end"] == 0.0
    assert report["progress"] == pytest.approx(2.4, abs=1e-6)
    assert (
        "past its end" not in dict(path_rows(report))["progress along the path (from 2 s to 4 s)"]
    )
    ((_, later),) = followed_reports(tr, [(_line([(0.0, 0.0), (5.0, 0.0)]), None)], 2.0, 6.0)
    assert later["past_end"] == pytest.approx(2.2, abs=1e-6)  # 7.2 m at 6 s


def test_speed_along_the_path_is_never_more_than_the_runners() -> None:
    """Running round a 1 m circle inside a 5 m path about the same centre at 1 m/s: the
    nearest point sweeps the path at 5 m/s, the runner goes 1 m/s along its tangent. Cutting a
    square's corner on the diagonal: its speed along, never its nearest point's jump."""
    spec = _circle(5.0, (0.0, 5.0))
    inside = _on_circle(1.0, 1.0, 12.0, (0.0, 5.0))
    report = path_report(inside, spec, 3.0)
    assert report["path_speed"] == pytest.approx(1.0, rel=1e-3)
    assert report["path_speed"] <= _horizontal_speed(inside, 3.0) + 1e-9
    assert "its progress and laps are those of the path's point nearest" in report["note"]
    # 8 m square; along x to (6, 0), the diagonal to (8, 2), then up: 1 m/s throughout
    square = _line([(0.0, 0.0), (8.0, 0.0), (8.0, 8.0), (0.0, 8.0)], closed=True)
    legs = [np.linspace((0.0, 0.0), (6.0, 0.0), 601), np.linspace((6.0, 0.0), (8.0, 2.0), 284)]
    legs.append(np.linspace((8.0, 2.0), (8.0, 6.0), 401))
    xy = np.vstack(legs)
    cut = _run(xy[:, 0], xy[:, 1])
    report = path_report(cut, square, 0.0)
    assert report["path_speed"] <= _horizontal_speed(cut, 0.0) + 1e-9
    # 6 m along x, 2 m of the diagonal's 2.83 m along a side (cos 45 deg), 4 m up, in 12.85 s:
    # its nearest point made 14 m, 1.09 m/s
    assert report["path_speed"] == pytest.approx(12.0 / 12.85, abs=0.002)


def test_a_path_far_away_reads_right() -> None:
    """A path starting 20 m away, the runner going up towards its line and along it: the speed
    along it is the runner's along its first side, and the report notes that it kept off."""
    t = np.arange(1501) * 0.01
    tr = _run(0.25 * t, np.minimum(1.5 * t, 20.0))
    report = path_report(tr, _line([(20.0, 20.0), (30.0, 20.0)]), 3.0)
    assert report["progress"] == 0.0 and report["past_end"] == pytest.approx(-16.25)
    assert report["path_speed"] == pytest.approx(0.25)
    assert report["note"] and "more than 1 m" in report["note"]


def test_a_miss_is_measured_against_the_paths_size() -> None:
    """0.58 m RMS off a 5 cm circle and 0.41 m off hairpins 0.3 m apart are misses (under the
    1 m that a path of metres needs); 0.3 m beside a straight line, or 1 cm beside a 5 cm line
    the runner goes on past, are not."""
    tiny = _circle(0.05, (0.0, 0.05))
    ring = _on_circle(0.6, 1.5, 6.0, (0.0, 0.05))
    note = path_report(ring, tiny, 3.0)["note"]
    assert note and "half the path's spread (0.050 m" in note
    zigzag = _line([(0.0, 0.0), (2.0, 0.0), (0.0, 0.3), (2.0, 0.6), (0.0, 0.9), (2.0, 1.2)])
    t = np.arange(1001) * 0.01
    wander = _run(0.2 * t, 0.6 + 0.45 * np.sin(t))  # across the hairpins, 0.4 m off
    report = path_report(wander, zigzag, 3.0)
    assert report["lateral_rms"] < 1.0 and report["note"]
    beside = _run(1.5 * t, np.full_like(t, 0.3))
    assert path_report(beside, _line([(0.0, 0.0), (2.0, 0.0)]), 3.0)["note"] is None
    on_past = _run(1.5 * t, np.full_like(t, 0.01))
    assert path_report(on_past, _line([(0.0, 0.0), (0.05, 0.0)]), 3.0)["note"] is None


def test_a_paths_spread() -> None:
    assert path_size(PathGeometry(_circle(0.05, (0.0, 0.0)))) == 0.05
    square = _line([(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)], closed=True)
    assert path_size(PathGeometry(square)) == pytest.approx(1 / np.sqrt(3))
    straight = _line([(0.0, 0.0), (1.0, 0.0), (3.0, 0.0)])
    assert path_size(PathGeometry(straight)) is None
    back = _line([(0.0, 0.0), (6.0, 0.0), (0.0, 0.0)])
    assert path_size(PathGeometry(back)) == pytest.approx(6 / np.sqrt(12))


def test_a_long_paths_row_shows_its_ends() -> None:
    """A waypoints file of 20,000 points printed its whole text in the path row (400,000
    characters); the row shows its first three points and last two, and how many."""
    points = [(0.01 * k, 0.0) for k in range(20001)]
    spec = _line(points)
    t = np.arange(601) * 0.01
    report = path_report(_run(1.5 * t, np.full_like(t, 2.0)), spec, 3.0)
    (row,) = [v for k, v in path_rows(report) if k == "path"]
    assert row == (
        "polyline((0, 0) m, (0.01, 0) m, (0.02, 0) m, ..., (199.99, 0) m, (200, 0) m) (20001 points)"
    )
    assert report["note"] and row in report["note"]  # 2 m off: the note names it so too
    square = _line([(0.0, 0.0), (8.0, 0.0), (8.0, 8.0), (0.0, 8.0)], closed=True)
    assert dict(path_rows(path_report(_run(t, t), square, 3.0)))["path"] == square.describe()
