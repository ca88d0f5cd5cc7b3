"""The top view's marks of the way the runner went: where its centre of mass was at the
window's start and end, and arrows along its track and along each path, pointing the way each
goes, so that a run out and back along one line (or round a path either way) reads."""

from __future__ import annotations

import re
from typing import Any

import numpy as np

ARROWS = 6  # arrows along the track, evenly by distance (and along each path: PATH_ARROWS)
PATH_ARROWS = 4
TRACK = "k"
PATH = "0.45"  # darker than the path's grey line, which the arrows sit on


def arrows_along(
    points: np.ndarray, count: int, into: float = 0.5
) -> list[tuple[np.ndarray, np.ndarray]]:
    """(place, way) of ``count`` arrowheads along a line through ``points``: each ``into`` one
    of ``count`` equal shares of its length (the middle: 0.5), pointing the way the line goes
    there (a unit vector, along the chord from a hundredth of the length before to one after:
    a stride's sway does not turn it); none along a line without length."""
    if len(points) < 2:
        return []
    steps = np.hypot(*np.diff(points, axis=0).T)
    along = np.concatenate([[0.0], np.cumsum(steps)])
    total = float(along[-1])
    if not np.isfinite(total) or total <= 0:
        return []

    def at(s: float) -> np.ndarray:
        s = min(max(s, 0.0), total)
        return np.array([np.interp(s, along, points[:, 0]), np.interp(s, along, points[:, 1])])

    out = []
    for k in range(count):
        middle = total * (k + into) / count
        chord = at(middle + total / 100) - at(middle - total / 100)
        length = float(np.hypot(*chord))
        if length > 0:
            out.append((at(middle), chord / length))
    return out


def mark_way(ax: Any, track: np.ndarray, times: np.ndarray, paths: list[np.ndarray]) -> None:
    """The start (a dot) and end (a square) of the centre of mass's ``track`` over the
    window, labelled with their times, and arrowheads the way it went and the way each path
    goes."""
    for points in paths:
        # off the shares' middles, so that a path out and back along one line has its arrows
        # each way at different places, not drawn over one another
        for place, way in arrows_along(points, PATH_ARROWS, 0.35):
            _arrow(ax, place, way, PATH, 16)
    for place, way in arrows_along(track, ARROWS):
        _arrow(ax, place, way, TRACK, 14)
    if len(track):
        ax.plot(track[:1, 0], track[:1, 1], "o", color=TRACK, label=f"start, {times[0]:.1f} s")
        ax.plot(track[-1:, 0], track[-1:, 1], "s", color=TRACK, markerfacecolor="white",
                markeredgewidth=1.5, label=f"end, {times[-1]:.1f} s")  # fmt: skip


def _arrow(ax: Any, place: np.ndarray, way: np.ndarray, color: str, size: float) -> None:
    """An arrowhead at ``place`` pointing ``way``, ``size`` points whatever the run's length:
    its shaft is a point long (the top view's axes are equal, so the way is the data's); a
    shaft in data units, a fiftieth of the track, drew 1.8 m chords on a 60 s circle that read
    as track."""
    back = (-float(way[0]), -float(way[1]))
    ax.annotate("", xy=tuple(place), xytext=back, textcoords="offset points",
                annotation_clip=False,
                arrowprops={"arrowstyle": "-|>", "color": color, "lw": 1,
                            "mutation_scale": size, "shrinkA": 0, "shrinkB": 0})  # fmt: skip


def unbroken(text: str) -> str:
    """``text`` with a no-break space between each number and its unit (m, s), so that a
    wrapped title keeps "(from 0 s)" on one line."""
    return re.sub(r"(\d) ([ms])\b", "\\1\xa0\\2", text)
