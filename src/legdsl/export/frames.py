"""Frame times and resampling: where a drawing of a run has its frames, and the run's values
there.

``frame_times`` gives an export's keyframes (at most as dense as the samples), ``every_frame``
a video's (one every 1/fps, as a player shows them), and ``enough_frames`` refuses a rate that
would keep one frame of a run that moves. ``interpolate`` is linear between samples;
``interpolate_q`` keeps a 3D root's quaternion a unit one.
"""

from __future__ import annotations

import math

import numpy as np

from legdsl.export.video_rates import MOST_SLOW_MOTION
from legdsl.ir.model import Model
from legdsl.lang.errors import UsageError
from legdsl.pipeline.report import time_left


def enough_frames(
    span: float,
    fps: float,
    usual: float = 60.0,
    slow: float = 1.0,
    top: float | None = None,
    flag: str = "--fps",
) -> None:
    """A frame rate keeping one frame of a run that moves is refused: --fps 1e-3 wrote one
    keyframe, and a video or replay of a 0.5 s run at --fps 1 was one still picture. The
    count is ``every_frame``'s and ``frame_times``'s (``span`` is what the frames cover;
    a video ``slow`` times slower than real time has ``fps * slow`` frames a simulated second).
    A video (``top``, the most frames a second its format shows) is told the least
    ``--slow-motion`` first: the least --fps of a 4.5 ms run, 223, was more than a GIF shows.
    ``flag`` names the rate as the caller takes it (the API's ``fps=``). A video slower than
    ``MOST_SLOW_MOTION`` is refused, saying how many frames it would have been."""
    if top is not None and slow > MOST_SLOW_MOTION:
        raise UsageError(too_slow(span, fps, slow))
    if span > 0 and math.floor(span * fps * slow + 1e-9) < 1:

        def rate(value: float) -> str:
            return f"{flag}{value:g}" if flag.endswith("=") else f"{flag} {value:g}"

        slowed = f" at --slow-motion {slow:g}" if slow != 1.0 else ""
        said = f"{rate(fps)}{slowed} gives one frame of this {span:.3g} s run; two frames need "
        least_fps = least_above(1 / (span * slow))
        if top is None:
            raise UsageError(f"{said}{rate(least_fps)} or more (the default is {usual:g})")
        faster = f", or {rate(least_fps)} or more" if least_fps <= top else ""
        raise UsageError(
            f"{said}--slow-motion {least_above(1 / (span * fps)):g} or more{faster} (a video "
            "shows --fps times --slow-motion frames a simulated second)"
        )


def too_slow(span: float, fps: float, slow: float) -> str:
    """Why a video ``slow`` times slower than real time is refused: its frames, and how long
    it would play (``every_frame``'s count, each frame shown 1/fps)."""
    frames = math.floor(span * fps * slow + 1e-9) + 1
    count = f"{frames:,}" if frames < 1e12 else f"{frames:.3g}"
    seconds = frames / fps
    years = seconds / (86400 * 365.25)
    plays = (
        time_left(seconds)
        if years < 1
        else f"{years:,.0f} years"
        if years < 1e6
        else f"{years:.3g} years"
    )
    return (
        f"--slow-motion {slow:g}: this {span:.3g} s run would be {count} frames, about {plays} "
        f"of video at --fps {fps:g}; a video is at most {MOST_SLOW_MOTION:g} times slower than "
        f"real time (--slow-motion {MOST_SLOW_MOTION:g} or less)"
    )


def least_above(value: float, digits: int = 3) -> float:
    """``value`` rounded up to ``digits`` significant digits (within 1e-9 of it: 1/4 s is 0.25),
    so that it is at least ``value`` as written: the least a message can name."""
    scale = 10.0 ** (digits - 1 - math.floor(math.log10(value)))
    return math.ceil(value * scale * (1 - 1e-10)) / scale


def frame_times(t: np.ndarray, fps: float) -> np.ndarray:
    """Frame times from the first to the last sample at ``fps`` (never denser than the samples)."""
    span = float(t[-1] - t[0])
    if len(t) < 2 or span <= 0:
        return t[:1].copy()
    recorded_fps = (len(t) - 1) / span
    # asked for as many frames as were recorded or more: the samples' own times (a step of
    # 1/(recorded rate (1 + 1e-9)) left the frames 1e-9 off them and the rate 100.0000001)
    step = 1.0 / fps if fps < recorded_fps * (1 - 1e-9) else span / (len(t) - 1)
    n = int(math.floor(span / step + 1e-9)) + 1
    return t[0] + step * np.arange(n)


def every_frame(span: float, fps: float) -> np.ndarray:
    """0, 1/fps, 2/fps, ... up to ``span`` (and one due within 1e-9 frame after it): a
    video's frame times, each shown for 1/fps, from a run's start."""
    return np.arange(int(math.floor(span * fps + 1e-9)) + 1) / fps


def interpolate(t: np.ndarray, values: np.ndarray, at: np.ndarray) -> np.ndarray:
    """Linear interpolation of ``values`` (N, ...) sampled at ``t`` (N,) to the times ``at``."""
    if len(t) == 1:
        return np.repeat(values[:1], len(at), axis=0)
    i = np.clip(np.searchsorted(t, at, side="right") - 1, 0, len(t) - 2)
    a = np.clip((at - t[i]) / (t[i + 1] - t[i]), 0.0, 1.0)
    # a frame a rounding off a sample is that sample (a weight 1e-15 off, times a diverged step)
    a = np.where(a < 1e-9, 0.0, np.where(a > 1 - 1e-9, 1.0, a))
    a = a.reshape((-1,) + (1,) * (values.ndim - 1))
    return (1 - a) * values[i] + a * values[i + 1]


def interpolate_q(model: Model, t: np.ndarray, q: np.ndarray, at: np.ndarray) -> np.ndarray:
    """Generalized positions at the times ``at``; a 3D root's quaternion stays a unit quaternion."""
    if not model.joints[0].is_free_3d or len(t) == 1:
        return interpolate(t, q, at)
    q = q.copy()
    dots = np.sum(
        q[1:, 3:7] * q[:-1, 3:7], axis=1
    )  # keep each sample in its predecessor's hemisphere
    q[:, 3:7] *= np.concatenate([[1.0], np.cumprod(np.where(dots < 0, -1.0, 1.0))])[:, None]
    out = interpolate(t, q, at)
    out[:, 3:7] /= np.linalg.norm(out[:, 3:7], axis=1, keepdims=True)
    return out
