"""The running speed (and its error) is the strides' mean weighted by their durations: the
distance the centre of mass ran along the heading over the strides' time. A plain mean, each
stride counting once, read an outside user's stumbling biped at 1.035 m/s (+3.5%) where it ran
0.962 (-3.8%): a tune could keep a candidate that missed its speed."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import legdsl
from legdsl.analysis.rows import stat

ROOT = Path(__file__).resolve().parents[2]


def test_a_weighted_mean_counts_each_stride_by_its_duration() -> None:
    speeds, durations = [2.0, 0.5, math.nan], [0.25, 1.0, 3.0]  # a stumble, a stride, a NaN
    row = stat("running_speed", "running speed (m/s)", speeds, durations)
    assert row.value == pytest.approx((2.0 * 0.25 + 0.5 * 1.0) / 1.25)
    assert row.std == pytest.approx(np.std([2.0, 0.5], ddof=1)) and row.n == 2
    # and says so (metrics.json's "how" said "mean", a reader's plain mean of the strides)
    assert row.how == "weighted mean" and stat("k", "l", speeds).how == "mean"


def test_the_bounds_running_speed_is_its_distance_over_its_strides_time(generated: Path) -> None:
    """The bound's strides are uneven (fore and hind pairs): its plain mean read 2.079 m/s at
    2 m/s where it ran 2.03."""
    run = legdsl.load(ROOT / "creatures" / "quadruped.leg", generated=generated).run(
        "bound", set={"speed": "2 m/s"}, time=10
    )
    metrics = run.metrics(start=3)
    strides = metrics.per_stride
    t, x = run["t"], run["com.x"]
    a, b = np.searchsorted(t, strides["t_start"][0]), np.searchsorted(t, strides["t_end"][-1])
    ran = (x[b] - x[a]) / (t[b] - t[a])
    assert metrics.value("running_speed") == pytest.approx(ran, abs=2e-3)
    assert metrics.value("speed_error") == pytest.approx(ran - 2.0, abs=2e-3)
