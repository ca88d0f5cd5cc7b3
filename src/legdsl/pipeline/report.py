"""What ``legdsl run`` prints about a run: the summary table, path rows and the progress bar."""

from __future__ import annotations

import sys
import time
from typing import Any

from legdsl.analysis.resolution import natural, natural_sizes, resolved
from legdsl.analysis.results import WELDED
from legdsl.figures import figure, figures
from legdsl.ir.model import Model
from legdsl.sim.run_loop import RunResult


def time_left(seconds: float) -> str:
    """A wall time still to go: minutes and seconds under an hour, then hours and minutes,
    then days and hours (a --time 1e9 run was 'about 24722m22s left')."""
    whole = int(seconds)
    if whole < 3600:
        return f"{whole // 60}m{whole % 60:02d}s"
    if whole < 86400:
        return f"{whole // 3600}h{whole % 3600 // 60:02d}m"
    return f"{whole // 86400}d{whole % 86400 // 3600:02d}h"


def progress_line(
    done: float, total: float, unit: str, left: float | None, stopped: bool = False
) -> None:
    """A progress bar on standard error, written over itself: how much of ``total`` is done
    (seconds of a run or a video, or runs of a sweep) and, when known, the time left; a bar
    ``stopped`` short of its end (a fall, Ctrl-C) says so and ends its line, as 'done' does."""
    width = 30
    frac = min(1.0, done / total) if total > 0 else 1.0
    filled = int(frac * width)
    if unit == "s":
        amount = f"{done:6.2f} / {total:.2f} s"
    elif unit == "%":  # a share of some work (a compile's)
        amount = f"{100 * frac:3.0f}%"
    else:
        amount = f"{_amount(done)}/{_amount(total)} {unit}"
    if frac >= 1.0:
        tail = ", done\n"
    elif stopped:
        tail = ", stopped\033[K\n"
    elif left is None:  # no estimate yet: no comma after the amount
        tail = "\033[K"
    else:
        tail = f", about {time_left(left)} left\033[K"  # \033[K: clear the rest
    print(f"\r[{'#' * filled}{'.' * (width - filled)}] {amount}{tail}", end="",
          file=sys.stderr, flush=True)  # fmt: skip


def _amount(x: float) -> str:
    """A count in digits with thousands marked (a sweep's 1,000,000 runs were '1e+06'),
    else as short as it reads."""
    return f"{int(x):,}" if float(x).is_integer() and abs(x) < 1e18 else f"{x:g}"


class ProgressLog:
    """``progress(done, total, left)`` where standard error is no terminal (a log, a pipe):
    a line every ``every`` s from the first call (and one at the end, after those) instead
    of a bar written over itself, so long work in a log still says how far it is and the
    time left, a stall included, if it is called while it waits (a sweep's lines came only
    with its rows, the first 20 s in); work shorter than ``every`` says nothing."""

    def __init__(self, what: str, unit: str, every: float = 10.0) -> None:
        self.what, self.unit, self.every = what, unit, every
        self.last: float | None = None  # the start, then each line's time
        self.said = False

    def __call__(self, done: float, total: float, left: float | None) -> None:
        now = time.monotonic()
        if self.last is None:
            self.last = now
        due = now - self.last >= self.every
        if not (due and done < total) and not (self.said and done >= total):
            return
        self.last, self.said = now, True
        if done >= total:
            eta = ""
        elif left is None:
            eta = ", time left not yet known"
        else:
            eta = f", about {time_left(left)} left"
        print(f"legdsl: {self.what}: {_amount(done)} of {_amount(total)} {self.unit}{eta}",
              file=sys.stderr, flush=True)  # fmt: skip


class ProgressBar:
    """``progress(t, total)`` of a run or a video (``unit`` s), or of work done in shares
    (``unit`` %): ``progress_line`` with the wall time left at the pace since the first call."""

    def __init__(self, unit: str = "s") -> None:
        self.unit = unit
        self._first: tuple[float, float] | None = None  # (wall clock, t) at the first call
        self._open: tuple[float, float] | None = None  # (t, total) of a line not yet ended

    def __call__(self, t: float, total: float) -> None:
        now = time.perf_counter()
        if self._first is None:
            self._first = (now, t)
        wall, t0 = self._first
        left = (now - wall) * (total - t) / (t - t0) if t > t0 else None
        progress_line(t, total, self.unit, left)
        self._open = (t, total) if total > 0 and t / total < 1.0 else None  # as 'done' is told

    def end(self) -> None:
        """The bar's line ended where the work stopped short (a fall, a divergence, Ctrl-C,
        an error): left open, the next message was printed on it, after a stale time left."""
        if self._open is not None:
            progress_line(*self._open, self.unit, None, stopped=True)
            self._open = None


class CompileProgress:
    """A compile's lines (``legdsl: ...``) on standard error and, on a terminal, under them a
    bar for each creature with the time left at the pace so far (its sympy lowering and the
    printing of its modules take seconds to minutes, and said nothing meanwhile)."""

    def __init__(self) -> None:
        self.shown = sys.stderr.isatty()
        self.bars: dict[str, ProgressBar] = {}
        self.finished: set[str] = set()  # creatures whose bar said done

    def line(self, message: str) -> None:
        clear = "\r\033[K" if self.bars else ""  # the bar's line, written over
        print(f"{clear}legdsl: {message}", file=sys.stderr, flush=True)

    def done(self, creature: str, share: float) -> None:
        if not self.shown or creature in self.finished:
            return
        if share >= 1.0 - 1e-9:  # the last share, however its parts summed
            share = 1.0
            self.finished.add(creature)
        self.bars.setdefault(creature, ProgressBar("%"))(share, 1.0)


def summary(model: Model, result: RunResult) -> str:
    """The table printed after a run."""
    tr = result.trajectory
    touchdowns = sum(1 for e in result.events if e["kind"] == "touchdown")
    liftoffs = sum(1 for e in result.events if e["kind"] == "liftoff")
    rows = [
        ("creature", f"{model.name} ({model.nv} DOF)"),
        *_no_controller(model, result),
        ("status", result.status + (f": {result.message}" if result.message else "")),
        ("simulated", f"{result.sim_time:.3f} s in {result.steps} steps"),
        (  # the simulation's alone: not reading the files before it, the reports nor writing
            "wall time",
            f"{result.wall_time:.2f} s simulating (real-time factor {result.real_time_factor:.2f})",
        ),
        ("samples", str(len(tr))),
        ("touchdowns / liftoffs", f"{touchdowns} / {liftoffs}"),
    ]
    if result.stop_time:
        on = ", ".join(f"{dof} {t:.3f} s" for dof, t in result.stop_time.items())
        rows.append(("time on joint stops", on))
    rows += _state_at_the_end(result)
    if len(tr):
        energy0 = tr.kinetic[0] + tr.potential[0] + tr.elastic[0]
        energy1 = tr.kinetic[-1] + tr.potential[-1] + tr.elastic[-1]
        rows += [
            ("final root position", f"{figures(tr.root_pos[-1].tolist())} m"),
            ("mean speed along x, start to end", _mean_speed_said(model, tr)),
            ("total energy start -> end", f"{figure(energy0)} J -> {figure(energy1)} J"),
        ]
    width = max(len(r[0]) for r in rows)
    return "\n".join(f"  {k:<{width}}  {v}" for k, v in rows)


def _state_at_the_end(result: RunResult) -> list[tuple[str, str]]:
    """Where a run that stopped early left its controller, and for how long it had been
    there: a table waiting in one state for an event that never came (a liftoff with the
    feet still down) shows as a state entered long before the fall."""
    entered = [e for e in result.events if e["kind"] == "state"]
    if result.status == "ok" or not entered:
        return []
    last = entered[-1]
    before = result.sim_time - last["t"]
    return [("controller state at the end",
             f"{last['state']}, entered at {last['t']:.3f} s ({before:.3f} s before)")]  # fmt: skip


def _no_controller(model: Model, result: RunResult) -> list[tuple[str, str]]:
    """A passive run of a creature that has controllers: ``legdsl run`` without
    ``--controller`` drops it, and a newcomer sees it fall without knowing why."""
    names = [c.name for c in model.controllers]
    if result.trajectory.state_names or not names:
        return []
    return [("controller", f"none, a passive run: choose one with --controller {names[0]} "
                           f"(the file has {', '.join(names)})")]  # fmt: skip


def _mean_speed_said(model: Model, tr: Any) -> str:
    """The centre of mass's mean speed along x; n/a for a creature welded to the world, which
    goes nowhere however its centre of mass sways (as its energy per metre is in the metrics:
    docs/metrics.md): a 2 km arm swinging on a fixed base read 0.839 m/s over 3 s."""
    if model.welded_root is not None:
        return f"n/a ({WELDED})"
    speed = resolved(_mean_speed(tr), natural("m/s", natural_sizes(tr)))  # 0, not -5.3e-18
    return f"{figure(speed)} m/s"


def _mean_speed(tr: Any) -> float:
    if len(tr) < 2 or tr.t[-1] <= tr.t[0]:
        return 0.0
    return float((tr.com[-1, 0] - tr.com[0, 0]) / (tr.t[-1] - tr.t[0]))


def path_summary(report: dict[str, Any]) -> str:
    """The path rows printed after a run's summary."""
    from legdsl.analysis.path_rows import path_text

    return path_text(report)


def run_path_reports(
    machine: Any, result: RunResult, scale: float | None, unit: float, model: Model | None = None
) -> list[Any]:
    """The report of each path a run followed, from ``PATH_FROM`` after its start or takeover
    for a creature whose natural time is ``unit`` (``legdsl.analysis.path_report``); n/a for
    a ``model`` whose root is welded to the world, as ``legdsl metrics`` has them."""
    from legdsl.analysis.metrics import without_path_travel
    from legdsl.analysis.path_report import followed_reports
    from legdsl.pipeline.scenes import followed_paths

    if machine is None or not len(result.trajectory):
        return []
    followed = followed_paths(machine, result.sim_time, scale)
    reports = [r for _, r in followed_reports(result.trajectory, followed, None, None, unit)]
    if model is not None and model.welded_root is not None:  # it goes nowhere
        return [without_path_travel(r) for r in reports]
    return reports
