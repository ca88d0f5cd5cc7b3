"""What ``legdsl sweep`` says of its rows once they are all in: a heat map its values cannot
be drawn on, and swept values that changed nothing."""

from __future__ import annotations

import json
import math
import sys
import threading
import time
from collections.abc import Callable, Sequence
from typing import Any

from legdsl.analysis.sweep_plot import as_number
from legdsl.api.sweep_axes import same_value

# beyond this, a plot axis's ticks overflow (matplotlib: 'arange: cannot compute length' for
# 1e308 to 1.7e308, an internal error after the rows were whole)
DRAWABLE = 1e300
# the columns a run's outcome is read from, beside the swept values and the run's number
OUTCOME = ("outcome", "simulated", "strides")


def beyond_a_plot(rows: Sequence[dict[str, Any]], names: Sequence[str], metric: str) -> str | None:
    """Why the heat map of ``metric`` over ``names`` cannot be drawn, or None: a swept value or
    a measured one too large for a plot's axis."""
    for name in [*names, metric]:
        values = [as_number(r.get(name)) for r in rows]
        huge = [v for v in values if math.isfinite(v) and abs(v) > DRAWABLE]
        if huge:
            what = "swept" if name in names else "measured"
            return (
                f"its {what} {name} reaches {max(huge, key=abs):g}, beyond what a plot's axis "
                f"can span ({DRAWABLE:g} at most)"
            )
    return None


def changed_nothing(
    rows: Sequence[dict[str, Any]], names: Sequence[str], measured: Sequence[str]
) -> list[str]:
    """The swept names whose values changed nothing: every row alike in its outcome and in
    every measured column to the bit, among rows that differ only in that name (a name with
    fewer than two values is left out). ``legdsl tune`` says as much of tuned parameters."""
    columns = [*OUTCOME, *measured]
    said = []
    for name in names:
        others = [n for n in names if n != name]
        groups: dict[tuple[Any, ...], list[dict[str, Any]]] = {}
        for r in rows:
            groups.setdefault(tuple(_key(r.get(n)) for n in others), []).append(r)
        varied = [g for g in groups.values() if len({_key(r.get(name)) for r in g}) > 1]
        ran = any(r.get("outcome") == "ok" for g in varied for r in g)  # not all fell alike
        if ran and all(
            len({tuple(_key(r.get(c)) for c in columns) for r in g}) == 1 for g in varied
        ):
            said.append(name)
    return said


def _key(value: Any) -> Any:
    """A cell as a key of its own value (NaN equal to NaN)."""
    if isinstance(value, float) and math.isnan(value):
        return "nan"
    return value


def step_of(options: Any, model: Any) -> str:
    """The step a sweep's runs take, and where it is from (a sweep has no --dt)."""
    given = model.simulation.dt is not None
    where = "the file's simulation block" if given else "the default: the file's gives none"
    return f"dt {options.dt:g}s, {where}"


def plan_text(plan: dict[str, Any]) -> str:
    """``sweep.json``'s text: indented, each run on a line of its own (indented throughout,
    1,000,000 runs took Python's JSON encoder some 10 s, before the sweep's first line)."""
    head = json.dumps({**plan, "runs": []}, indent=2)
    runs = ",\n    ".join(map(json.dumps, plan["runs"]))
    return head.replace('"runs": []', f'"runs": [\n    {runs}\n  ]', 1) + "\n"


def alike(a: Any, b: Any) -> bool:
    """Two plans (or parts) alike, their numbers to a relative 1e-12: a value written in
    other units is the same (``57cm/s`` is 0.5700000000000001 m/s; it was refused as another
    sweep of ``0.57``)."""
    if isinstance(a, dict) and isinstance(b, dict):
        return a.keys() == b.keys() and all(alike(a[k], b[k]) for k in a)
    if isinstance(a, list | tuple) and isinstance(b, list | tuple):  # == first: 1e6 runs
        return len(a) == len(b) and (a == b or all(map(alike, a, b)))
    numbers = (int, float)
    if isinstance(a, numbers) and isinstance(b, numbers) and not isinstance(a, bool):
        return not isinstance(b, bool) and same_value(float(a), float(b))
    return bool(a == b)


class Preparing:
    """A line every ``every`` s while a sweep reads and writes its plan, until its progress
    (``progress``, called by ``run_sweep``) is first reported: a plan of 1,000,000 runs took
    some 30 s, where a log had no line (a line every 10 s from the start, a stall included)."""

    def __init__(self, runs: int, bar: Callable[[int, int, float | None], None],
                 every: float = 10.0) -> None:  # fmt: skip
        self.runs, self.bar, self.every = runs, bar, every
        self.start = time.monotonic()
        self.done = threading.Event()
        self.thread: threading.Thread | None = threading.Thread(
            target=self._beat, daemon=True, name="legdsl-sweep-preparing"
        )
        try:
            self.thread.start()
        except RuntimeError:  # no thread to spare (ulimit -v): no lines, the sweep goes on
            self.thread = None

    def _beat(self) -> None:
        while not self.done.wait(self.every):
            clear = "\r\033[K" if sys.stderr.isatty() else ""
            print(f"{clear}legdsl: sweep: reading its plan of {self.runs:,} runs "
                  f"({time.monotonic() - self.start:.0f} s)", file=sys.stderr, flush=True)  # fmt: skip

    def stop(self) -> None:
        self.done.set()
        if self.thread is not None:
            self.thread.join()
            self.thread = None

    def progress(self, done: int, total: int, left: float | None) -> None:
        if self.thread is not None:
            self.stop()
        self.bar(done, total, left)
