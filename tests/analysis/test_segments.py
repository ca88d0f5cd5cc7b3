"""Each controller segment's speed from 3 s after its switch, on a synthetic run."""

from __future__ import annotations

import numpy as np
import pytest

from legdsl.analysis.segments import segment_report, segment_table
from legdsl.sim.trajectory import empty


def test_each_segment_is_measured_from_three_seconds_after_its_switch() -> None:
    n = 1201  # 12 s at 100 Hz
    tr = empty(n, 1, 1, 1, 0, q_names=("x",), v_names=("x",), contact_names=("toe",))
    tr.t[:] = np.arange(n) * 0.01
    # 0-5 s: 2 m/s, command 2; 5-12 s: 1 m/s for 3 s (settling), then 1.5 m/s, command 1.6
    tr.com_vel[:, 0] = np.where(tr.t < 5, 2.0, np.where(tr.t < 8, 1.0, 1.5))
    tr.speed_command[:] = np.where(tr.t < 5, 2.0, 1.6)
    segments = [
        {"controller": "run", "from": 0.0, "to": 5.0},
        {"controller": "gallop", "from": 5.0, "to": 12.0},
        {"controller": "run", "from": 12.0},  # a switch at the last sample: nothing to measure
    ]
    report = segment_report(tr, segments)
    assert [r["controller"] for r in report] == ["run", "gallop", "run"]
    assert report[0]["speed"] == pytest.approx(2.0) and report[0]["error_percent"] == 0.0
    assert report[1]["measured_from"] == 8.0
    assert report[1]["speed"] == pytest.approx(1.5)
    assert report[1]["command"] == pytest.approx(1.6)
    assert report[1]["error_percent"] == pytest.approx(-6.25)
    assert report[2]["speed"] is None
    text = segment_table(report)
    assert "gallop" in text and "(-6.2%)" in text and "too short to measure" in text


def test_a_window_shorter_than_a_second_is_too_short_to_measure() -> None:
    """A trot switched at 3 s took over at 3.06 s: its 60 ms after the settling 3 s, under a
    tenth of a stride, gave a speed 12% off; a window under ``SHORTEST`` is not measured."""
    n = 1001  # 10 s at 100 Hz
    tr = empty(n, 1, 1, 1, 0, q_names=("x",), v_names=("x",), contact_names=("toe",))
    tr.t[:] = np.arange(n) * 0.01
    tr.com_vel[:, 0] = 2.0 + np.sin(2 * np.pi * tr.t / 0.77)  # a speed that swings each stride
    tr.speed_command[:] = 2.0
    segments = [
        {"controller": "trot", "from": 0.0, "to": 3.06},
        {"controller": "bound", "from": 3.06, "to": 6.5},
        {"controller": "trot", "from": 6.5},
    ]
    report = segment_report(tr, segments)
    assert report[0]["speed"] is None and report[0]["error_percent"] is None
    assert report[1]["speed"] is None  # 0.44 s from 6.06 to 6.5 s
    assert report[2]["measured_from"] == pytest.approx(9.5) and report[2]["speed"] is None
    text = segment_table(report)
    assert text.count("too short to measure") == 3 and "1 s or more" in text
