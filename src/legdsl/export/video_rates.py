"""The frame rates a video is written with, apart so that ``legdsl.export.animate`` (the
command line, cheap to import) and ``legdsl.export.video`` (the rendering) share them, and
the ``--fps`` every export command reads (a number, or a frequency with its unit)."""

from __future__ import annotations

import math
import numbers

from legdsl.lang.errors import UsageError

VIDEO_FPS = 1.0, 240.0  # a video's frames per second: slower is a slide show, faster no player
GIF_FPS = 50.0  # a GIF's frames are shown 20 ms at least (browsers slow shorter ones down)
# the slowest video: a 1 s run is 17 minutes of it; --slow-motion 1e6 began a five-week render
# (90 million frames of a 3 s run) and 1e20 an array too large for numpy (an internal error)
MOST_SLOW_MOTION = 1000.0


def most_fps(gif: bool = False) -> float:
    """The most frames per second a GIF, or an .mp4, is written with."""
    return GIF_FPS if gif else VIDEO_FPS[1]


def positive(value: float | None, flag: str) -> None:
    if value is not None and not 0 < value < math.inf:
        raise UsageError(f"{flag} must be positive and finite, not {value:g}")


def frame_rate(text: str | float | None, flag: str = "--fps") -> float | None:
    """``--fps 30`` or ``--fps 30Hz``: frames per second, a frequency with its unit checked."""
    if getattr(text, "shape", None) == () and getattr(text, "dtype", None) is not None:
        text = text[()]  # type: ignore[index]  # numpy's 0-d array: its number
    if text is None:
        value = None
    elif isinstance(text, numbers.Real) and not isinstance(text, bool):  # 30, np.int64(30)
        try:
            value = float(text)
        except OverflowError:
            size = int(text).bit_length()  # too many digits to print
            raise UsageError(f"{flag} a whole number of about 2**{size}: too large") from None
    elif not isinstance(text, str):  # the API's fps=True or fps=[60]
        raise UsageError(f"{flag}{text!r}: give the frames per second as a number, e.g. 60")
    else:
        try:  # a bare number (inf and nan too, told as such below): frames per second; not
            value = float(text if text.isascii() and "_" not in text else "?")  # 6_0, as 60
        except ValueError:
            from legdsl.pipeline.options import Numeric, read_numeric

            value = read_numeric(flag, text, Numeric("frequency", "Hz"))
    positive(value, flag)
    return value


def video_fps(value: float | None, default: float, gif: bool = False) -> float:
    """``--fps`` of a video: one that no player shows as given, or that would render for
    hours (a million frames a second), is refused."""
    fps = default if value is None else value
    top = most_fps(gif)
    if not VIDEO_FPS[0] <= fps <= top:
        more = "; write an .mp4 for more" if gif else ""
        raise UsageError(
            f"--fps {fps:g}: a{' GIF' if gif else 'n .mp4'} shows {VIDEO_FPS[0]:g} to {top:g} "
            f"frames per second{more}"
        )
    return fps
