"""A video's caption lines: a long status message wrapped to the frame's width.

The caption ran a diverged run's message on one line, off the frame's right edge.
"""

from __future__ import annotations

import textwrap

CAPTION_SIZE = 11  # points
CHAR_WIDTH = 0.62  # DejaVu Sans' widest usual characters, in ems (its average is some 0.55)
CAPTION_LINES = 6  # of the status message at most: the rest is on standard error


def wrapped(text: str, width: int) -> list[str]:
    """``text`` in lines of at most ``width`` characters, ``CAPTION_LINES`` of them at most
    (the last then ending in '...')."""
    lines = textwrap.wrap(text, width, break_long_words=True) or [""]
    if len(lines) > CAPTION_LINES:
        lines = lines[:CAPTION_LINES]
        lines[-1] = textwrap.shorten(lines[-1] + " ...", width, placeholder=" ...")
        if not lines[-1].endswith("..."):
            lines[-1] = lines[-1][: width - 4] + " ..."
    return lines


def caption_chars(ax: object) -> int:
    """How many characters of the caption's text fit on a line across ``ax``."""
    fig = ax.figure  # type: ignore[attr-defined]
    width = ax.get_position().width * fig.get_figwidth() * 72  # type: ignore[attr-defined]
    return max(16, int((0.96 * width - 12) / (CAPTION_SIZE * CHAR_WIDTH)))
