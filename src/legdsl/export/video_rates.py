"""The frame rates a video is written with, apart so that ``legdsl.export.animate`` (the
command line, cheap to import) and ``legdsl.export.video`` (the rendering) share them."""

from __future__ import annotations

VIDEO_FPS = 1.0, 240.0  # a video's frames per second: slower is a slide show, faster no player
GIF_FPS = 50.0  # a GIF's frames are shown 20 ms at least (browsers slow shorter ones down)


def most_fps(gif: bool = False) -> float:
    """The most frames per second a GIF, or an .mp4, is written with."""
    return GIF_FPS if gif else VIDEO_FPS[1]
