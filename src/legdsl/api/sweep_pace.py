"""The time a sweep has left: its pace in simulated seconds per wall second, by batch.

A batch's rows come back together (within milliseconds): counted row by row, the estimate
fell with each (an outside user's bar read 21, 18, 16, 14 and 13 s left within 20 ms) and
rose again at the next batch. Here the rows that come back within ``GROUP`` s of each other
are one arrival; the pace is the simulated time of the arrivals over the last waves of
batches (none before the second arrival: the first includes the workers' start and compile),
smoothed from arrival to arrival; the runs to go are each as long as the mean run so far (a
fall's setup costs time too) over the same waves, and while an arrival comes in, and between arrivals, the time
left counts down with the clock.
"""

from __future__ import annotations

import math
from collections import deque

GROUP = 0.5  # s: rows each closer than this to the one before are one arrival
SMOOTHING = 0.5  # weight of the newest pace at each arrival


class SweepPace:
    """``row(simulated, now)`` as each row comes back; ``left(now)``: seconds to go, or None
    while unknown. ``runs`` runs are to be run on ``workers`` workers."""

    def __init__(self, runs: int, workers: int) -> None:
        self.runs_left = runs
        # the last arrivals, [wall time, simulated seconds, rows]: two waves of batches
        self.arrivals: deque[list[float]] = deque(maxlen=2 * max(1, workers) + 1)
        self.pace = math.nan  # simulated seconds per wall second, smoothed
        self.before = math.nan  # the pace before the last arrival
        self.shown: tuple[float, float] | None = None  # the last estimate given, and when

    def row(self, simulated: float, now: float) -> None:
        self.runs_left = max(0, self.runs_left - 1)
        sim = simulated if math.isfinite(simulated) and simulated > 0 else 0.0
        if self.arrivals and now - self.arrivals[-1][0] < GROUP:
            # the same batch's (its rows written one by one, each synced to the disk), or
            # one at the same moment: the arrival ends with its last row
            self.arrivals[-1][0] = now
            self.arrivals[-1][1] += sim
            self.arrivals[-1][2] += 1
        else:
            self.arrivals.append([now, sim, 1])
            self.before = self.pace  # the smoothed pace before this arrival
        span = self.arrivals[-1][0] - self.arrivals[0][0]
        # the first arrival of the window ended the wait before it: its time is the start
        done = sum(a[1] for a in list(self.arrivals)[1:])
        if len(self.arrivals) < 2 or span <= 0 or done <= 0:
            return
        latest = done / span  # (revised by each row of an arrival until it is whole)
        self.pace = latest if math.isnan(self.before) else (
            SMOOTHING * latest + (1 - SMOOTHING) * self.before)  # fmt: skip

    def left(self, now: float) -> float | None:
        if self.arrivals and now - self.arrivals[-1][0] < GROUP:
            # an arrival still coming in: the estimate before it, counting down (row by row
            # it would fall with each and rise again with the next batch)
            if self.shown is None:
                return None
            said, when = self.shown
            return _counted_down(said - (now - when))
        if math.isnan(self.pace) or not self.arrivals:
            return None
        since = now - self.arrivals[-1][0]
        # the runs to go, each as long as the mean of the window's (falls included: their
        # setup counts; not the mean since the first: 230 runs falling at once, then long
        # ones, said '0m02s left' with 18 s to go)
        window = list(self.arrivals)[1:]
        to_run = self.runs_left * sum(a[1] for a in window) / max(1, sum(a[2] for a in window))
        left = to_run / self.pace - since
        self.shown = (left, now)
        return _counted_down(left)


def _counted_down(left: float) -> float | None:
    """Seconds left, None past the end of the estimate: a stall (a Dask scheduler whose
    workers were lost) read 'about 0m00s left' for minutes."""
    return left if left >= 0 else None
