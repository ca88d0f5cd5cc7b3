"""The ``legdsl tune`` command (the search itself is ``legdsl.api.tune``)."""

from __future__ import annotations

import argparse
import contextlib
import json
import math
import os
import signal
import sys
from collections.abc import Callable, Iterator
from dataclasses import asdict
from pathlib import Path
from typing import IO, Any

from legdsl.api.sweep import Job, actuator_settings, units_of
from legdsl.api.sweep_cli import release, writer_lock
from legdsl.api.tune import (
    NO_STRIDE,
    Bound,
    Objective,
    dump,
    plot_history,
    report,
    tune,
    tune_pitch,
    tune_speed,
    unsettled,
)
from legdsl.api.tune_journal import Journal
from legdsl.api.tune_options import (  # checked options; tests import them from here too
    _bounds,
    _check_read,
    _check_search,
    _speed_input,
    _speeds,
    _table2_legs,
    _weight,
)
from legdsl.api.tuned_file import write_tuned, written_unit
from legdsl.check.source import check_model
from legdsl.codegen.fingerprints import controller_fingerprint, creature_fingerprint
from legdsl.ir.controller import Controller
from legdsl.ir.model import Model
from legdsl.lang.errors import UsageError
from legdsl.lang.units import UnitError, parse_unit
from legdsl.pipeline.backend import python_backend_note
from legdsl.pipeline.options import check_output_dir
from legdsl.pipeline.outputs import drawn_if_room
from legdsl.pipeline.settings import require_controller
from legdsl.signals import STOPPING, handled
from legdsl.sim.run_loop import Interrupted

Command = Callable[[argparse.Namespace], int]


def add_tune_parser(sub: Any) -> Command:
    p = sub.add_parser(
        "tune",
        help="tune controller parameters by CMA-ES against speed error (Table 2, energy)",
        description=(
            "Search the named parameters within their bounds by CMA-ES so that the controller "
            "holds each of --speeds (and, with --table2, comes close to the paper's rows; with "
            "--energy-weight, spends less positive actuator work per metre; with --pitch-weight, "
            "rocks its trunk less from stride to stride); "
            "falls are penalised by how early they happen. Writes OUT/NAME.leg with the "
            "tuned values, OUT/tune.json and OUT/tune.png (after Ctrl-C or SIGTERM too, with the "
            "best so far; the same command run again then goes on from there)."
        ),
        epilog="Example: legdsl tune creatures/hopper.leg --controller hop --param "
        "k_speed=0.02:0.2 --param kp=50:300 --speeds 0.5,1,1.5 --time 10 --out tuned/hopper",
    )
    p.add_argument("file", metavar="FILE", help="a .leg file")
    p.add_argument("--creature", help="which creature, if the file has several")
    p.add_argument("--controller", required=True, metavar="NAME", help="the controller to tune")
    p.add_argument("--param", action="append", default=[], metavar="NAME=LO:HI",
                   help="a parameter and its bounds (units as in legdsl sweep; bare = SI)")  # fmt: skip
    p.add_argument("--speeds", required=True, metavar="V,V,...",
                   help="the commanded speeds every candidate runs at (m/s, or with a unit)")  # fmt: skip
    p.add_argument(
        "--table2", metavar="ROW", help="also approach this Table 2 row's animation column"
    )
    p.add_argument("--table2-weight", type=_weight, default=1.0, help="its weight (1)")
    p.add_argument("--energy-weight", type=_weight, default=0.0,
                   help="add this times the cost of transport, positive actuator work / (m g d) "
                   "(dimensionless; 0)")  # fmt: skip
    p.add_argument("--spread-weight", type=_weight, default=0.0,
                   help="add this times the running speed's stride-to-stride standard deviation "
                   "over the command (0)")  # fmt: skip
    p.add_argument("--pitch-weight", type=_weight, default=0.0,
                   help="add this times the trunk's pitch magnitude in radians: the mean over "
                   "the strides of each stride's peak-to-peak pitch (0)")  # fmt: skip
    p.add_argument("--time", default=10.0, help="simulated time per run (s, 10; or with a unit)")
    p.add_argument("--from", dest="t_from", default=3.0, help="measure from (s, 3; or with a unit)")
    p.add_argument("--generations", type=int, default=10, help="CMA-ES generations (10)")
    p.add_argument("--popsize", type=int, default=None, help="candidates per generation")
    p.add_argument("--seed", type=int, default=1, help="CMA-ES seed (1)")
    p.add_argument("--jobs", type=int, default=os.cpu_count() or 1, help="runs at once")
    p.add_argument("--out", required=True, metavar="DIR", help="where the results go")
    p.add_argument("--generated", default="generated", help="where generated modules live")
    p.add_argument("--dask", metavar="ADDRESS", default=None,
                   help="run on the Dask cluster at tcp://HOST:PORT, or 'local' for a LocalCluster "
                   "of --jobs workers (default: local processes)")  # fmt: skip
    return cmd_tune


def cmd_tune(args: argparse.Namespace) -> int:
    measured: list[bool] = []  # one once the file's own values are measured
    try:
        return _cmd_tune(args, measured)
    except (KeyboardInterrupt, Interrupted):
        if not measured:  # at any point before, however early (checking, compiling, forking)
            print("legdsl: tune: stopped before the file's own values were measured: nothing "
                  f"written to {args.out}", file=sys.stderr)  # fmt: skip
        raise


def _cmd_tune(args: argparse.Namespace, measured: list[bool]) -> int:
    source = Path(args.file)
    model = check_model(source, args.creature)
    require_controller(model, args.controller)
    controller = model.controller(args.controller)
    notes: list[str] = []  # said once every refusal has had its say
    bounds = _bounds(args, controller, source, actuator_settings(model), notes)
    _check_read(bounds, model, controller)
    speeds = _speeds(args.speeds, _speed_input(args.controller, controller, model).dim)
    _check_search(args, len(speeds), model)
    if args.table2 is not None:  # before --out is made: a row this creature cannot be measured as
        _table2_legs(args.table2, model, source)
    out = Path(args.out)
    if (out / source.name).resolve() == source.resolve():
        raise UsageError(
            f"--out {args.out}: the tuned {source.name} would replace {source} itself (and its "
            "own values with it); choose another --out"
        )
    check_output_dir(out, "--out", args.out)  # a folder for the tuned file, tune.json, tune.png
    made = not out.exists()  # removed again if the tune is stopped before it writes anything
    out.mkdir(parents=True, exist_ok=True)
    first = not (out / ".tune.lock").exists()  # a folder of the user's own, say
    lock = writer_lock(out, "tune")  # held until it is done (two would share one journal)
    try:
        try:
            journal, objective = _journal_for(out, args, source, model, controller, bounds,
                                              speeds)  # fmt: skip
        except UsageError:  # refused: the folder left as it was, without a lock file of its own
            if first:
                Path(lock.name).unlink(missing_ok=True)
            raise
        for note in notes:  # every refusal has had its say: they are of the tune that runs
            print(note, file=sys.stderr)
        return _tune_into(out, made, lock, args, source, model, controller, bounds, journal,
                          objective, measured)  # fmt: skip
    finally:  # an API caller may tune into the same --out again in this process
        release(lock, out, made)


def _journal_for(
    out: Path,
    args: argparse.Namespace,
    source: Path,
    model: Model,
    controller: Controller,
    bounds: list[Bound],
    speeds: tuple[float, ...],
) -> tuple[Journal, Objective]:
    """The tune's objective and its journal in ``out`` (its lock held), or a ``UsageError``
    where the tune would replace what it must not: another tune's results, generations of
    this one past ``--generations``, a ``.leg`` file no run of this tune wrote."""
    objective = Objective(
        speeds,
        args.time,
        args.t_from,
        args.table2,
        args.table2_weight,
        args.energy_weight,
        args.spread_weight,
        args.pitch_weight,
    )
    plan = {"creature": creature_fingerprint(model),
            "controller": controller_fingerprint(model, controller), "bounds": bounds,
            "objective": objective, "popsize": args.popsize, "seed": args.seed}  # fmt: skip
    journal = Journal.open(out, json.loads(json.dumps(plan, default=asdict)))
    if journal.another:  # its files are another tune's results: not replaced, unsaid
        raise UsageError(
            f"{out} holds another tune ({journal.path.name} is {journal.another}); choose "
            "another --out or remove it"
        )
    if len(journal.generations) > args.generations:  # its later ones would be lost, unsaid
        done = len(journal.generations)
        raise UsageError(
            f"--generations {args.generations}: {journal.path} holds {done} generations of this "
            f"tune (the files in {out} are of them), and a tune of fewer would replace its "
            f"results with those of generation {args.generations}; give --generations {done} "
            f"or more to keep them (the same command again runs no candidate), or another "
            f"--out to tune {args.generations} afresh"
        )
    tuned = out / source.name
    if why := journal.replaces(tuned):  # a user's own file, or their edits of the tuned one
        raise UsageError(
            f"--out {args.out}: {tuned} {why}, and the tuned {source.name} would replace it; "
            f"choose another --out or remove {tuned}"
        )
    return journal, objective


def _tune_into(
    out: Path,
    made: bool,
    lock: IO[str],
    args: argparse.Namespace,
    source: Path,
    model: Model,
    controller: Controller,
    bounds: list[Bound],
    journal: Journal,
    objective: Objective,
    measured: list[bool],
) -> int:
    """The tune, its lock held and ``out`` found fit (``_journal_for``): the search, the three
    files, the report (``measured`` told once the search has measured the file's own values)."""
    params = {c.name: c for c in controller.params}
    units = units_of({b.name: params[b.name].dim for b in bounds})
    pairs = _table2_legs(args.table2, model, source) if args.table2 is not None else {}
    base = Job(index=0, source=str(source), creature=args.creature, controller=args.controller,
               values={}, units=units, fixed=(), duration=args.time, start=args.t_from,
               generated=args.generated, keep=None,
               groups=tuple(f"{n}={','.join(legs)}" for n, legs in pairs.items()))  # fmt: skip
    if journal.set_aside:  # the user may have meant to go on from it: say why not
        print(f"legdsl: note: not going on from {journal.path}: {journal.set_aside}; this tune "
              "starts afresh and replaces it", file=sys.stderr)  # fmt: skip
    from legdsl.api import load

    if (slow := python_backend_note()) is not None:  # the runs' own notice is not shown
        print(f"legdsl: note: {slow}", file=sys.stderr)
    load(source, args.creature, args.generated).session.control(args.controller)  # compile once
    with _Stops(out).installed() as stops:
        try:
            result = tune(
                base, bounds, objective, args.generations, args.popsize, args.seed, args.jobs,
                dask=args.dask, journal=journal,
            )  # fmt: skip
        except (KeyboardInterrupt, Interrupted):  # before the file's own values were measured
            lock.close()
            Path(lock.name).unlink(missing_ok=True)
            if made and not any(out.iterdir()):
                out.rmdir()
            raise  # cmd_tune says nothing was written
        measured.append(True)
        stops.searching = False  # from here on a signal waits for the three files
        tuned = write_tuned(source, controller, result["best"]["values"], out / source.name,
                            model.controllers)  # fmt: skip
        journal.written(tuned)  # the file the same tune run again may replace
        dump(result, out / "tune.json")
        not_drawn = drawn_if_room(  # what precedes it is whole: said, not lost in an error
            "draw the convergence plot",
            lambda: plot_history(result["history"], out / "tune.png", result["start"]["objective"]),
        )
    shown, factors = _file_units(source, controller, units)
    print(report(result, shown, bounds, factors))
    _say_between(result.get("between", []), _say_fell(result["best"]["runs"]))
    _say_longer(result, objective)
    _say_deaf(result["best"]["runs"])
    runs = len(objective.speeds) + sum(h["runs"] for h in result["history"])
    runs += len(result.get("between", [])) + len(result.get("longer", []))
    done = len(result["history"])
    generations = "1 generation" if done == 1 else f"{done} generations"
    kept = "" if result["ended"] == "finished" else f", the best of {generations} so far"
    plot = "" if not_drawn else f", {out / 'tune.png'}"
    print(f"{runs} runs; wrote {tuned}, {out / 'tune.json'}{plot}{kept}")
    if not_drawn:
        print(f"legdsl: tune: tune.png not drawn: {not_drawn}", file=sys.stderr)
    if result["ended"] == "interrupted":
        raise KeyboardInterrupt  # the command's status, now that its results are written
    if result["ended"] == "terminated":
        raise Interrupted(result.get("signal", "SIGTERM"))
    if stops.late:  # it came as the files were written, the tune done: they are whole
        print(f"legdsl: {stops.late[0]} came once the tune had finished; its files are whole",
              file=sys.stderr)  # fmt: skip
        if stops.late[0] == "SIGINT":
            raise KeyboardInterrupt
        raise Interrupted(stops.late[0])
    return 2 if not_drawn else 0  # 2 as for any out-of-memory line


class _Stops:
    """SIGINT and the ending signals (SIGTERM, SIGHUP...) for the length of a tune: the first
    while it searches (or runs between the tuned speeds) stops it, ``tune`` keeping the best so
    far; any other, and any once its files are being written, is noted and not obeyed until
    they are whole. Before, a signal as ``tune.json`` or ``tune.png`` was written ended the
    command with one of them, or both, missing; a second Ctrl-C as the workers were stopped
    lost the best so far."""

    def __init__(self, out: Path) -> None:
        self.out = out
        self.searching = True
        self.stopped = False
        self.late: list[str] = []  # the signals noted and not obeyed

    def __call__(self, signum: int, frame: Any) -> None:
        if self.searching and not self.stopped:
            self.stopped = True
            if signum == signal.SIGINT:
                raise KeyboardInterrupt
            raise Interrupted(signal.Signals(signum).name)
        self.late.append(signal.Signals(signum).name)
        print(f"legdsl: finishing {self.out}/ first; it takes a moment", file=sys.stderr,
              flush=True)  # fmt: skip

    @contextlib.contextmanager
    def installed(self) -> Iterator[_Stops]:
        """Installed for SIGINT and each ending signal but one ignored when legdsl started
        (``nohup``), which stays ignored; not at all off the main thread."""
        with handled(STOPPING, self):
            yield self


def _say_between(rows: list[dict[str, Any]], tuned_fell: bool) -> None:
    if not rows:
        return
    print("running speed (m/s) between the tuned speeds (not scored)")
    for row in rows:
        pitch = tune_pitch(row)
        print(f"  at {row['speed']:<6.4g}    {tune_speed(row):<20} pitch {pitch}"
              + ("" if pitch == "n/a" else " deg"))  # fmt: skip
    fell = [f"{row['speed']:.4g}" for row in rows if row["outcome"] != "ok"]
    if fell and not tuned_fell:  # where the tuned speeds fall too, more speeds would not help
        print(f"legdsl: note: the tuned values did not last at {', '.join(fell)} m/s, between "
              "the tuned speeds: add speeds there to --speeds and tune again", file=sys.stderr)  # fmt: skip


def _say_fell(rows: list[dict[str, Any]]) -> bool:
    """A note where the tuned values still fall at a tuned speed (a tune whose every candidate
    fell wrote its file and said only that the runs between the speeds fell); whether any did."""
    fell = [row for row in rows if row["outcome"] != "ok"]
    if fell:
        at = ", ".join(f"{float(row['speed']):g}" for row in fell)
        how = "; ".join(str(row["outcome"]) for row in fell)
        print(f"legdsl: note: the tuned values do not last at {at} m/s ({how}), nor does the "
              "tuned file: widen the --param bounds, tune other parameters or more "
              "--generations, or see how the creature fails with legdsl run",
              file=sys.stderr)  # fmt: skip
    return bool(fell)


def _say_longer(result: dict[str, Any], objective: Objective) -> None:
    """The tuned values' speeds over twice the tune's time, and a note where they moved."""
    rows = result.get("longer", [])
    if not rows:
        return
    twice, since = 2 * objective.duration, objective.start
    print(f"running speed (m/s) over {since:g} to {twice:g} s, twice the tune's time (not scored)")
    for row in rows:
        print(f"  at {row['speed']:<6.4g}    {tune_speed(row)}")
    moved = unsettled(result["best"]["runs"], rows, objective.speeds)
    if moved:  # one note for them all: the speeds, then what they ran each time
        at = ", ".join(f"{speed:g}" for speed, _, _ in moved)
        longer_at = {row["speed"]: row for row in rows}
        scored_at = dict(zip(objective.speeds, result["best"]["runs"], strict=True))
        where = len(moved) > 1  # each speed named where there are several
        longer = _and(_did(long, longer_at[speed], speed, where) for speed, _, long in moved)
        scored = _and(_ran(short, scored_at[speed], speed) for speed, short, _ in moved)
        print(f"legdsl: note: the tuned speed had not settled by --time {objective.duration:g} "
              f"at {at} m/s: over {since:g} to {twice:g} s it {longer}, against {scored} "
              f"scored over {since:g} to {objective.duration:g} s; tune with a longer --time "
              f"({twice:g})", file=sys.stderr)  # fmt: skip


def _and(parts: Iterator[str]) -> str:
    """``a``, ``a and b``, ``a, b and c``."""
    items = list(parts)
    return items[0] if len(items) == 1 else f"{', '.join(items[:-1])} and {items[-1]}"


def _did(speed: float, row: dict[str, Any], command: float, where: bool) -> str:
    """What a longer run did, to follow "it": "runs 1.482 (+48.2%)", "fell at 5.608 s", "has
    no whole stride", and with ``where``, "at 1 m/s" after it (it printed "it runs fell")."""
    at = f" at {command:g} m/s" if where else ""
    if math.isfinite(speed):
        return f"runs {_ran(speed, row, command)}{at}"
    outcome = str(row["outcome"])
    return f"has {NO_STRIDE}{at}" if outcome == "ok" else f"{outcome}{at}"


def _ran(speed: float, row: dict[str, Any], command: float = 0.0) -> str:
    """A run's speed, off a ``command`` by how much (as the report's speeds are, relative to
    it; none for 0): + faster than the command, - slower, whichever way it runs (-1.115 at -1
    said -11.5%, 11.5% too fast backwards, where 0.9611 at 1 said -3.9%, too slow), or why it
    has none: it fell or diverged, or lasted without a whole stride in the window (it was said
    to have fallen, and a scored one's speed was 'nan')."""
    if math.isfinite(speed):
        return f"{speed:.4g}" + (f" ({(speed - command) / command:+.1%})" if command else "")
    outcome = str(row["outcome"])
    return NO_STRIDE if outcome == "ok" else outcome.partition(" at ")[0]


def _say_deaf(rows: list[dict[str, Any]]) -> None:
    """A note where the runs at every commanded speed went alike: the gait does not follow the
    command (a random kangaroo variant ran 1.995 m/s at 3, 4 and 5 m/s, start and tuned), and
    the objective cannot tell the speeds apart."""
    speeds = {float(r["speed"]) for r in rows}
    ran = {(float(r["running_speed"]), r["outcome"], float(r["simulated"])) for r in rows}
    if len(speeds) > 1 and len(ran) == 1:
        speed, outcome, _ = ran.pop()
        how = f"at {speed:.4g} m/s" if math.isfinite(speed) else "alike"
        ended = "" if outcome == "ok" else f", {outcome}"
        print(f"legdsl: note: the tuned values ran {how}{ended} at every commanded speed "
              f"({', '.join(f'{s:g}' for s in sorted(speeds))} m/s): the gait does not follow "
              "the command (a limit it reaches at every speed, or a state machine that stops "
              "cycling); no gain tuned against the speed error can tell them apart: compare "
              "legdsl run at two speeds", file=sys.stderr)  # fmt: skip


def _file_units(
    source: Path, controller: Controller, units: dict[str, str]
) -> tuple[dict[str, str], dict[str, float]]:
    """The unit each tuned parameter is reported in, the one the file (and the tuned file)
    writes it in, and its factor to SI: a tilt of ``0 deg`` was reported as ``0.02801 rad``
    while the tuned file wrote ``1.605 deg``; SI where the file writes a bare number."""
    shown, factors = dict(units), {}
    for name in units:
        unit = written_unit(source, controller, name)
        if unit and unit != units[name]:
            with contextlib.suppress(UnitError):  # one the file's checker read: it reads
                factors[name], shown[name] = parse_unit(unit)[0], unit
    return shown, factors
