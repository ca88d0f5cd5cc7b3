"""A path report (``legdsl.analysis.path_report``) as the rows ``legdsl run``'s summary,
``legdsl metrics`` and ``GaitMetrics.path_table()`` print, each naming the window it is of."""

from __future__ import annotations

import re
from collections.abc import Mapping
from typing import Any

from legdsl.figures import figure


def path_rows(report: Mapping[str, Any]) -> list[tuple[str, str]]:
    """The report as (label, value) rows for ``legdsl run``'s summary and ``legdsl metrics``."""

    def num(key: str, unit: str) -> str:
        v = report.get(key)
        why = f" ({report['why']})" if report.get("why") else ""
        return f"n/a{why}" if v is None else f"{figure(v)}{unit}"

    window = window_label(report)
    covered = "laps of" if report.get("closed", True) else "of its"  # open: the fraction covered
    progress = f"{num('progress', ' m')} ({num('laps', '')} {covered} {num('length', ' m')})"
    past = report.get("past_end") or 0.0  # beyond an open path's end (or before its start)
    if past > 0:
        progress += f", then {figure(past)} m on past its end along its last side"
    elif past < 0:
        progress += f", and {figure(-past)} m back before its start along its first side"
    speed = f"speed along the path ({window}"
    if report.get("speed_past_end"):
        speed += "; on past its end"
    if report.get("speed_before_start"):
        speed += "; from before its start"
    speed += ")"
    deviation = f"{num('lateral_max', ' m')} / {num('lateral_mean', ' m')}"
    if report.get("why"):  # a creature that goes nowhere (welded): metrics.without_path_travel
        progress = deviation = f"n/a ({report['why']})"
    return [
        ("path", shown_path(str(report["path"]))),
        (f"lateral deviation RMS ({window})", num("lateral_rms", " m")),
        (f"lateral deviation max / mean ({window})", deviation),
        (f"progress along the path ({progress_label(report)})", progress),
        (speed, num("path_speed", " m/s")),
    ]


def path_text(report: Mapping[str, Any]) -> str:
    """The report's rows as the run's summary and ``legdsl metrics`` print them."""
    rows = path_rows(report)
    width = max(len(r[0]) for r in rows)
    return "\n".join(f"  {k:<{width}}  {v}" for k, v in rows)


def window_label(report: Mapping[str, Any]) -> str:
    """The report's window as its rows and the top view's title say it: "from 3 s", and "to
    5 s" where it ends before the run does (``--to``, or a later controller took over)."""
    window = f"from {report['from']:g} s"
    if "followed_from" in report or report.get("to_before_end"):
        window += f" to {report['to']:g} s"
    return window


def progress_label(report: Mapping[str, Any]) -> str:
    """The window the progress and laps were made in: "from 0 s" (the run's start, a takeover
    or ``--from``), and "to 8 s" as ``window_label``'s."""
    return window_label({**report, "from": report.get("progress_from", report["from"])})


LONGEST = 200  # characters of a path's text shown whole in a row or a note
POINT = re.compile(r"\([^()]*\) m")  # a point as PathSpec.describe writes it: "(0.01, 0.001) m"


def shown_path(text: str) -> str:
    """A path's text for a row or a note: whole, or for a polyline too long to read (a
    waypoints file of 20,000 points printed 400,000 characters) its first three points and
    its last two, and how many there are."""
    points = POINT.findall(text)
    if len(text) <= LONGEST or len(points) <= 5:
        return text
    head = text[: text.index(points[0])]
    tail = text[text.rindex(points[-1]) + len(points[-1]) :]
    shown = ", ".join(points[:3]) + ", ..., " + ", ".join(points[-2:])
    return f"{head}{shown}{tail} ({len(points)} points)"
