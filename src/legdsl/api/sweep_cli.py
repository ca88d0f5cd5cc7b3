"""The ``legdsl sweep`` command (the sweep itself is ``legdsl.api.sweep``)."""

from __future__ import annotations

import argparse
import contextlib
import errno
import fcntl
import json
import math
import os
import sys
from collections.abc import Callable
from dataclasses import asdict
from pathlib import Path
from typing import IO, Any

from legdsl.analysis.sweep_plot import as_number, plot_sweep
from legdsl.api.run_options import run_options
from legdsl.api.sweep import (
    METRIC_UNITS,
    METRICS,
    actuator_settings,
    check_not_negative,
    iter_jobs,
    points,
    progress_bar,
    read_planned,
    read_table,
    run_sweep,
    seconds,
    units_of,
)
from legdsl.api.sweep_axes import bare_in_si, parse_axis, refuse_swept_twice
from legdsl.api.sweep_notes import (
    Preparing,
    alike,
    beyond_a_plot,
    changed_nothing,
    plan_text,
    step_of,
)
from legdsl.api.workers import dask_address
from legdsl.check.source import check_model
from legdsl.codegen.fingerprints import controller_fingerprint, creature_fingerprint
from legdsl.files import REFUSED_WRITES, atomic_same_name, write_atomic
from legdsl.lang.errors import UsageError
from legdsl.lang.units import Dim
from legdsl.pipeline.backend import python_backend_note
from legdsl.pipeline.options import check_output_dir
from legdsl.pipeline.outputs import drawn_if_room
from legdsl.pipeline.report import ProgressLog
from legdsl.pipeline.settings import parse_given, refuse_repeated, require_controller, sort_settings
from legdsl.sim.machine import overwritten
from legdsl.sim.run_loop import Interrupted

Command = Callable[[argparse.Namespace], int]
DEFAULT_FROM = 3.0  # s: the metrics are measured from here (--from)


def add_sweep_parser(sub: Any) -> Command:
    p = sub.add_parser(
        "sweep",
        help="run a controller over a grid or samples of its parameters; one table row per run",
        description=(
            "Run a controller over every combination of --grid values (and --random or --lhs "
            "draws), recording each run's gait metrics and outcome in OUT/sweep.csv and drawing "
            "OUT/sweep.png. Rerunning the same command resumes an interrupted sweep."
        ),
        epilog="Example: legdsl sweep creatures/kangaroo.leg --controller hop --grid speed=2:6:5 "
        "--grid k_speed=0.05:0.2:4 --time 10 --out sweeps/k",
    )
    p.add_argument("file", metavar="FILE", help="a .leg file")
    p.add_argument("--creature", help="which creature, if the file has several")
    p.add_argument("--controller", required=True, metavar="NAME", help="the controller to run")
    p.add_argument("--grid", action="append", default=[], metavar="NAME=LO:HI:N",
                   help="N values from LO to HI, or NAME=A,B,C; NAME an input, a parameter or "
                   "ACTUATOR.KEY (a unit may follow each number; a bare number is in SI units)")  # fmt: skip
    p.add_argument("--random", action="append", default=[], metavar="NAME=LO:HI",
                   help="--samples uniform draws from LO to HI")  # fmt: skip
    p.add_argument("--lhs", action="append", default=[], metavar="NAME=LO:HI",
                   help="--samples Latin-hypercube draws from LO to HI")  # fmt: skip
    p.add_argument("--samples", type=int, default=None, help="draws for --random/--lhs (10)")
    p.add_argument("--seed", type=int, default=None, help="seed of the draws (0)")
    p.add_argument("--set", action="append", default=[], metavar="NAME=VALUE",
                   help="a fixed setting for every run, as legdsl run --set")  # fmt: skip
    p.add_argument("--time", default=10.0, help="simulated time per run (s, 10; or with a unit)")
    p.add_argument("--from", dest="t_from", default=None,
                   help="measure the metrics from this time (s, default 3)")  # fmt: skip
    p.add_argument("--out", required=True, metavar="DIR", help="where the table and plot go")
    p.add_argument("--keep-runs", action="store_true", help="keep each run's directory")
    p.add_argument("--jobs", type=int, default=os.cpu_count() or 1,
                   help="runs at once, in separate processes (default: all cores)")  # fmt: skip
    p.add_argument("--plot", default=None, choices=METRICS,
                   help="the metric to draw (default speed_error)")  # fmt: skip
    p.add_argument("--generated", default="generated", help="where generated modules live")
    p.add_argument("--dask", metavar="ADDRESS", default=None,
                   help="run on the Dask cluster at tcp://HOST:PORT, or 'local' for a LocalCluster "
                   "of --jobs workers (default: local processes)")  # fmt: skip
    return cmd_sweep


def cmd_sweep(args: argparse.Namespace) -> int:
    model = check_model(args.file, args.creature)
    require_controller(model, args.controller)
    controller = model.controller(args.controller)
    dims: dict[str, Dim] = {c.name: c.dim for c in (*controller.inputs, *controller.params)}
    dims |= actuator_settings(model)
    axes = [parse_axis(kind, text, dims) for kind in ("grid", "random", "lhs")
            for text in getattr(args, kind)]  # fmt: skip
    notes = []  # said once the options' refusals have had their say (--samples 0 was told
    # 'not used' first, then refused)
    for kind in ("grid", "random", "lhs"):  # bare numbers are SI: an angle's are radians
        for text in getattr(args, kind):
            name = text.partition("=")[0].strip()
            if note := bare_in_si(text, name, dims[name]):
                notes.append(f"legdsl: note: --{kind} {text}: {note.removeprefix('; ')}")
    check_not_negative(axes)
    unused = [f"--{n}" for n in ("samples", "seed") if getattr(args, n) is not None]
    if unused and not args.random and not args.lhs:  # they were taken and unused, unsaid
        notes.append(f"legdsl: note: {' and '.join(unused)} {'are' if len(unused) > 1 else 'is'} "
                     "for --random and --lhs draws, and this sweep has none (its --grid values "
                     "are every one run): not used")  # fmt: skip
    args.samples = 10 if args.samples is None else args.samples
    args.seed = 0 if args.seed is None else args.seed
    if not axes:
        raise UsageError("sweep: give at least one --grid, --random or --lhs")
    refuse_swept_twice([(k, t) for k in ("grid", "random", "lhs") for t in getattr(args, k)])
    for text in args.set:  # a fixed value would override the swept one in every run
        name, _, value = text.partition("=")
        name = name.strip().removeprefix(f"{args.controller}.")  # its own value: the same
        if name in {a.name for a in axes} and "@" not in value:
            raise UsageError(
                f"--set {text}: {name} is swept, and this would set it in every run; "
                f"leave out the --set (a change during the run is --set {name}=VALUE@T)"
            )
    args.time = seconds("--time", args.time)
    if args.t_from is not None:
        args.t_from = seconds("--from", args.t_from, "nonnegative")
    for flag, value, what in (
        ("--samples", args.samples, "draws"),
        ("--jobs", args.jobs, "runs at once"),
    ):
        if value < 1:  # which one, and its value pointed at ('sweep: --samples, --jobs and
            # --time must be positive' named all three)
            raise UsageError(f"{flag} {value}: must be more than zero; give 1 or more ({what})")
    dask_address(args.dask)
    if args.seed < 0:  # numpy's generator takes none
        raise UsageError(f"sweep: --seed {args.seed}: give a whole number, 0 or more")
    default = " (the default)" if args.t_from is None else ""
    args.t_from = DEFAULT_FROM if args.t_from is None else args.t_from
    if not args.t_from < args.time:  # every row's metrics would be n/a
        raise UsageError(
            f"sweep: --from {args.t_from:g}{default} is not a time within the runs (--time "
            f"{args.time:g}), so every row's metrics would be n/a; give --from from 0 to "
            "before --time (seconds)"
        )
    combos = points(axes, args.samples, args.seed)
    # a wrong --set is refused here, before sweep.json records it (the corrected command
    # would be refused as another sweep), not by every run
    refuse_repeated(args.set)
    sort_settings(args.set, model, args.controller)
    check_output_dir(args.out, "--out")
    for note in notes:
        print(note, file=sys.stderr)
    # compile once here, so that the workers never race to write generated/NAME/
    from legdsl.api import load

    if (slow := python_backend_note()) is not None:  # the runs' own notice is not shown
        print(f"legdsl: note: {slow}", file=sys.stderr)
    session = load(args.file, args.creature, args.generated).session
    module = session.control(args.controller)
    swept = [(f"--{a.kind} {a.name}", a.name) for a in axes]
    for flag, name in [*swept, *((f"--set {t}", t.partition("=")[0].strip()) for t in args.set)]:
        if said := overwritten(name, args.controller, module, model):  # rows alike, unsaid
            print(f"legdsl: note: {flag}: {said}", file=sys.stderr)
    _refuse_too_stiff(session, args, axes, dims, combos)
    out = Path(args.out)
    made = not out.exists()
    out.mkdir(parents=True, exist_ok=True)
    lock = writer_lock(out, "sweep")  # held until it is done (two would append the same rows)
    bar = progress_bar if sys.stderr.isatty() else ProgressLog("sweep", "runs")
    if isinstance(bar, ProgressLog):  # its lines every 10 s from here (1e6 runs: 30 s unsaid)
        bar(0, len(combos), None)
    preparing = Preparing(len(combos), bar)  # a line every 10 s until the first bar
    try:
        return _sweep_into(out, args, model, controller, axes, dims, combos, preparing)
    finally:  # an API caller may sweep into the same --out again in this process
        preparing.stop()
        release(lock, out, made)


STIFFNESS = ("k", "b", "kp", "kv")  # the settings an explicit step may be too large for


def _refuse_too_stiff(
    session: Any,
    args: argparse.Namespace,
    axes: list[Any],
    dims: dict[str, Dim],
    combos: list[dict[str, float]],
) -> None:
    """The first run, and each swept stiffness or damping too large for the step, refused
    before the plan is recorded: found at its run, it stopped the sweep part-way with its rows
    and sweep.json kept, and the corrected command was refused as another sweep. A larger
    value is never more stable, so each actuator's largest swept values alone are prepared."""
    by_actuator: dict[str, list[str]] = {}
    for a in axes:
        actuator, _, key = a.name.partition(".")
        if key in STIFFNESS:
            by_actuator.setdefault(actuator, []).append(a.name)
    tried = [combos[0]] + [
        dict(zip(names, values, strict=True))
        for names in by_actuator.values()
        for values in _largest(sorted({tuple(c[n] for n in names) for c in combos}))
    ]
    units = units_of(dims)
    options = run_options(session.model, args.time, {})
    if options.dt > options.duration:  # told as legdsl run's (--dt), which a sweep has not
        raise UsageError(f"sweep: --time {args.time:g}s is shorter than one step ({step_of(options, session.model)}); give --time {options.dt:g}s or more, or a smaller dt in the file's simulation block (a sweep has no --dt)")  # fmt: skip
    session.note = None  # its runs' notes are the sweep's rows
    session.step_flags = False  # and their step the file's
    for k, values in enumerate(tried):
        given = [f"{n}={v!r}{units[n]}" for n, v in values.items()]
        try:
            session.prepare(args.controller, [*given, *args.set], options=options)
        except UsageError as e:
            shown = ", ".join(f"{n} = {v:g} {units[n]}".rstrip() for n, v in values.items())
            which = f"its runs at {shown}" if k else f"its first run ({shown})"
            raise UsageError(f"sweep: {which}: {e}") from None


def _largest(points: list[tuple[float, ...]]) -> list[tuple[float, ...]]:
    """The sorted points no other is at least as large as in every coordinate (one or two:
    a spring's k and b, a servo's kp and kv)."""
    front: list[tuple[float, ...]] = []
    for p in reversed(points):  # by the first coordinate, largest first
        if not front or p[-1] > front[-1][-1]:
            front.append(p)
    return front


def _sweep_into(
    out: Path,
    args: argparse.Namespace,
    model: Any,
    controller: Any,
    axes: list[Any],
    dims: dict[str, Dim],
    combos: list[dict[str, float]],
    preparing: Preparing,
) -> int:
    """The sweep, its lock held: the plan, the runs, the table's copies and the map."""
    plan = {"file": str(args.file), "creature": model.name, "controller": args.controller,
            "time": args.time,
            "from": args.t_from, "set": args.set, "runs": combos,
            # what the file says, so that rows of an edited file are not mixed with the new
            "creature_digest": creature_fingerprint(model),
            "controller_digest": controller_fingerprint(model, controller),
            # the step the runs take from the file (a sweep before legdsl read it from the
            # API took 0.4 ms: its rows are not mixed with these)
            "simulation": asdict(model.simulation)}  # fmt: skip
    plan_file = out / "sweep.json"
    planned_before = plan_file.is_file()
    before_plan = _plan_in(plan_file) if planned_before else plan
    if isinstance(before_plan, dict):  # an older legdsl's plan names no creature: its digest
        before_plan = {"creature": model.name, **before_plan}
    if not alike(_comparable(before_plan), _comparable(plan)):
        digests = ("creature_digest", "controller_digest", "simulation")
        edited = (  # the same sweep but for the file (an older legdsl's plan has no digests)
            isinstance(before_plan, dict)
            and all(k in before_plan for k in digests)
            and all(before_plan.get(k) == v for k, v in plan.items() if k not in digests)
        )
        why = ("the .leg file's creature or controller has changed since its rows were run"
               if edited else _plan_differs(before_plan, plan))  # fmt: skip
        raise UsageError(f"{out} holds another sweep ({why}); choose another --out or remove it")
    if planned_before and isinstance(before_plan, dict):  # its values as first run, to the bit
        # (57cm is 0.5700000000000001 m, the same sweep as 0.57 m: its runs take the 0.57)
        combos = [{n: float(v) for n, v in r.items()} for r in before_plan["runs"]]
        args.set = list(before_plan["set"])
        plan = {**plan, "runs": combos, "set": args.set}
    base = {
        "source": str(args.file),
        "creature": args.creature,
        "controller": args.controller,
        "units": units_of({a.name: dims[a.name] for a in axes}),
        "fixed": tuple(args.set),
        "duration": args.time,
        "start": args.t_from,
        "generated": args.generated,
    }
    jobs = list(iter_jobs(base, combos, out / "runs" if args.keep_runs else None))
    ran = [int(r["run"]) for r in read_planned(out / "sweep.csv", jobs)]
    if ran and not planned_before:  # its --time, --from... unknown
        raise UsageError(
            f"{out / 'sweep.csv'} has rows but no sweep.json, so what they were run with is "
            "unknown (they were taken as this sweep's, whatever their --time or --from); put "
            "its sweep.json back, or remove the table to run the sweep again"
        )
    write_atomic(plan_file, plan_text(plan))
    before = len(ran)
    # a run is kept by the sweep that runs it: resumed with --keep-runs added, the rows from
    # before had no directory, and nothing said so
    bare = [i for i in ran if args.keep_runs and not Path(str(jobs[i].keep)).is_dir()]
    if args.keep_runs and before >= len(jobs):  # it kept nothing, and said nothing
        print(f"legdsl: note: --keep-runs keeps the runs a sweep runs, and every run of "
              f"this one is in {out / 'sweep.csv'} already; to keep them, sweep into "
              "another --out", file=sys.stderr)  # fmt: skip
    elif bare:
        print(f"legdsl: note: --keep-runs keeps the runs a sweep runs: {len(bare)} of the "
              f"{before} rows from before in {out / 'sweep.csv'} have no directory under "
              f"{out / 'runs'} (run {bare[0]}{', ...' if len(bare) > 1 else ''}), as they ran "
              "without it; to keep every run, sweep into another --out", file=sys.stderr)  # fmt: skip
    try:
        rows = run_sweep(jobs, out / "sweep.csv", args.jobs, preparing.progress, args.dask)
    except UsageError:  # every run refused (a setting too stiff for the step): the plan it
        # wrote would refuse the corrected command as another sweep
        if not planned_before and not read_table(out / "sweep.csv"):
            plan_file.unlink(missing_ok=True)
        raise
    except OSError as e:  # a full disk, a quota, ulimit -f: what is kept, and the resume
        if e.errno not in REFUSED_WRITES:
            raise
        done = len(read_table(out / "sweep.csv"))
        fix = ("raise the file-size limit (ulimit -f)" if e.errno == errno.EFBIG else
               "free some space" if e.errno in (errno.ENOSPC, errno.EDQUOT) else "check the disk")  # fmt: skip
        raise UsageError(
            f"sweep stopped: cannot write {e.filename}: {e.strerror}; {done} of {len(jobs)} runs "
            f"are in {out / 'sweep.csv'}: {fix}, and the same command again runs the other "
            f"{len(jobs) - done}"
        ) from None
    except (KeyboardInterrupt, Interrupted):
        preparing.stop()
        done = len(read_table(out / "sweep.csv"))
        kept = (f"{done} of {len(jobs)} runs are in {out / 'sweep.csv'}" if done else
                f"no run's row had come back, so {out / 'sweep.csv'} was not begun")  # fmt: skip
        print(f"legdsl: sweep interrupted: {kept}; the same command again runs the other "
              f"{len(jobs) - done}", file=sys.stderr)  # fmt: skip
        raise
    metric = args.plot or "speed_error"
    units = {**base["units"], **METRIC_UNITS}
    picture = out / "sweep.png"

    def draw() -> None:
        shown, labels = in_written_units(rows, axes, units)
        with atomic_same_name(picture) as drawn:  # matplotlib writes in place: no half PNG
            plot_sweep(shown, [a.name for a in axes], metric, drawn, labels,
                       [a.name for a in axes if a.kind != "grid"])  # fmt: skip

    huge = beyond_a_plot(rows, [a.name for a in axes], metric)  # matplotlib's ValueError
    try:
        _parquet(rows, out / "sweep.parquet")
        not_drawn = None if huge else drawn_if_room("draw the heat map", draw)
    except (KeyboardInterrupt, Interrupted):  # it said only "interrupted"
        print(f"legdsl: sweep interrupted as it drew its heat map: its {len(rows)} rows "
              f"are whole in {out / 'sweep.csv'}; the same command again draws {picture} "
              "without a run", file=sys.stderr)  # fmt: skip
        raise
    if huge:
        print(f"legdsl: note: {picture} not drawn: {huge}; the rows are in "
              f"{out / 'sweep.csv'}", file=sys.stderr)  # fmt: skip
    elif not not_drawn:
        _say_unmeasured(rows, metric, args, controller, picture)
    quiet = changed_nothing(rows, [a.name for a in axes], METRICS)
    for a in axes:  # as legdsl tune says of tuned parameters that changed nothing
        if a.name in quiet:
            print(f"legdsl: note: --{a.kind} {a.name}: its values changed nothing in these "
                  "runs (every row alike, to the bit, but for it): the controller reads it only "
                  "where these runs never go, a limit they never reach or a state they never "
                  "enter", file=sys.stderr)  # fmt: skip
    fell = sum(1 for r in rows if r["outcome"] != "ok")
    resumed = f", {before} of them from before" if before else ""
    wrote = f"{out / 'sweep.csv'}" + ("" if not_drawn or huge else f", {picture}")
    print(f"{len(rows)} run{'' if len(rows) == 1 else 's'}{resumed} ({fell} fell or diverged): "
          f"{wrote}")  # fmt: skip
    if not_drawn:  # the table is whole; the same command again draws the map from it
        print(f"legdsl: sweep: its table is whole, its heat map not drawn: {not_drawn} "
              "(the table is kept: that draws it)", file=sys.stderr)  # fmt: skip
        return 2  # as for any out-of-memory line
    return 0


def in_written_units(
    rows: list[dict[str, Any]], axes: list[Any], units: dict[str, str]
) -> tuple[list[dict[str, Any]], dict[str, str]]:
    """The rows and units to draw: each swept name in the unit its values were given in
    (``--grid heading=0deg:90deg:3``: a panel was titled 'heading = 1.5708 rad'), the table's
    own cells in SI units."""
    factors = {}
    for a in axes:
        if a.written and a.written != units.get(a.name):
            with contextlib.suppress(UsageError):  # a unit the axis read: it reads again
                factors[a.name] = (a.written, parse_given(f"1{a.written}", "--grid").value)
    if not factors:
        return rows, units
    shown = [{**r, **{n: as_number(r.get(n)) / f for n, (_, f) in factors.items()}} for r in rows]
    return shown, {**units, **{n: u for n, (u, _) in factors.items()}}


def _say_unmeasured(
    rows: list[dict[str, Any]],
    metric: str,
    args: argparse.Namespace,
    controller: Any,
    picture: Path,
) -> None:
    """A note where no run measured the metric drawn: the picture has nothing to colour (a
    controller whose command is not called 'speed' drew an empty map, and said nothing)."""
    lacking = sum(1 for r in rows if metric not in r)  # a table from before the column
    if lacking:  # (or its header edited): plotted as far as it goes, said
        which = "its rows have" if lacking == len(rows) else f"{lacking} of its rows have"
        print(f"legdsl: note: {args.out}/sweep.csv has no column {metric} (written before "
              f"legdsl measured it, or its header edited): {which} that cell empty, and "
              f"{picture} shows{' none' if lacking == len(rows) else ' the others'}; to "
              "measure it, sweep into another --out", file=sys.stderr)  # fmt: skip
        return
    if any(math.isfinite(as_number(r.get(metric))) for r in rows):
        return
    if metric == "speed_error" and "speed" not in {c.name for c in controller.inputs}:
        why = (f"controller '{args.controller}' has no input 'speed', the command the error is "
               "measured from (docs/controllers.md); draw another metric, --plot running_speed")  # fmt: skip
    elif all(r["outcome"] != "ok" for r in rows):
        why = "every run fell or diverged"
    else:
        why = f"no run has a whole stride from --from {args.t_from:g} s to its end"
    print(f"legdsl: note: no run measured {metric}, so {picture} shows none: {why}",
          file=sys.stderr)  # fmt: skip


# the plan's parts as the command gives them, to say which differ from the one in OUT
_PLAN_WORDS = {
    "file": ".leg file", "creature": "--creature", "controller": "--controller",
    "time": "--time", "from": "--from",
    "set": "--set", "runs": "swept values (--grid, --random, --lhs, --samples, --seed)",
    "creature_digest": "creature (the .leg file changed)",
    "controller_digest": "controller (or its file changed)",
    "simulation": "simulation block (its step)",
}  # fmt: skip


def _plan_differs(before: object, plan: dict[str, Any]) -> str:
    """What differs between the plan in OUT's sweep.json and this sweep's, in words."""
    if not isinstance(before, dict):
        return "its sweep.json is damaged"
    mine, theirs = _comparable(plan), _comparable(before)
    keys = [k for k in plan if not alike(theirs.get(k), mine[k])]
    if "file" in keys or "creature" in keys:  # whose digests differ with them, unsaid
        keys = [k for k in keys if not k.endswith("_digest")]
    other = [_PLAN_WORDS.get(k, k) for k in keys]
    return f"other {', '.join(other)}" if other else "its sweep.json differs"


def _comparable(plan: Any) -> Any:
    """A plan with its --set values in SI units: ``speed=150cm/s`` is ``speed=1.5m/s``'s sweep
    (it was refused as another, where the grid's values in other units were not)."""
    if not isinstance(plan, dict) or not isinstance(plan.get("set"), list):
        return plan
    return {**plan, "set": sorted(map(_setting_in_si, plan["set"]), key=repr)}


def _setting_in_si(text: object) -> object:
    """``NAME=VALUE[@T]`` as (NAME, VALUE, T) in SI units; as it is where it does not read."""
    if not isinstance(text, str):
        return text
    name, _, value = text.partition("=")
    value, at, when = value.partition("@")
    try:
        numbers = [parse_given(v, "--set").value for v in (value, *([when] if at else []))]
    except UsageError:
        return text
    return [name.strip(), *numbers]


def _parquet(rows: list[dict[str, Any]], path: Path) -> None:
    """The table as Parquet too, when pyarrow is installed."""
    try:
        import pyarrow as pa
        import pyarrow.parquet as pq
    except ImportError:
        return
    columns = {k: [r.get(k) for r in rows] for k in rows[0]} if rows else {}
    pq.write_table(pa.table(columns), path)


def _plan_in(plan_file: Path) -> object:
    """The plan a sweep directory records (None when its sweep.json is damaged: then it is
    another sweep's, as far as this one can tell)."""
    try:
        return json.loads(plan_file.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, json.JSONDecodeError):
        return None


def writer_lock(out: Path, command: str) -> IO[str]:
    """An exclusive lock on ``OUT/.COMMAND.lock`` (``sweep``, ``tune``), or a ``UsageError``
    if another of that command holds it (released by the system when the process ends,
    killed or not)."""
    handle = (out / f".{command}.lock").open("w")
    try:
        fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        handle.close()
        raise UsageError(f"another legdsl {command} is writing {out}; wait for it to finish, "
                         "or choose another --out") from None  # fmt: skip
    return handle


def release(lock: IO[str], out: Path, made: bool) -> None:
    """The lock closed; a folder the command ``made`` that holds nothing else (refused before
    any result: a --dask scheduler not reached left it with its lock alone) removed."""
    lock.close()
    held = Path(lock.name)
    with contextlib.suppress(OSError):  # gone already, or something else came into it
        if made and [p.name for p in out.iterdir()] == [held.name]:
            held.unlink()
            out.rmdir()
