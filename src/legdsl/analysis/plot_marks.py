"""Marks on a run's pictures whose size is set in pixels, not seconds: a stance at least a
pixel wide, and controller-switch labels that do not print over one another."""

from __future__ import annotations

from typing import Any

DPI = 100  # the pictures are saved at this many dots per inch
LABEL_LEVELS = 4  # rows of switch labels at most; a label finding no room in them is left out
LABEL_GAP = 4.0  # px between two labels on one row
LABEL_STEP = 11.0  # points from one row of labels to the next (8 pt text)


def seconds_per_pixel(ax: Any, t_from: float, end: float) -> float:
    """How much time one pixel column of ``ax`` spans in the saved picture (laid out)."""
    width = ax.get_window_extent().width * DPI / ax.figure.dpi
    return (end - t_from) / max(width, 1.0)


def visible_bars(
    stances: list[tuple[float, float]], t_from: float, end: float, pixel: float
) -> list[tuple[float, float]]:
    """(start, width) of each stance inside the window, at least ``pixel`` wide: narrower,
    a stance fell between two pixel columns and was not drawn (a 600 s hopper's 913 stances
    became 89 evenly spaced bars, a false gait; a gallop's 0.1 s stances left 4 s blank)."""
    bars = []
    for a, b in stances:
        if b < t_from or a > end:
            continue
        start, stop = max(a, t_from), min(b, end)
        if stop - start < pixel:  # widened to the right, or to the left at the window's end
            start = max(t_from, min(start, end - pixel))
            stop = start + pixel
        bars.append((start, stop - start))
    return bars


def label_levels(spans: list[tuple[float, float]], most: int = LABEL_LEVELS) -> list[int | None]:
    """For labels spanning (left, right) pixels, in time order: the lowest row where no
    label before it reaches within ``LABEL_GAP``, or None when none of ``most`` rows has room."""
    ends: list[float] = []  # the right edge of the last label on each row
    levels: list[int | None] = []
    for left, right in spans:
        free = [k for k, end in enumerate(ends) if left >= end + LABEL_GAP]
        if free:
            level: int | None = free[0]
        elif len(ends) < most:
            level = len(ends)
            ends.append(right)
        else:
            level = None
        if level is not None:
            ends[level] = right
        levels.append(level)
    return levels


def stack_labels(texts: list[Any]) -> int:
    """Move each of ``texts`` (switch labels, in time order, drawn on one row of a laid-out
    figure) up to a row where it overlaps none before it, and remove those with no room
    ('bound', 'gallop' and 'trot' 6 s apart in 600 s read as one word); the rows used."""
    from matplotlib.transforms import offset_copy

    if not texts:
        return 0
    fig = texts[0].figure
    renderer = fig.canvas.get_renderer()
    spans = [(box.x0, box.x1) for box in (t.get_window_extent(renderer) for t in texts)]
    levels = label_levels(spans)
    for text, level in zip(texts, levels, strict=True):
        if level is None:
            text.remove()
        elif level:
            text.set_transform(offset_copy(text.get_transform(), fig, y=level * LABEL_STEP,
                                           units="points"))  # fmt: skip
    return 1 + max((level for level in levels if level is not None), default=0)
