"""The searches that found the trot's, the pace's, the bound's and the gallop's own gains.

    nice python docs/scripts/quadruped_search.py --search turning --generations 15 --seed 3
    nice python docs/scripts/quadruped_search.py --search speed --generations 25 --seed 1
    nice python docs/scripts/quadruped_search.py --search pace --generations 20 --seed 1
    nice python docs/scripts/quadruped_search.py --search bound --generations 60 --popsize 16 \
        --step 0.05 --seed 7 --jobs 2
    nice python docs/scripts/quadruped_search.py --search bound_steady --generations 40 \
        --popsize 10 --step 0.08 --seed 13 --jobs 2
    nice python docs/scripts/quadruped_search.py --search gallop --generations 100 --popsize 16 \
        --start-from bound --step 0.15 --seed 3 --jobs 2
    nice python docs/scripts/quadruped_search.py --search gallop_fast --generations 40 \
        --popsize 20 --step 0.08 --seed 17 --jobs 2 --start FILE.json
    nice python docs/scripts/quadruped_search.py --search gallop_fast --check
    nice -n 10 python docs/scripts/quadruped_search.py --search gallop_robust --generations 45 \
        --popsize 12 --step 0.04 --seed 2 --jobs 1
    nice -n 10 python docs/scripts/quadruped_search.py --search gallop_robust --generations 35 \
        --popsize 10 --step 0.03 --seed 4 --jobs 1 --speeds 2.97,3.02,3.04,3.13,3.26,3.52,3.73,\
3.9,3.94,3.96,3.97,3.98,3.99,4.01,4.02,4.03,4.04,4.06,4.1,4.27,4.51,4.74,4.97,5.03
    nice python docs/scripts/quadruped_search.py --search gallop_robust --check --start FILE.json

CMA-ES (pycma) through the Python API over a search's gains (SEARCHES, bounds in SI units),
each scaled to [0, 1] within its bounds, starting from the file's values (or ``--start
FILE.json``, the JSON this prints at the end; or ``--start-from`` another controller's),
each candidate rounded to the three significant digits the file is written with before it
runs, its runs in ``--jobs`` processes, on generated code of its own (a search never
writes ``generated/``). A straight run scores its relative speed error from 3 s; a path run
its lateral deviation (RMS, from 3 s) plus its relative speed error along the path; a run
that falls at t of T scores 10 + (T - t) / T. The objectives (TRIALS: weight, path, speed,
seconds):

* ``turning`` (the trot): 2 x a 5 m circle + 0.5 x an 8 m square (30 s each at 1.5 m/s) +
  straight runs at 2.3, 2.6 (20 s) and 1 m/s (10 s). The shipped values were reached in
  four searches from the shared part's values, each adding runs to the objective (the
  circle alone; the square and 2.3 m/s; the circle weighted twice; 1 and 2.6 m/s).
* ``speed`` (the trot, on the turning values): 2 x straight at 3 m/s + 2.6 + 2.3 (20 s) +
  1 m/s (10 s) + 0.5 x the circle.
* ``pace`` (on the trot's values, which it extends): straight runs of 20 s at 1, 1.5 and
  2 m/s, each plus twice the shortfall below 0.97 of its lateral pairs' stances whose
  members land within 10 ms.
* ``bound``: straight runs of 20 s at 2 to 3.5 m/s (2.8 twice), each relative error past
  3.5% counted six times. The shipped values: three searches, the last (the command above)
  from the second's values.
* ``bound_windows`` (the bound's gains): straight runs of 20 s at 2 to 3.5 m/s, each scored
  by its worst 3 s window from 3 s (3-6, 6-9, ..., 15-18 and 17-20 s), an error past 3.5%
  counted six times, plus half the windows' mean. Run from the shipped values
  (``--generations 40 --popsize 16 --step 0.05 --seed 11 --jobs 2``) it found nothing
  better than them (docs/quadruped.md).
* ``bound_steady`` (the bound's rate servo, speed gains and per-stance speed correction):
  straight runs of 20 s at 2, 2.4, 2.8, 3.2 and 3.5 m/s (or ``--speeds``), each scored as
  ``bound_windows`` over every 3 s window from 3 to 17 s, stepped by 0.5 s. The shipped
  values: ``--generations 40 --popsize 10 --step 0.08 --seed 13 --jobs 2`` from
  ``k_stride_speed`` 3 rad/m (docs/quadruped.md).
* ``gallop``: straight runs of 20 s at 3, 3.5 (half), 4, 4.5 and 5 m/s, each plus twice the
  shortfall below 0.6 of its pairs' stances that go single, double, then single support.
  The shipped values: the command above at 3 (twice), 3.5 and 4 m/s, then from its best
  (``--start``, ``--step 0.08 --seed 6``, 50 generations) at the speeds listed.
* ``gallop_fast`` (the gallop's ``fast_*`` values, what its gains move by past 4 m/s): 20 s
  straight runs at 4.25, 4.4, 4.5, 4.6, 4.7, 4.8, 4.9, 5 (twice), 5.1 and 5.2 m/s, 40 s at 4.6
  and 5 m/s, and 5 m/s commanded at 8 s after 4 m/s (scored from 12 s): each relative error
  past 4% counted six times, plus twice the single-double-single shortfall below 0.6. The
  shipped values: three searches, each from the last one's best: from 0 (``--step 0.2 --seed
  5``, 60 generations of 24, some bounds narrower) scoring 4.5, 4.75, 5 (twice) and 5.25
  (half) m/s, 5 m/s over 30 s and the step; then (``--step 0.1 --seed 11``, 45 of 24) 4.5,
  4.6, 4.75, 4.9, 5 (twice), 5.1 and 5.25 (half) m/s, 5 m/s over 40 s and the step; then the
  command above. ``--check`` runs the file's values (or ``--start``'s) on CHECKS, runs no
  search scored, and prints each one's outcome and speed error.
* ``gallop_robust`` (the gallop's own gains, as ``gallop``, plus its own ``trim_band``): for
  robustness to the changes docs/scripts/robustness.py makes, no round command: 20 s
  straight runs at 2.97, 3.04, 3.13, 3.26, 3.52, 3.73, 3.98, 4.02, 4.27, 4.51, 4.74, 4.97 and
  5.03 m/s, and at 3.01 and 4.01 m/s with ``dt`` 0.39 ms, 3.02, 3.99 and 4.99 m/s with
  ``control_dt`` 1.6 ms, 2.99 and 4.03 m/s started 1 mm higher; each scored as
  ``gallop_fast``'s. It prints CMA-ES's mean beside its best (``"mean"``; the best of a
  noisy objective can be a lucky one). ``--check`` (CHECKS): 20 s at 3.13, 3.37, 3.5, 3.77,
  4.02, 4.38, 4.5, 4.63, 4.85 m/s and at 3, 4 and 5 m/s moved by -1 to +1% in steps of
  0.25% (35 runs). Nothing it found was shipped (docs/quadruped.md, "The gallop, off the
  round commands"): the two commands above (about 15 minutes each) and a first search over
  these gains with the ``fast_*`` ones (``--step 0.07``) each found values that scored
  better on their own runs and were less robust at 4 m/s on runs they had not scored.
"""

from __future__ import annotations

import argparse
import json
import multiprocessing
import tempfile
import time
from pathlib import Path

import cma
import numpy as np

import legdsl
from legdsl.analysis.pairs import UNISON, touchdown_spreads
from legdsl.analysis.strides import EPS_T, Unit, runs, touching
from legdsl.api import Quantity

CIRCLE = "circle(center = (0, 5) m, radius = 5 m, turn = left)"
SQUARE = "square(corner = (0, 0) m, side = 8 m, turn = left, lookahead = 2 m)"
PATH_SPEED = 1.5  # m/s
Space = dict[str, tuple[float, float, str]]  # name: (low, high, SI unit)
SEARCHES: dict[str, tuple[str, Space]] = {
    "turning": ("trot", {
        "kp_yaw": (2, 60, "N*m/rad"), "kv_yaw": (1, 30, "N*m*s/rad"), "k_turn": (0, 3, ""),
        "yaw_lead": (0, 0.5, "s"), "turn_most": (0.0175, 0.262, "rad"),
        "k_path": (0.1, 2, "m^-1"), "turn_limit": (0.0873, 0.698, "rad"),
        "k_aim_rate": (0, 1.5, ""), "k_side_trim": (0, 0.6, ""),
        "kp_roll": (100, 500, "N*m/rad"), "kv_roll": (5, 50, "N*m*s/rad"),
    }),
    "speed": ("trot", {
        "k_speed": (0.03, 0.2, "s"), "k_trim": (0, 0.8, ""), "stroke": (0.005, 0.04, "m"),
        "k_height": (0, 0.5, ""), "k_height_trim": (0, 0.1, ""), "stroke_max": (0.02, 0.08, "m"),
        "stand": (-0.06, 0, "m"), "short": (-0.18, -0.08, "m"), "leg_k": (4000, 12000, "N/m"),
        "leg_b": (30, 120, "N*s/m"), "accel": (0.5, 1.5, "m/s^2"), "kp": (150, 600, "N*m/rad"),
        "kv": (10, 60, "N*m*s/rad"), "swing_kp": (100, 400, "N*m/rad"),
    }),
    "bound": ("bound", {
        "kv_rate": (5, 40, "N*m*s/rad"), "omega_f": (0.5, 4, "rad/s"),
        "omega_r": (0.5, 4, "rad/s"), "k_center": (0, 8, "s^-1"), "k_pitch_i": (0, 3, "s^-1"),
        "k_pitch_thrust": (0, 0.2, "m/rad"), "idle_delay": (0, 0.12, "s"),
        "k_speed": (0.03, 0.2, "s"), "k_trim": (0, 0.8, ""), "stroke": (0.005, 0.04, "m"),
        "k_height": (0, 0.5, ""), "stroke_max": (0.02, 0.08, "m"), "stand": (-0.06, 0, "m"),
        "leg_k": (3000, 12000, "N/m"), "leg_b": (30, 120, "N*s/m"),
        "kp_roll": (100, 500, "N*m/rad"), "kv_roll": (5, 50, "N*m*s/rad"),
        "accel": (0.8, 2, "m/s^2"),
    }),
    "gallop": ("gallop", {
        "kv_rate": (5, 40, "N*m*s/rad"), "omega_f": (0.5, 5, "rad/s"),
        "omega_r": (0.5, 5, "rad/s"), "k_center": (0, 8, "s^-1"), "k_pitch_i": (0, 3, "s^-1"),
        "k_pitch_thrust": (0, 0.2, "m/rad"), "idle_delay": (0, 0.12, "s"),
        "k_speed": (0.005, 0.2, "s"), "k_trim": (0, 0.8, ""), "stroke": (0.005, 0.05, "m"),
        "k_height": (0, 0.5, ""), "stroke_max": (0.02, 0.1, "m"), "stand": (-0.06, 0, "m"),
        "leg_k": (3000, 12000, "N/m"), "leg_b": (30, 120, "N*s/m"),
        "kp_roll": (100, 600, "N*m/rad"), "kv_roll": (5, 60, "N*m*s/rad"),
        "accel": (0.5, 2, "m/s^2"), "stagger": (0, 0.04, "m"), "stance_lead": (-0.04, 0.01, "m"),
        "kp_yaw": (2, 60, "N*m/rad"), "kv_yaw": (1, 30, "N*m*s/rad"),
        "lift_slew": (1, 10, "m/s"), "height": (0.6, 0.75, "m"),
    }),
    "gallop_fast": ("gallop", {
        "fast_k_speed": (-0.0175, 0.1, "s"), "fast_stance_f": (-0.04, 0.08, "s"),
        "fast_stance_r": (-0.08, 0.04, "s"), "fast_omega_f": (-2, 4, "rad/s"),
        "fast_omega_r": (-2.1, 4, "rad/s"), "fast_kv_rate": (-20, 60, "N*m*s/rad"),
        "fast_k_center": (-2, 6, "s^-1"), "fast_k_trim": (-0.08, 0.4, ""),
        "fast_trim_band": (-0.25, 1, "m/s"), "fast_height": (-0.05, 0.1, "m"),
        "fast_stroke_max": (-0.01, 0.05, "m"), "fast_pitch_thrust": (-0.0125, 0.1, "m/rad"),
        "fast_window": (0, 0.1, "s"), "fast_lag": (0, 0.06, "s"),
    }),
    "pace": ("pace", {
        "kp": (150, 1200, "N*m/rad"), "kv": (10, 100, "N*m*s/rad"),
        "kp_roll": (100, 1000, "N*m/rad"), "kv_roll": (5, 100, "N*m*s/rad"),
        "k_side_trim": (0, 1, ""), "leg_k": (3000, 9000, "N/m"), "leg_b": (30, 200, "N*s/m"),
        "k_speed": (0.03, 0.2, "s"), "stroke": (0.005, 0.04, "m"),
    }),
}  # fmt: skip
SEARCHES["bound_windows"] = SEARCHES["bound"]  # the bound's gains, scored by 3 s windows
# the gallop's own gains, by commands off the round speeds and by perturbed runs
TRIM_BAND: Space = {"trim_band": (0.1, 1.5, "m/s")}
SEARCHES["gallop_robust"] = ("gallop", SEARCHES["gallop"][1] | TRIM_BAND)
STEADY = (
    "kv_rate",
    "omega_f",
    "omega_r",
    "k_center",
    "k_pitch_i",
    "idle_delay",
    "k_speed",
    "k_trim",
)
STRIDE_SPEED: Space = {"k_stride_speed": (0, 8, "rad/m"), "stride_most": (0.2, 2, "rad/s")}
# the bound's rate servo and speed gains with the per-stance speed correction, by every window
SEARCHES["bound_steady"] = ("bound", {n: SEARCHES["bound"][1][n] for n in STEADY} | STRIDE_SPEED)
WINDOWS = (3.0, 6.0, 9.0, 12.0, 15.0, 17.0)  # the 3 s windows' starts (20 s runs)
STEADY_WINDOWS = tuple(3.0 + 0.5 * k for k in range(29))  # 3 to 17 s, every 0.5 s


def fell(run: legdsl.Run, duration: float) -> float | None:
    if run.status == "ok":
        return None
    return 10 + (duration - float(run.info.get("sim_time", 0.0))) / duration


PACE_PAIRS = ((0, 2), (1, 3))  # the lateral pairs, as columns of trajectory.contact
BOUND_PAIRS = ((0, 1), (2, 3))  # the front and the rear pair


def unison(run: legdsl.Run, pairs: tuple[tuple[int, int], ...], start: float = 3.0) -> float:
    """The share of a pair's stances from ``start`` whose members land within 10 ms (the
    touchdown spread of ``legdsl metrics``)."""
    tr = run.trajectory
    spreads = [spread for a, b in pairs
               for spread in touchdown_spreads(tr, _pair(a, b), start, float(tr.t[-1]))]  # fmt: skip
    return float(np.mean(np.array(spreads) <= UNISON + EPS_T)) if spreads else 0.0


def staggered(run: legdsl.Run, pairs: tuple[tuple[int, int], ...], start: float = 3.0) -> float:
    """The share of a pair's stances from ``start`` that go single, double, then single
    support (one member down alone, then both, then the other alone)."""
    tr = run.trajectory
    down = tr.contact != 0
    total = sds = 0
    for a, b in pairs:
        starts, stops = runs(touching(tr, (a, b)))
        for lo, hi in zip(starts.tolist(), stops.tolist(), strict=True):
            if tr.t[lo] < start:
                continue
            pattern = down[lo:hi, a].astype(int) + 2 * down[lo:hi, b].astype(int)
            phases = [int(p) for k, p in enumerate(pattern) if k == 0 or p != pattern[k - 1]]
            total += 1
            sds += phases in ([1, 3, 2], [2, 3, 1])
    return sds / total if total else 0.0


def _pair(a: int, b: int) -> Unit:
    """Two feet (columns of trajectory.contact) as one virtual leg, for the analysis."""
    return Unit(f"contacts {a} and {b}", "group", (a, b), ())


# (weight, path or "", speed, seconds), and optionally (speed, until): the command before a
# step, or the run's options (``legdsl run``'s, as Creature.run takes them)
Extra = tuple[float, float] | dict[str, float]
Trial = tuple[float, str, float, float] | tuple[float, str, float, float, Extra]
STEP_SETTLE = 4.0  # s: a stepped command's speed is measured from this long after the step
TRIALS: dict[str, list[Trial]] = {
    "turning": [(2, CIRCLE, PATH_SPEED, 30), (0.5, SQUARE, PATH_SPEED, 30),
                (1, "", 2.3, 20), (1, "", 2.6, 20), (1, "", 1.0, 10)],
    "speed": [(2, "", 3.0, 20), (1, "", 2.6, 20), (1, "", 2.3, 20), (1, "", 1.0, 10),
              (0.5, CIRCLE, PATH_SPEED, 30)],
    "bound": [(w, "", v, 20) for v, w in ((2.0, 1), (2.2, 1), (2.4, 1), (2.6, 1), (2.8, 2), (3.0, 1),
                                          (3.2, 1), (3.5, 1))],
    "bound_windows": [(1, "", v, 20) for v in (2.0, 2.2, 2.4, 2.6, 2.8, 3.0, 3.2, 3.5)],
    "bound_steady": [(1, "", v, 20) for v in (2.0, 2.4, 2.8, 3.2, 3.5)],
    "gallop": [(w, "", v, 20) for v, w in ((3.0, 1), (3.5, 0.5), (4.0, 1), (4.5, 1), (5.0, 1))],
    "pace": [(1, "", v, 20) for v in (1.0, 1.5, 2.0)],
    "gallop_fast": [(1, "", v, 20) for v in (4.25, 4.4, 4.5, 4.6, 4.7, 4.8, 4.9, 5.0, 5.0, 5.1, 5.2)]
                   + [(1, "", 4.6, 40), (1, "", 5.0, 40), (1, "", 5.0, 20, (4.0, 8.0))],
}  # fmt: skip
# gallop_robust: commands off the round ones, and runs changed as robustness.py changes them
# (drop 0.031 m: the shipped start, the lowest foot 3 cm up, 1 mm higher)
ROBUST_SPEEDS = (2.97, 3.04, 3.13, 3.26, 3.52, 3.73, 3.98, 4.02, 4.27, 4.51, 4.74, 4.97, 5.03)
ROBUST_CHANGED: tuple[tuple[float, dict[str, float]], ...] = (
    (3.01, {"dt": 0.00039}), (3.02, {"control_dt": 0.0016}), (2.99, {"drop": 0.031}),
    (4.01, {"dt": 0.00039}), (3.99, {"control_dt": 0.0016}), (4.03, {"drop": 0.031}),
    (4.99, {"control_dt": 0.0016}),
)  # fmt: skip
TRIALS["gallop_robust"] = [(1.0, "", v, 20.0) for v in ROBUST_SPEEDS]
TRIALS["gallop_robust"] += [(1.0, "", v, 20.0, o) for v, o in ROBUST_CHANGED]


class Search:
    """A search's controller and gains, and its runs through the API."""

    def __init__(self, creature: legdsl.Creature, name: str):
        self.creature, self.name = creature, name
        self.controller, self.space = SEARCHES[name]

    def settings(self, values: dict[str, float], speed: float) -> dict[str, str]:
        units = {n: unit for n, (_, _, unit) in self.space.items()}
        return {"speed": f"{speed} m/s"} | {n: f"{v} {units[n]}".strip() for n, v in values.items()}

    def score(self, values: dict[str, float], trial: Trial) -> float:
        """A run's score: a path run its lateral deviation (RMS, from 3 s) plus its relative
        speed error along the path; a straight one its relative speed error from 3 s; a
        fall 10 and more."""
        _, path, speed, t = trial[:4]
        extra = trial[4] if len(trial) > 4 else None  # type: ignore[misc]
        step = extra if isinstance(extra, tuple) else None
        run = self.run(values, speed, t, step, path, extra if isinstance(extra, dict) else None)
        penalty = fell(run, t)
        if penalty is not None:
            return penalty
        if path:
            report = run.info["path_reports"][0]
            return float(report["lateral_rms"] + abs(report["path_speed"] - speed) / speed)
        times, x = run.samples["t"], run.samples["q.x"]
        if self.name == "bound_windows":  # every 3 s window within 5%: past 3.5% costs five times
            return window_score(times, x, speed)
        if self.name == "bound_steady":  # the same over every window stepped by 0.5 s
            return window_score(times, x, speed, STEADY_WINDOWS)
        error = abs(settled_speed(run, step) - speed) / speed
        if self.name in ("gallop_fast", "gallop_robust"):  # within 5%: past 4% costs 6x; staggered
            return (
                error + 5 * max(0.0, error - 0.04) + 2 * max(0.0, 0.6 - staggered(run, BOUND_PAIRS))
            )
        if self.name == "bound":  # every speed within 5%: an error past 3.5% costs five times
            error += 5 * max(0.0, error - 0.035)
        if self.name == "pace":  # and the pairs must land together (95% within 10 ms)
            error += 2 * max(0.0, 0.97 - unison(run, PACE_PAIRS))
        if self.name == "gallop":  # and the pairs must not: single, double, single support
            error += 2 * max(0.0, 0.6 - staggered(run, BOUND_PAIRS))
        return error

    def run(
        self,
        values: dict[str, float],
        speed: float,
        t: float,
        step: tuple[float, float] | None = None,
        path: str = "",
        options: dict[str, float] | None = None,
    ) -> legdsl.Run:
        """A run of the search's controller with ``values`` at ``speed`` for ``t`` seconds; with
        ``step`` (before, until), commanded ``before`` until ``until``, then ``speed``; with
        ``options`` (``dt``, ``control_dt``, ``drop``) as ``legdsl run`` takes them."""
        sets = self.settings(values, speed)
        if step is not None:
            sets |= {"speed": f"{step[0]} m/s", f"speed@{step[1]}s": f"{speed} m/s"}
        return self.creature.run(
            controller=self.controller, set=sets, time=t, path=path or None, **(options or {})
        )

    def objectives(self, candidates: list[dict[str, float]], jobs: int) -> list[float]:
        """Each candidate's weighted sum of its trials' scores, the runs in ``jobs`` processes."""
        trials = TRIALS[self.name]
        tasks = [(v, trial) for v in candidates for trial in trials]
        if jobs > 1:
            _FORKED[0] = self  # the forked workers find the search here (it does not pickle)
            with multiprocessing.get_context("fork").Pool(jobs) as pool:
                scores = pool.starmap(_forked_score, tasks, chunksize=1)
        else:
            scores = [self.score(v, trial) for v, trial in tasks]
        n = len(trials)
        return [sum(trial[0] * scores[k * n + j] for j, trial in enumerate(trials))
                for k in range(len(candidates))]  # fmt: skip


def settled_speed(run: legdsl.Run, step: tuple[float, float] | None = None) -> float:
    """A run's mean speed from 3 s, or from ``STEP_SETTLE`` after a stepped command."""
    times, x = run.samples["t"], run.samples["q.x"]
    i = int(np.searchsorted(times, 3.0 if step is None else step[1] + STEP_SETTLE))
    return float((x[-1] - x[i]) / (times[-1] - times[i]))


def window_score(
    times: np.ndarray, x: np.ndarray, speed: float, starts: tuple[float, ...] = WINDOWS
) -> float:
    """The worst relative speed error of a run's 3 s windows (WINDOWS), an error past 3.5%
    counted six times, plus half their mean (so a search feels the windows it is not
    worst in)."""
    errors = []
    for start in starts:
        i, j = int(np.searchsorted(times, start)), int(np.searchsorted(times, start + 3.0)) - 1
        errors.append(abs((x[j] - x[i]) / (times[j] - times[i]) - speed) / speed)
    worst = max(errors)
    return float(worst + 5 * max(0.0, worst - 0.035) + 0.5 * np.mean(errors))


_FORKED: list[Search | None] = [None]


def _forked_score(values: dict[str, float], trial: Trial) -> float:
    search = _FORKED[0]
    assert search is not None
    return search.score(values, trial)


def gains(creature: legdsl.Creature, controller: str) -> dict[str, Quantity]:
    """A controller's parameters and inputs, by name."""
    found = creature.controllers[controller]
    return found.params | found.inputs


# runs none of gallop_fast's searches scored, to check a result: (speed, seconds, step or None)
CHECKS: dict[str, list[tuple[float, float, tuple[float, float] | None]]] = {
    "gallop_fast": [(v, 20, None) for v in (4.3, 4.45, 4.55, 4.65, 4.75, 4.85, 4.95, 5.0, 5.05,
                                             5.15, 5.25, 5.5)]
    + [(v, 40, None) for v in (4.4, 4.8, 5.1)]
    + [(5.0, 20, (4.0, 10.0)), (5.0, 20, (4.5, 8.0)), (4.5, 20, (5.0, 10.0))],
}  # fmt: skip
# gallop_robust: odd commands, and robustness.py's commands moved by up to 1% at 3, 4, 5 m/s
ODD = (3.13, 3.37, 3.5, 3.77, 4.02, 4.38, 4.5, 4.63, 4.85)
MOVED = (-1, -0.75, -0.5, -0.25, 0, 0.25, 0.5, 0.75, 1)  # % of the command
CHECKS["gallop_robust"] = [(v, 20.0, None) for v in ODD]
CHECKS["gallop_robust"] += [(round(v * (1 + m / 100), 6), 20.0, None) for v in (3.0, 4.0, 5.0)
                            for m in MOVED if round(v * (1 + m / 100), 6) not in ODD]  # fmt: skip


def check(search: Search, values: dict[str, float]) -> None:
    """Each CHECKS run's outcome and relative speed error from 3 s (from 4 s after a step)."""
    errors, falls = [], 0
    for speed, t, step in CHECKS[search.name]:
        run = search.run(values, speed, t, step)
        error = settled_speed(run, step) / speed - 1
        after = "" if step is None else f" after {step[0]} m/s to {step[1]} s"
        print(f"{speed} m/s{after}, {t} s: {run.status} at {run.info.get('sim_time', t):.2f} s, "
              f"{error:+.1%}", flush=True)  # fmt: skip
        falls += run.status != "ok"
        errors += [error] if run.status == "ok" else []
    print(f"{falls} fell; the others {min(errors):+.1%} to {max(errors):+.1%}, "
          f"mean |error| {np.mean(np.abs(errors)):.1%}")  # fmt: skip


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--search", choices=sorted(SEARCHES), required=True)
    parser.add_argument("--file", default="creatures/quadruped.leg")
    parser.add_argument("--start", help="a JSON file with 'values' (SI) to start from")
    parser.add_argument("--generations", type=int, default=20)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--step", type=float, default=0.2, help="CMA-ES's first step in [0, 1]")
    parser.add_argument("--popsize", type=int, default=10)
    parser.add_argument("--jobs", type=int, default=1, help="runs in this many processes")
    parser.add_argument("--start-from", help="start from another controller's values")
    parser.add_argument("--speeds", help="straight 20 s runs at these speeds (m/s, 2,2.4)")
    parser.add_argument("--check", action="store_true", help="run CHECKS for the start values")
    args = parser.parse_args()
    if args.speeds:  # in place of the search's own trials
        TRIALS[args.search] = [(1, "", float(v), 20) for v in args.speeds.split(",")]
    # its own generated code: a search never writes generated/ (nor reads a later compile's)
    creature = legdsl.load(args.file, generated=tempfile.mkdtemp(prefix="quadruped-search-"))
    search = Search(creature, args.search)
    own = gains(creature, search.controller)
    start = (
        json.loads(Path(args.start).read_text())["values"]
        if args.start
        else {n: own[n].value for n in search.space}
    )
    if args.start_from:
        other = gains(creature, args.start_from)
        start |= {n: other[n].value for n in search.space if n in other}
    bounds = {n: (lo, hi) for n, (lo, hi, _) in search.space.items()}

    def values(x: list[float]) -> dict[str, float]:
        """The gains at ``x``, rounded to the three significant digits the file is written
        with (so the values the search scores are the values shipped)."""
        return {
            n: float(f"{lo + min(max(xi, 0.0), 1.0) * (hi - lo):.3g}")
            for xi, (n, (lo, hi)) in zip(x, bounds.items(), strict=True)
        }

    search.creature.run(controller=search.controller, time=0.01)  # built once, before a fork
    x0 = [min(max((start[n] - lo) / (hi - lo), 0.0), 1.0) for n, (lo, hi) in bounds.items()]
    if args.check:
        return check(search, values(x0))
    print(f"start: {search.objectives([values(x0)], args.jobs)[0]:.3f}", flush=True)
    options = {"seed": args.seed, "popsize": args.popsize, "bounds": [0, 1], "verbose": -9}
    cmaes = cma.CMAEvolutionStrategy(x0, args.step, options)
    best: tuple[float, dict[str, float]] = (float("inf"), start)
    began = time.perf_counter()
    for generation in range(args.generations):
        xs = cmaes.ask()
        scores = search.objectives([values(x) for x in xs], args.jobs)
        cmaes.tell(xs, scores)
        i = int(np.argmin(scores))
        if scores[i] < best[0]:
            best = (scores[i], values(xs[i]))
        elapsed = time.perf_counter() - began
        left = elapsed / (generation + 1) * (args.generations - generation - 1)
        print(f"generation {generation + 1}/{args.generations}: best {scores[i]:.3f}, so far "
              f"{best[0]:.3f} ({elapsed:.0f} s, about {left:.0f} s left)", flush=True)  # fmt: skip
    # the best candidate can be a lucky one; CMA-ES's mean, its estimate, is printed beside it
    mean = values(list(cmaes.mean))
    print(json.dumps({"objective": best[0], "values": best[1], "mean": mean}, indent=1))


if __name__ == "__main__":
    main()
