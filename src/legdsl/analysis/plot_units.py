"""Axis units chosen by the magnitudes a picture shows.

A hopper scaled by 0.0001 was drawn in m and s: its height axis read '1e-5' as an offset over
ticks of 0.25, its time ticks 0.01025 s. An axis whose values are all under 0.1 of its unit
is ticked in milli- (under 1e-3: micro-) units instead, its label saying so; the curves' data
stay in SI units (the marks drawn at times, in seconds, are where they were).
"""

from __future__ import annotations

import re
from typing import Any

PREFIXES = ((0.1, 1.0, ""), (1e-3, 1e3, "m"), (0.0, 1e6, "\u00b5"))  # 0.1 mm reads 100 µm


def prefix_for(most: float) -> tuple[float, str]:
    """(factor, prefix) for an axis whose largest magnitude is ``most``."""
    if not most > 0.0 or most != most:
        return 1.0, ""
    for least, factor, prefix in PREFIXES:
        if most >= least:
            return factor, prefix
    return 1.0, ""


def scale_axis(axis: Any, label: Any, limits: tuple[float, float]) -> None:
    """Tick ``axis`` (a matplotlib XAxis or YAxis) in the prefixed unit its ``limits`` call
    for, and put the prefix into its label's '(m)', '(m/s)' or '(s)'."""
    from matplotlib.ticker import FuncFormatter

    factor, prefix = prefix_for(max(abs(limits[0]), abs(limits[1])))
    if factor == 1.0:
        return
    axis.set_major_formatter(FuncFormatter(lambda v, _pos: f"{v * factor:.4g}"))
    text = label.get_text()
    label.set_text(re.sub(r"\((m/s|m|s)\)", lambda m: f"({prefix}{m.group(1)})", text))


def scale_axes(axes: Any, time_axis: Any) -> None:
    """Each of ``axes``' y axis whose label is in m or m/s, and ``time_axis``'s x axis."""
    for ax in axes:
        if re.search(r"\((m|m/s)\)", ax.yaxis.label.get_text()):
            scale_axis(ax.yaxis, ax.yaxis.label, ax.get_ylim())
    scale_axis(time_axis.xaxis, time_axis.xaxis.label, time_axis.get_xlim())
