"""The time a tune has left: its closing runs counted, at the pace per simulated second (the
last generation said "about 0 s left" before five runs of up to twice --time; candidates
falling fast early made it far too low)."""

from __future__ import annotations

import pytest

from legdsl.api.tune_pace import time_left


def test_the_last_generation_counts_the_closing_runs() -> None:
    # 8 runs of 6 s on 1 process took 48 s: 1 s a simulated second; then 1 run halfway
    # between 1 and 2 m/s (6 s) and 2 runs of 12 s
    left = time_left(48.0, 48.0, 0, 8, 1, 6.0, (1.0, 2.0), (1.5,))
    assert left == pytest.approx(6.0 + 24.0)
    # on 4 processes: the halfway run alone, the two long ones side by side
    assert time_left(12.0, 48.0, 0, 8, 4, 6.0, (1.0, 2.0), (1.5,)) == pytest.approx(6.0 + 12.0)


def test_candidates_that_fell_early_do_not_make_it_short() -> None:
    # the first generation's 8 runs all fell at 0.5 s of 6, in 4 s: the 9 generations left
    # are counted as lasting their 6 s (48 s each), not as 4 s each
    left = time_left(4.0, 4.0, 9, 8, 1, 6.0, (1.0, 2.0), (1.5,))
    assert left == pytest.approx(9 * 48.0 + 30.0)
    assert time_left(1.0, 0.0, 3, 8, 1, 6.0, (1.0,), ()) == 0.0  # nothing to time by
