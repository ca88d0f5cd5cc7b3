"""Means and spreads of finite numbers of any size: a sum of values near a double's largest
(a speed command of 1e308 m/s, accepted as finite) overflowed to infinity in numpy's mean,
which warned ('overflow encountered in reduce') and made the command's mean, its error and
their summaries NaN. Each is taken of the values divided by the largest of them, then
multiplied back: finite whenever the values are."""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np


def _scaled(x: np.ndarray) -> tuple[np.ndarray, float]:
    most = float(np.max(np.abs(x))) if x.size else 0.0
    return (x / most, most) if most > 0 else (x, 1.0)


def mean(
    values: Sequence[float] | np.ndarray, weights: Sequence[float] | np.ndarray | None = None
) -> float:
    """The mean of ``values`` (all finite; weighted by ``weights``, finite and not negative,
    where given and their sum is more than 0); NaN for none."""
    x = np.asarray(values, dtype=float)
    if not x.size:
        return math.nan
    unit, most = _scaled(x)
    if weights is not None:
        w = np.asarray(weights, dtype=float)
        if w.sum() > 0:
            return most * float(np.sum(unit * (w / w.max())) / np.sum(w / w.max()))
    return most * float(np.mean(unit))


def finite_mean(values: np.ndarray) -> float:
    """The mean of the finite ones of ``values``; NaN when none is."""
    return mean(values[np.isfinite(values)])


def spread(values: Sequence[float] | np.ndarray) -> float:
    """The sample standard deviation of ``values`` (all finite); NaN for fewer than two."""
    x = np.asarray(values, dtype=float)
    if x.size < 2:
        return math.nan
    unit, most = _scaled(x)
    return most * float(np.std(unit, ddof=1))
