"""``legdsl sweep``: one creature run over a set of parameter values, one table row per run.

    legdsl sweep creatures/kangaroo.leg --controller hop --grid speed=2:6:5 \\
        --grid k_speed=0.05:0.2:4 --time 10 --out sweeps/k

Values: ``--grid NAME=LO:HI:N`` (N values from LO to HI), ``--grid NAME=A,B,C`` (a list),
``--random NAME=LO:HI`` or ``--lhs NAME=LO:HI`` (``--samples`` uniform or Latin-hypercube
draws, with ``--seed``). Numbers take a unit right after them (``2m/s:6m/s:5``); a bare
number is in the SI unit of what it sets (m/s for a speed, s for ``k_speed``). Grids combine
with each other; random and Latin-hypercube draws combine with the grid.

The runs go on in parallel processes (all cores unless ``--jobs``) or on a Dask cluster, in
small batches through the C backend's batched entry point; each finished run's row is
appended to ``OUT/sweep.csv`` at once (and the whole table to ``OUT/sweep.parquet`` when
pyarrow is installed), so an interrupted sweep resumes where it stopped: rows already in the
table are not run again. ``--keep-runs`` keeps each run's directory under ``OUT/runs/``.
The table is drawn into ``OUT/sweep.png``: a heat map over two swept names, lines over one.
"""

from __future__ import annotations

import contextlib
import csv
import itertools
import math
import os
import time
import warnings
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from legdsl.analysis.sweep_plot import as_number
from legdsl.api.notes import LegdslWarning
from legdsl.api.sweep_axes import Axis, _at_most
from legdsl.api.sweep_axes import bare_in_si as bare_in_si  # (read from here before)
from legdsl.api.sweep_axes import parse_axis as parse_axis
from legdsl.api.sweep_pace import SweepPace
from legdsl.api.workers import Workers
from legdsl.files import atomic_path, refused
from legdsl.ir.model import NON_NEGATIVE, SETTABLE, Model, setting_kind
from legdsl.lang.errors import UsageError
from legdsl.lang.units import KINDS, Dim, named_si_unit
from legdsl.pipeline.options import read_seconds
from legdsl.pipeline.report import progress_line

# The metrics kept in every row (keys of legdsl.analysis.metrics' summaries).
METRICS = (
    "running_speed", "running_speed_std", "speed_error", "stride_duration", "stride_length",
    "flight_duration", "stance_duration", "pitch_magnitude", "peak_vertical_acceleration",
    "positive_work", "energy_per_metre", "cost_of_transport",
)  # fmt: skip
METRIC_UNITS = {
    "running_speed": "m/s", "running_speed_std": "m/s", "speed_error": "m/s",
    "stride_duration": "s", "stride_length": "m", "flight_duration": "s", "stance_duration": "s",
    "pitch_magnitude": "deg", "peak_vertical_acceleration": "g", "positive_work": "J",
    "energy_per_metre": "J/m", "cost_of_transport": "-",
}  # fmt: skip


def points(axes: Sequence[Axis], samples: int, seed: int) -> list[dict[str, float]]:
    """Every combination of the grids, times the random and Latin-hypercube draws."""
    grids = [a for a in axes if a.kind == "grid"]
    drawn = [a for a in axes if a.kind != "grid"]
    _at_most(math.prod(len(a.values) for a in grids) * (samples if drawn else 1), "the sweep")
    combos = [dict(zip([a.name for a in grids], c, strict=True)) for c in
              itertools.product(*[a.values for a in grids])]  # fmt: skip
    if not drawn:
        return combos
    rng = np.random.default_rng(seed)
    draws: list[dict[str, float]] = [{} for _ in range(samples)]
    for a in drawn:
        lo, hi = a.values
        if a.kind == "lhs":  # one draw in each of `samples` equal strata, strata shuffled
            u = (rng.permutation(samples) + rng.random(samples)) / samples
        else:
            u = rng.random(samples)
        for d, x in zip(draws, lo + u * (hi - lo), strict=True):
            d[a.name] = float(x)
    return [{**c, **d} for c in combos for d in draws]


# ---------------------------------------------------------------- running


@dataclass(frozen=True)
class Job:
    index: int
    source: str
    creature: str | None
    controller: str
    values: dict[str, float]  # SI
    units: dict[str, str]  # SI unit of each swept name
    fixed: tuple[str, ...]  # --set texts for every run
    duration: float
    start: float
    generated: str
    keep: str | None  # the run's directory, if kept
    # virtual legs to measure with (``NAME=LEG,LEG``), the first starting the strides: a gait's
    # pairs (``legdsl tune --table2 "quadruped trot"``), as ``legdsl metrics --table2`` finds them
    groups: tuple[str, ...] = ()


_CREATURES: dict[tuple[str, str | None, str], Any] = {}  # per process


def _creature(job: Job) -> Any:
    from legdsl.api import load

    key = (job.source, job.creature, job.generated)
    if key not in _CREATURES:
        _CREATURES[key] = load(job.source, job.creature, job.generated)
        session = _CREATURES[key].session
        session.note = None  # a row says how its run went: no warning per run
        session.step_flags = False  # its runs take the file's step: a sweep has no --dt
    return _CREATURES[key]


def _run_args(job: Job) -> dict[str, Any]:
    """The job as the keyword arguments of ``Creature.run``."""
    settings = {f"{n}": f"{v!r}{job.units[n]}" for n, v in job.values.items()}
    for text in job.fixed:
        name, _, value = text.partition("=")
        settings[name] = value
    return {"controller": job.controller, "set": settings, "time": job.duration}


BATCH_RUNS = 8  # runs in one batch at most


def run_jobs(jobs: Sequence[Job], pool: Workers) -> Iterator[dict[str, Any]]:
    """The row of each job, as each finishes: the jobs go to the pool's processes (or Dask
    workers) in small batches of one creature, each run there through the C backend's
    batched entry point (``run_batch_of_jobs``)."""
    by_creature: dict[tuple[str, str | None, str], list[Job]] = {}
    for job in jobs:
        by_creature.setdefault((job.source, job.creature, job.generated), []).append(job)
    size = batch_size(len(jobs), pool.workers)
    batches = [group[k : k + size] for group in by_creature.values()
               for k in range(0, len(group), size)]  # fmt: skip
    for rows in pool.as_completed(run_batch_of_jobs, batches):
        yield from rows


def batch_size(runs: int, workers: int) -> int:
    """Runs in one batch: about four batches per worker, so that a row comes back soon after
    its run (for the progress bar and for resuming), and a batch's setup is shared."""
    return max(1, min(BATCH_RUNS, math.ceil(runs / (4 * workers))))


def run_batch_of_jobs(jobs: Sequence[Job]) -> list[dict[str, Any]]:
    """The rows of several jobs of one creature, in this process: one batch
    (``Creature.run_many``, on one thread: the pool's workers are the parallelism). A run
    cut short by Ctrl-C ends the batch: its row says ``interrupted`` and no other run
    starts after it."""
    rows = []
    for i, run in _creature(jobs[0]).run_many([_run_args(j) for j in jobs], threads=1):
        rows.append(_row(jobs[i], run))
        if run.status == "interrupted":
            break
    return rows


def _row(job: Job, run: Any) -> dict[str, Any]:
    row: dict[str, Any] = {"run": job.index, **job.values}
    end = float(run.info.get("sim_time", 0.0))  # the last sample may be before it
    when = float(run.info.get("diverged_at", end))  # an energy rise's end, not the run's
    row["outcome"] = "ok" if run.status == "ok" else f"{run.status} at {when:.3f} s"
    row["simulated"] = end
    values: dict[str, float] = {}
    row["by_label"] = {}  # every metric by its Table 2 label, for tuning (not in the table)
    try:
        first = job.groups[0].partition("=")[0] if job.groups else None
        pairs = {"leg": first, "groups": list(job.groups)} if first else {}
        with warnings.catch_warnings():  # the outcome cell says how the run ended
            warnings.simplefilter("ignore", LegdslWarning)
            metrics = run.metrics(start=min(job.start, end), **pairs)
        values = {s.key: s.value for s in metrics.summaries}
        # the stride-to-stride spread of the speed: a mean on the command may hide a gait
        # swinging 0.5 m/s about it over seconds
        spread = [s.std for s in metrics.summaries if s.key == "running_speed"]
        values["running_speed_std"] = spread[0] if spread else math.nan
        # by label, and by key for the Table 2 rows measured under another name
        row["by_label"] = {s.key: s.value for s in metrics.summaries} | {
            s.label: s.value for s in metrics.summaries
        }
        row["strides"] = metrics.n_strides
        if not metrics.n_strides and run.status == "ok":  # the window too short for a stride?
            row["run_stride_duration"] = whole_run_stride(run, pairs)
    except UsageError:
        row["strides"] = 0
    for name in METRICS:  # a run that fell or diverged measured none: its strides until
        # then (a fall at 1.044 s kept 'running_speed 2.73') were averaged with the runs that
        # lasted by a reader of the table; `legdsl metrics` of its kept directory measures them
        row[name] = values.get(name, math.nan) if run.status == "ok" else math.nan
    if job.keep is not None:
        run.save(job.keep)
    return row


def whole_run_stride(run: Any, pairs: dict[str, Any]) -> float:
    """The mean stride duration over the whole run (NaN without a whole stride in it either):
    for a run that lasted with none in its window, to say how long a window would hold one
    (``legdsl tune`` on a 1 s window of a 0.7 s stride scored it as a fall, unsaid)."""
    try:
        return float(run.metrics(start=0.0, **pairs).value("stride_duration"))
    except (UsageError, LookupError):
        return math.nan


def run_sweep(
    jobs: Sequence[Job],
    table: Path,
    workers: int,
    progress: Callable[[int, int, float | None], None] | None = None,
    dask: str | None = None,
) -> list[dict[str, Any]]:
    """Run the jobs not yet in ``table`` (CSV), appending each row as it finishes, on
    ``workers`` local processes or a Dask cluster (``legdsl.api.workers``)."""
    done = read_planned(table, jobs)
    finished = {int(r["run"]) for r in done}
    todo = [j for j in jobs if j.index not in finished]
    if not todo:
        return done
    columns = ["run", *jobs[0].values, "outcome", "simulated", "strides", *METRICS]
    if table.exists():  # drop a line a kill left half-written before appending to it
        with atomic_path(table) as fresh:
            fresh.touch()
            for row in done:  # a fall's metrics, from a table written before, left out
                fell = str(row.get("outcome")) != "ok"
                _append(fresh, columns, {**row, **dict.fromkeys(METRICS if fell else (), math.nan)})
    # never more processes than runs (--jobs 100000 forked 100000 processes for two runs)
    workers = min(workers, len(todo))
    pace = SweepPace(len(todo), workers, batch_size(len(todo), workers))
    count = 0

    def report() -> None:  # at the start, at each row, and about every second between
        if progress is not None:
            progress(len(done) + count, len(jobs), pace.left(time.monotonic()))

    report()  # a bar at once, and a log's lines from the start (a stall says so too)
    with Workers(workers, dask) as pool:
        if pool is not None:
            pool.waiting = report
        for row in run_jobs(todo, pool):
            if str(row["outcome"]).startswith("interrupted"):
                # not a result: the run is left out of the table, for the resume to run it
                raise KeyboardInterrupt
            _append(table, columns, row)
            count += 1
            pace.row(as_number(row.get("simulated")), time.monotonic())
            report()
    return read_table(table)


def _append(table: Path, columns: list[str], row: dict[str, Any]) -> None:
    existed = table.exists()
    size = table.stat().st_size if existed else 0
    try:
        with table.open("a", newline="") as f:
            writer = csv.DictWriter(f, fieldnames=columns)
            if size == 0:
                writer.writeheader()
            writer.writerow({c: _cell(row.get(c, "")) for c in columns})
            f.flush()
            os.fsync(f.fileno())
    except OSError as e:  # a full disk: no half row left, and the table named
        with contextlib.suppress(OSError):
            if existed:
                os.truncate(table, size)
            else:
                table.unlink()
        raise refused(OSError(e.errno, e.strerror, str(table)), table) from None


def _cell(value: Any) -> Any:
    """A row's value as its table cell: a metric the run did not measure (NaN) is empty, as
    docs/controllers.md says of a speed error without a commanded speed (it was 'nan'), and
    as CSV readers (pandas, a spreadsheet) take a missing value."""
    return "" if isinstance(value, float) and math.isnan(value) else value


def read_planned(table: Path, jobs: Sequence[Job]) -> list[dict[str, Any]]:
    """The rows of a sweep table (``read_table``), each of a run of the plan (``jobs``, by
    their index) once, with that run's swept values: a row twice (two tables joined) or of
    other values (renumbered) was counted, '8 runs' of a 6-run sweep; told by its line."""
    by_index = {j.index: j for j in jobs}
    rows = _numbered_rows(table)
    if any(r["run"] not in by_index for _, r in rows):
        raise UsageError(
            f"{table} has rows of runs this sweep has not; remove it to run the sweep again"
        )
    seen: dict[int, int] = {}  # run -> its line
    for line, r in rows:
        job = by_index[r["run"]]
        for name, planned in job.values.items():
            if not math.isclose(as_number(r.get(name)), planned, rel_tol=1e-9, abs_tol=1e-12):
                raise UsageError(
                    f"{table} is damaged at line {line}: run {job.index}'s {name} is "
                    f"{r.get(name)} there, but {planned!r} in the sweep's plan (edited, or "
                    "another sweep's row); remove that line, and its run is run again"
                )
        if job.index in seen:
            raise UsageError(
                f"{table} is damaged at line {line}: a second row of run {job.index} (line "
                f"{seen[job.index]} is one); remove one of them"
            )
        seen[job.index] = line
    return sorted((r for _, r in rows), key=lambda r: int(r["run"]))


def read_table(table: Path) -> list[dict[str, Any]]:
    """The rows of a sweep table (a half-written last line, from a kill, is dropped)."""
    return sorted((r for _, r in _numbered_rows(table)), key=lambda r: int(r["run"]))


def _numbered_rows(table: Path) -> list[tuple[int, dict[str, Any]]]:
    """``read_table``'s rows as they stand in the file, each with its line number."""
    if not table.is_file():
        return []
    damaged = (
        f"{table} is damaged (edited, or not a sweep's table); remove it to run the sweep again"
    )
    try:
        with table.open(newline="", encoding="utf-8") as f:
            rows = list(csv.DictReader(f))
    except (UnicodeDecodeError, csv.Error):
        raise UsageError(damaged) from None
    if rows and (None in rows[-1].values() or None in rows[-1]):
        rows.pop()
    for i, r in enumerate(rows):  # a row of too few or too many cells before the last one
        if None in r.values() or None in r:  # (which DictReader fills with None) is no run's
            raise UsageError(f"{table} is damaged at line {i + 2}: it has too "
                             f"{'many' if None in r else 'few'} cells (edited, or written over); "
                             "remove that line, and its run is run again")  # fmt: skip
    typed = [{k: _typed(v) for k, v in r.items()} for r in rows]
    if not all(isinstance(r.get("run"), int) and r["run"] >= 0 for r in typed):
        raise UsageError(damaged)
    return [(i + 2, r) for i, r in enumerate(typed)]


def _typed(text: str) -> Any:
    """A table cell as the number it holds, else as text; an empty one (a metric not measured,
    or a column the table did not have yet) as NaN, as a table that wrote 'nan' read back."""
    if not text:
        return math.nan
    try:
        return int(text)
    except ValueError:
        pass
    try:
        return float(text)
    except ValueError:
        return text


def seconds(flag: str, value: str | float, least: str = "positive") -> float:
    """``--time`` or ``--from`` in seconds: a number as given on the command line (a unit may
    follow, as for ``legdsl run``: ``2s``, ``500ms``; a bare number is seconds), or a default."""
    return read_seconds(flag, value, least) if isinstance(value, str) else value


def progress_bar(done: int, total: int, left: float | None) -> None:
    progress_line(done, total, "runs", left)


def iter_jobs(
    base: dict[str, Any], combos: Sequence[dict[str, float]], runs_dir: Path | None
) -> Iterator[Job]:
    for i, values in enumerate(combos):
        keep = str(runs_dir / f"{i:04d}") if runs_dir is not None else None
        yield Job(index=i, values=values, keep=keep, **base)


def actuator_settings(model: Model) -> dict[str, Dim]:
    """Each actuator setting a run takes (``--set ACTUATOR.KEY``), by its dimension."""
    return {
        f"{a.name}.{key}": KINDS[setting_kind(key, a.rotary)][0]
        for a in model.actuators
        for key in SETTABLE[a.kind]
    }


def check_not_negative(axes: Sequence[Axis]) -> None:
    """An actuator's gain, damping or stiffness swept below 0 (refused by the .leg checker and
    by ``--set``), refused before any run rather than by the first run that takes it."""
    for a in axes:
        if "." in a.name and a.name.partition(".")[2] in NON_NEGATIVE and min(a.values) < 0:
            raise UsageError(f"--{a.kind} {a.name}: must not be negative (as in the .leg file)")


def units_of(dims: dict[str, Dim]) -> dict[str, str]:
    return {n: named_si_unit(d) for n, d in dims.items()}
