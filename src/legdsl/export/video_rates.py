"""The frame rates a video is written with, apart so that ``legdsl.export.animate`` (the
command line, cheap to import) and ``legdsl.export.video`` (the rendering) share them."""

from __future__ import annotations

VIDEO_FPS = 1.0, 240.0  # a video's frames per second: slower is a slide show, faster no player
GIF_FPS = 50.0  # a GIF's frames are shown 20 ms at least (browsers slow shorter ones down)
# the slowest video: a 1 s run is 17 minutes of it; --slow-motion 1e6 began a five-week render
# (90 million frames of a 3 s run) and 1e20 an array too large for numpy (an internal error)
MOST_SLOW_MOTION = 1000.0


def most_fps(gif: bool = False) -> float:
    """The most frames per second a GIF, or an .mp4, is written with."""
    return GIF_FPS if gif else VIDEO_FPS[1]
