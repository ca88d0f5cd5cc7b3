"""The top view marks where the window's track starts and ends and which way it went.

An outside user's out-and-back run (6 m along x and back, then on past the start) could not be
read from its top view: one dot, "start", and a line over itself both ways."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt
import numpy as np
import pytest

from legdsl.analysis.top_marks import arrows_along, mark_way


def _out_and_back() -> np.ndarray:
    x = np.concatenate([np.linspace(0.0, 6.0, 601), np.linspace(6.0, -8.0, 1401)])
    return np.column_stack([x, np.zeros_like(x)])


def test_arrows_point_the_way_out_and_the_way_back() -> None:
    arrows = arrows_along(_out_and_back(), 6)
    ways = [float(np.sign(way[0])) for _, way in arrows]
    assert ways == [1.0, 1.0, -1.0, -1.0, -1.0, -1.0]  # 20 m: out 6 m, back 14 m
    assert arrows_along(np.zeros((5, 2)), 6) == []  # standing still: no way to point
    # a path out and back: its arrows each way are at different places
    path = np.array([[0.0, 0.0], [6.0, 0.0], [0.0, 0.0]])
    places = sorted(round(float(p[0]), 3) for p, _ in arrows_along(path, 4, 0.35))
    assert len(set(places)) == 4


def test_the_start_and_the_end_are_marked_with_their_times() -> None:
    fig, ax = plt.subplots()
    track = _out_and_back()
    mark_way(ax, track, np.linspace(0.0, 15.0, len(track)), [np.array([[0, 0], [6, 0], [0, 0]])])
    _, labels = ax.get_legend_handles_labels()
    assert labels == ["start, 0.0 s", "end, 15.0 s"]
    ends = [line.get_xydata()[0] for line in ax.get_lines()]
    assert ends[0] == pytest.approx((0.0, 0.0)) and ends[1] == pytest.approx((-8.0, 0.0))
    assert len(ax.texts) == 6 + 4  # the track's arrows and the path's
    plt.close(fig)


def test_an_arrow_is_a_head_of_one_size_on_the_track_whatever_its_length() -> None:
    """Each arrow was a black chord from 1% of the track's length before a point to 1% after:
    on a 60 s circle, 1.8 m straight strokes that read as track. It is an arrowhead now, on
    the track, its shaft a point long, the same on a 5 m and a 500 m circle."""
    shapes = []
    for radius in (5.0, 500.0):
        turn = np.linspace(0.0, 2 * np.pi, 2001)
        track = radius * np.column_stack([np.sin(turn), 1 - np.cos(turn)])
        fig, ax = plt.subplots()
        mark_way(ax, track, np.linspace(0.0, 60.0, len(track)), [])
        arrows = ax.texts
        assert len(arrows) == 6
        for a in arrows:
            assert a.anncoords == "offset points" and np.hypot(*a.xyann) == pytest.approx(1.0)
            x, y = a.xy  # on the circle
            assert np.hypot(x, y - radius) == pytest.approx(radius, rel=1e-4)
        shapes.append([tuple(np.round(a.xyann, 6)) for a in arrows])
        plt.close(fig)
    assert shapes[0] == shapes[1]
