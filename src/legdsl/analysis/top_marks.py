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
    """(tail, head) of ``count`` short arrows along a line through ``points``, ``into`` each
    of ``count`` equal shares of its length (the middle: 0.5), each from a hundredth of the
    length before to one after (the way it goes there); none along a line without length."""
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
        tail, head = at(middle - total / 100), at(middle + total / 100)
        if np.hypot(*(head - tail)) > 0:
            out.append((tail, head))
    return out


def mark_way(ax: Any, track: np.ndarray, times: np.ndarray, paths: list[np.ndarray]) -> None:
    """The start (a dot) and end (a square) of the centre of mass's ``track`` over the
    window, labelled with their times, and arrows the way it went and the way each path goes."""
    for points in paths:
        # off the shares' middles, so that a path out and back along one line has its arrows
        # each way at different places, not drawn over one another
        for tail, head in arrows_along(points, PATH_ARROWS, 0.35):
            _arrow(ax, tail, head, PATH, 13)
    for tail, head in arrows_along(track, ARROWS):
        _arrow(ax, tail, head, TRACK, 11)
    if len(track):
        ax.plot(track[:1, 0], track[:1, 1], "o", color=TRACK, label=f"start, {times[0]:.1f} s")
        ax.plot(track[-1:, 0], track[-1:, 1], "s", color=TRACK, markerfacecolor="white",
                markeredgewidth=1.5, label=f"end, {times[-1]:.1f} s")  # fmt: skip


def _arrow(ax: Any, tail: np.ndarray, head: np.ndarray, color: str, size: float) -> None:
    ax.annotate("", xy=tuple(head), xytext=tuple(tail), annotation_clip=False,
                arrowprops={"arrowstyle": "-|>", "color": color, "lw": 1,
                            "mutation_scale": size, "shrinkA": 0, "shrinkB": 0})  # fmt: skip


def unbroken(text: str) -> str:
    """``text`` with a no-break space between each number and its unit (m, s), so that a
    wrapped title keeps "(from 0 s)" on one line."""
    return re.sub(r"(\d) ([ms])\b", "\\1\xa0\\2", text)
