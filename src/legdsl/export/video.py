"""Render a run to a video (mp4 through ffmpeg, or an animated GIF through Pillow).

Each frame is the HTML player's picture, drawn with matplotlib (Agg) by a view of
``legdsl.export.video_views``: a side view for planar creatures, a perspective view for 3D
ones, the camera following the mass centre, with the player's overlays.
"""

from __future__ import annotations

import importlib.util
import os
import shutil
import subprocess
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from legdsl.analysis.plot import pyplot
from legdsl.export.frames import enough_frames, every_frame
from legdsl.export.motion import Motion, Snapshot
from legdsl.export.player import OVERLAYS
from legdsl.export.video_rates import most_fps
from legdsl.export.video_views import SKY, PerspectiveView, SideView, View
from legdsl.files import atomic_path, refused_in
from legdsl.lang.errors import UsageError

if TYPE_CHECKING:
    from legdsl.pipeline.report import ProgressBar

FFMPEG_HINT = (
    "writing .mp4 needs ffmpeg, which is not installed: pip install 'legdsl[export]' "
    "(its imageio-ffmpeg wheel carries one), or install it with "
    "'apt-get install -y ffmpeg' (Debian/Ubuntu) or 'brew install ffmpeg' (macOS), "
    "or write a .gif instead, which needs no ffmpeg"
)


@dataclass(frozen=True)
class VideoResult:
    path: Path
    frames: int
    seconds: float  # wall time to render and encode
    size: int  # bytes
    span: float = 0.0  # s of the run from its first frame to its last (simulated time)


# ---------------------------------------------------------------- rendering


def render_video(
    motion: Motion,
    path: Path,
    fps: float = 30.0,
    size: tuple[int, int] = (960, 540),
    overlays: tuple[str, ...] = OVERLAYS,
    progress: Callable[[float, float], None] | None = None,
    slow: float = 1.0,
) -> VideoResult:
    """Render ``motion`` to ``path`` (.mp4 or .gif), ``slow`` times slower than real time;
    returns the frame count and timing."""
    suffix = path.suffix.lower()
    if suffix not in (".mp4", ".gif"):
        raise UsageError(f"{path}: a video is written as .mp4 or .gif")
    if suffix == ".mp4" and ffmpeg_exe() is None:
        raise UsageError(FFMPEG_HINT)
    if suffix == ".gif" and importlib.util.find_spec("PIL") is None:
        raise UsageError("writing a .gif needs Pillow: pip install 'legdsl[export]'")
    enough_frames(motion.duration, fps, usual=30.0, slow=slow, top=most_fps(suffix == ".gif"))
    width, height = (size[0] // 2) * 2, (size[1] // 2) * 2
    plt = pyplot()
    start = time.perf_counter()
    fig = plt.figure(figsize=(width / 100, height / 100), dpi=100, facecolor=SKY)
    ax = fig.add_axes((0, 0, 1, 1))
    ax.set_axis_off()
    ax.set_autoscale_on(False)
    view: View = (
        SideView(motion, ax, overlays, width / height)
        if motion.planar
        else PerspectiveView(motion, ax, overlays, width, height)
    )
    if motion.planar:
        ax.set_aspect("auto")
    times = every_frame(motion.duration, fps * slow)  # simulated times, shown 1/fps each
    frames = (_frame(fig, view, motion.at(float(t))) for t in times)

    def report(i: int) -> None:
        if progress is not None:
            progress(times[i], times[-1])

    try:
        with atomic_path(path) as tmp:
            if suffix == ".mp4":
                _write_mp4(frames, tmp, fps, width, height, report)
            else:
                _write_gif(frames, tmp, fps, report)
    finally:
        plt.close(fig)
    took = time.perf_counter() - start
    return VideoResult(path, len(times), took, path.stat().st_size, float(times[-1]))


def _frame(fig: Any, view: View, snap: Snapshot) -> np.ndarray:
    view.update(snap)
    fig.canvas.draw()
    return np.asarray(fig.canvas.buffer_rgba())[..., :3]


def ffmpeg_exe() -> str | None:
    """The system's ffmpeg, or else the one the imageio-ffmpeg wheel carries; None without both."""
    found = shutil.which("ffmpeg")
    if found:
        return found
    try:
        import imageio_ffmpeg
    except ImportError:
        return None
    try:
        return str(imageio_ffmpeg.get_ffmpeg_exe())
    except RuntimeError:  # the wheel for another platform, without a binary
        return None


def _write_mp4(
    frames: Any, path: Path, fps: float, width: int, height: int, report: Callable[[int], None]
) -> None:
    exe = ffmpeg_exe()
    if exe is None:
        raise UsageError(FFMPEG_HINT)
    command = [
        exe, "-y", "-xerror", "-loglevel", "error", "-f", "rawvideo", "-pix_fmt", "rgb24",
        "-s", f"{width}x{height}", "-r", f"{fps:g}", "-i", "-", "-an", "-c:v", "libx264",
        "-pix_fmt", "yuv420p", "-crf", "20", "-threads", "1", "-movflags", "+faststart",
        "-f", "mp4", str(path),
    ]  # fmt: skip
    proc = subprocess.Popen(command, stdin=subprocess.PIPE, stderr=subprocess.PIPE)
    assert proc.stdin is not None and proc.stderr is not None
    try:
        for i, frame in enumerate(frames):
            proc.stdin.write(np.ascontiguousarray(frame).tobytes())
            report(i)
        proc.stdin.close()
    except BrokenPipeError:
        pass
    except BaseException:  # Ctrl-C, SIGTERM, a frame that fails: ffmpeg must not finish the
        proc.kill()  # file (with +faststart it writes it again by name, after its removal)
        proc.wait()
        raise
    error = proc.stderr.read().decode(errors="replace")
    code = proc.wait()
    # a full disk: ffmpeg says so (and, without -xerror, exits 0 leaving a file with no index)
    disk = refused_in(error)
    if disk is not None:
        raise OSError(disk, os.strerror(disk), str(path))
    if code != 0 and any(words in error.lower() for words in _SHORT_OF_MEMORY):
        said = error.strip().splitlines()[0]  # the first line names the allocation refused
        raise UsageError(
            f"ffmpeg ran out of memory encoding the video (it said: {said}): raise the memory limit "
            "(ulimit -v), which ffmpeg shares, and run again"
        )
    if code != 0:  # ffmpeg's own trouble (a missing library, a broken install): not legdsl's
        said = (error.strip().splitlines() or ["nothing"])[-1][-300:]
        raise UsageError(
            f"ffmpeg ({ffmpeg_exe()}) failed with exit status {code} (it said: "
            f"{said}); check that it runs (ffmpeg -version), or render a .gif, which needs none"
        )


# ffmpeg's and its encoders' words for an allocation refused (under ulimit -v, inherited)
_SHORT_OF_MEMORY = ("malloc of size", "cannot allocate memory", "out of memory")


def _write_gif(frames: Any, path: Path, fps: float, report: Callable[[int], None]) -> None:
    from PIL import Image

    images = []
    for i, frame in enumerate(frames):
        images.append(Image.fromarray(frame).quantize(colors=128, method=Image.Quantize.MEDIANCUT))
        report(i)
    # GIF delays are whole 10 ms steps: one delay for all (30 ms at 30 fps) played the run
    # 10% fast; each frame's delay is where the next frame is due, rounded, so none drifts
    due = np.round(np.arange(len(images) + 1) * 100.0 / fps).astype(int)
    durations = [max(2, int(d)) * 10 for d in np.diff(due)]
    images[0].save(
        path, format="GIF", save_all=True, append_images=images[1:], duration=durations, loop=0
    )


def stderr_progress() -> ProgressBar | None:
    """A video's progress bar on stderr when it is a terminal."""
    from legdsl.pipeline.report import ProgressBar

    return ProgressBar() if sys.stderr.isatty() else None
