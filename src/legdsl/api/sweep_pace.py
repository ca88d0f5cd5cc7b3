"""The time a sweep has left: its pace in simulated seconds per wall second, by arrival.

A batch's rows come back together (within milliseconds): counted row by row, the estimate
fell with each (an outside user's bar read 21, 18, 16, 14 and 13 s left within 20 ms) and
rose again at the next batch. Here the rows that come back within ``GROUP`` s of the one before
are one arrival, and an arrival is at most ``GROUP`` s long: rows coming back steadily, less
than ``GROUP`` apart (short runs, many workers), are an arrival every ``GROUP`` s, parted where
a batch's rows end (``BURST``), or every ``LONGEST`` s if they never pause (chained
from row to row, they were one arrival for ever, and a sweep of 10,000 runs said "time left not
yet known" to its end). An estimate is made as each arrival is whole (at the next row after
it, or ``GROUP`` s after its last): the pace is the simulated time of the arrivals over the
last waves of batches (none before the second arrival: the first includes the workers' start
and compile), smoothed from arrival to arrival; the runs to go are each as long as the mean run
over the same waves (a fall's setup costs time too); between estimates the time left counts
down with the clock.
"""

from __future__ import annotations

import math
from collections import deque

GROUP = 0.5  # s: rows closer than this to the one before, within this of the first, are one arrival
BURST = 0.05  # s: rows closer than this are one batch's, not parted (but by LONGEST)
LONGEST = 2 * GROUP  # s: the longest arrival, however close its rows
SMOOTHING = 0.5  # weight of the newest pace at each arrival


class SweepPace:
    """``row(simulated, now)`` as each row comes back; ``left(now)``: seconds to go, or None
    while unknown. ``runs`` runs are to be run on ``workers`` workers, ``batch`` at a time."""

    def __init__(self, runs: int, workers: int, batch: int = 1) -> None:
        self.runs_left = runs
        self.waves = 2 * max(1, workers) * max(1, batch)  # the rows of two waves of batches
        # the whole arrivals paced over, [wall time of the last row, simulated seconds, rows]
        self.arrivals: deque[list[float]] = deque()
        self.open: list[float] | None = None  # the arrival coming in: [first, last, sim, rows]
        self.pace = math.nan  # simulated seconds per wall second, smoothed
        self.said: tuple[float, float] | None = None  # the last estimate, and its time

    def row(self, simulated: float, now: float) -> None:
        sim = simulated if math.isfinite(simulated) and simulated > 0 else 0.0
        if self.open is not None:
            gap, age = now - self.open[1], now - self.open[0]
            if gap >= GROUP or (age >= GROUP and gap >= BURST) or age >= LONGEST:
                self._whole()
        self.runs_left = max(0, self.runs_left - 1)
        if self.open is None:
            self.open = [now, now, 0.0, 0.0]
        self.open[1] = now
        self.open[2] += sim
        self.open[3] += 1

    def left(self, now: float) -> float | None:
        if self.open is not None and now - self.open[1] >= GROUP:
            self._whole()  # no row since: the arrival is whole
        if self.said is None:
            return None
        estimate, when = self.said
        return _counted_down(estimate - (now - when))

    def _whole(self) -> None:
        """The open arrival is whole: the pace and the estimate, as of its last row."""
        assert self.open is not None
        _, last, sim, rows = self.open
        self.open = None
        self.arrivals.append([last, sim, rows])
        while len(self.arrivals) > 2 and sum(a[2] for a in list(self.arrivals)[2:]) >= self.waves:
            self.arrivals.popleft()  # the window keeps two waves' rows, after its start
        # the first arrival of the window ended the wait before it: its time is the start
        window = list(self.arrivals)[1:]
        span = last - self.arrivals[0][0]
        done = sum(a[1] for a in window)
        if not window or span <= 0 or done <= 0:
            return
        latest = done / span
        self.pace = latest if math.isnan(self.pace) else (
            SMOOTHING * latest + (1 - SMOOTHING) * self.pace)  # fmt: skip
        # the runs to go, each as long as the mean of the window's (falls included: their
        # setup counts; not the mean since the first: 230 runs falling at once, then long
        # ones, said '0m02s left' with 18 s to go)
        to_run = self.runs_left * done / max(1.0, sum(a[2] for a in window))
        self.said = (to_run / self.pace, last)


def _counted_down(left: float) -> float | None:
    """Seconds left, None past the end of the estimate: a stall (a Dask scheduler whose
    workers were lost) read 'about 0m00s left' for minutes."""
    return left if left >= 0 else None
