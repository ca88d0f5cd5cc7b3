"""Frames asked for denser than the run was recorded are the recorded samples' own times."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from legdsl.export.frames import frame_times
from legdsl.export.motion import frame_rate


def test_a_run_recorded_at_100_hz_exports_at_exactly_100_frames_a_second() -> None:
    t = np.arange(201) * 0.01  # 2 s at 100 Hz, as the hexapod records
    frames = frame_times(t, 240.0)
    assert len(frames) == len(t)
    assert np.max(np.abs(frames - t)) < 1e-15
    # the rate USD's timeCodesPerSecond and glTF's extras carry, and BVH's Frame Time
    motion = SimpleNamespace(frames=len(frames), duration=float(frames[-1] - frames[0]))
    assert frame_rate(motion) == 100.0  # type: ignore[arg-type]


def test_a_rate_below_the_recorded_one_is_kept() -> None:
    t = np.arange(385) * 0.0052
    frames = frame_times(t, 60.0)
    assert np.allclose(np.diff(frames), 1 / 60, rtol=1e-12, atol=0)
    assert frames[-1] <= t[-1] < frames[-1] + 1 / 60


def test_the_rate_is_the_asked_one_whatever_the_rounding_of_the_frame_times() -> None:
    for samples in (12, 132, 221):  # 60 fps over these gave 60.00000000000001
        frames = frame_times(np.arange(samples * 4) * 0.0025, 60.0)[:samples]
        motion = SimpleNamespace(frames=len(frames), duration=float(frames[-1] - frames[0]))
        assert frame_rate(motion) == 60.0, samples  # type: ignore[arg-type]
