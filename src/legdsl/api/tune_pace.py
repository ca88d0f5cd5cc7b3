"""How long a ``legdsl tune`` has left, told after each generation: at the pace its runs have
gone, per simulated second, for the generations left, each run counted as lasting ``--time``,
and the closing runs (halfway between the tuned speeds, and twice ``--time`` at each).

It counted generations alone: candidates falling fast early made the estimate far too low,
and the last generation said "about 0 s left" with the closing runs, twice as long, to come.
"""

from __future__ import annotations

from collections.abc import Sequence


def time_left(
    spent: float,
    simulated: float,
    generations_left: int,
    runs_per_generation: int,
    lanes: int,
    duration: float,
    speeds: Sequence[float],
    halfway: Sequence[float],
) -> float:
    """Seconds left, from ``spent`` seconds of wall time that ran ``simulated`` seconds of
    runs on ``lanes`` processes at once; ``duration`` is a run's ``--time``."""
    lanes = max(1, lanes)
    if simulated <= 0:  # nothing ran long enough to time: no pace to go by
        return 0.0
    pace = spent * min(lanes, runs_per_generation) / simulated  # wall s per simulated s, one lane

    def batch(runs: int, each: float) -> float:
        """The wall time of ``runs`` runs of ``each`` simulated seconds, as many at once as
        there are lanes."""
        return pace * runs * each / min(lanes, runs) if runs else 0.0

    searching = generations_left * batch(runs_per_generation, duration)
    closing = batch(len(halfway), duration) + batch(len(speeds), 2 * duration)
    return searching + closing


def wall(seconds: float) -> str:
    """A wall time as the progress line tells it: seconds under a minute, then as ``legdsl
    sweep`` writes it (1m05s, 13h53m, 2d04h; a long tune told 'about 122240633 s left')."""
    from legdsl.pipeline.report import time_left as sweep_wall

    whole = round(seconds)
    return f"{whole} s" if whole < 60 else sweep_wall(whole)
