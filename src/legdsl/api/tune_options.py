"""The options of ``legdsl tune`` checked before it searches: the ``--param`` bounds, the
``--speeds``, the ``--table2`` row, the weights, times and CMA-ES's options."""

from __future__ import annotations

import argparse
import contextlib
import math
import sys
from pathlib import Path
from typing import Any

from legdsl.analysis.results import MetricsError
from legdsl.analysis.table2 import virtual_legs
from legdsl.api.sweep import seconds, units_of
from legdsl.api.sweep_axes import MAX_RUNS, PointedError, bare_in_si, in_usual_unit, parse_axis
from legdsl.api.tune import Bound
from legdsl.api.tuned_file import declared_in, shared_owners, used_owners, written_unit
from legdsl.api.workers import dask_address
from legdsl.check.values import did_you_mean
from legdsl.ir.controller import Constant, Controller
from legdsl.ir.model import Model
from legdsl.lang.errors import UsageError
from legdsl.lang.units import KINDS, Dim, describe
from legdsl.pipeline.settings import plain_number

MAX_POPSIZE = 10_000  # candidates of a generation: its runs are held and ranked at once
MAX_GENERATIONS = 100_000  # each is kept, in tune.json and the journal


def _bounds(
    args: argparse.Namespace,
    controller: Controller,
    source: Path,
    settings: dict[str, Any],
    notes: list[str] | None = None,
) -> list[Bound]:
    """``--param NAME=LO:HI`` of each parameter to tune: a parameter the controller declares
    in ``source`` itself, given once, its file value within the bounds. Its notes go to
    ``notes``, to be said after any refusal (else to standard error at once)."""
    say = notes.append if notes is not None else lambda line: print(line, file=sys.stderr)
    params = {c.name: c for c in controller.params}
    if not args.param:
        raise UsageError("tune: name the parameters to tune with --param NAME=LO:HI")
    if not params:
        raise UsageError(
            f"tune: controller '{args.controller}' has no parameters to tune; declare them in "
            "it (param NAME = VALUE UNIT) or tune another controller"
        )
    bounds: list[Bound] = []
    for text in args.param:
        name = text.partition("=")[0].strip()
        if name in {c.name for c in controller.inputs}:
            raise UsageError(
                f"--param {text}: {name} is an input of '{args.controller}', not a parameter; "
                "tune its parameters (commanded speeds are --speeds)"
            )
        if "=" in text and name in settings and name not in params:  # knee_spring.k: swept
            raise UsageError(
                f"--param {name}: an actuator's setting, which a tune cannot write into the "
                "tuned file (it changes the controller's parameters); sweep it with 'legdsl "
                "sweep --grid', or declare a param the controller sets it from and tune that"
            )
        if "=" in text and name not in params:  # the list: those the tuned file can change
            raise UsageError(
                f"--param {name}: not a parameter of the controller{did_you_mean(name, params)} "
                f"(it has {', '.join(params)})"
            )
        axis = parse_axis("param", text, {n: c.dim for n, c in params.items()})
        first = next((t for t in args.param if t.partition("=")[0].strip() == axis.name), text)
        if any(b.name == axis.name for b in bounds):  # named, the caret under the second
            lead = len(text) - len(text.lstrip())
            raise PointedError(
                f"{axis.name}'s bounds are given twice (--param {first} before it); give each "
                "parameter's bounds once", "--param", text, lead, len(axis.name),
            )  # fmt: skip
        low, high = axis.values
        start = params[axis.name].value
        if not low <= start <= high:
            unit = units_of({axis.name: params[axis.name].dim})[axis.name]  # the bounds' SI unit
            unit = f" {unit}" if unit else ""  # a plain number's: no space before nothing
            written = written_unit(source, controller, axis.name)  # the file's own ("cm")
            lo_text, _, hi_text = text.partition("=")[2].partition(":")
            at = text.index("=") + 1 + (len(lo_text) + 1 if start > high else 0)
            bound = hi_text if start > high else lo_text  # the caret under the bound to widen
            raise PointedError(
                f"the file's value {start:g}{unit} is outside the bounds ({low:g} to "
                f"{high:g}{unit}); widen them"
                + _unit_note(text, axis.name, params[axis.name].dim, written, start),
                "--param", text, at + len(bound) - len(bound.lstrip()), len(bound.strip()),
            )  # fmt: skip
        # bare numbers are SI, as a sweep's: an angle's are radians (lean=-5:5 searched
        # ±286° of a 2 deg lean, unsaid), and the note is the sweep's, where it helps
        bare = _unit_note(text, axis.name, params[axis.name].dim,
                          written_unit(source, controller, axis.name), start)  # fmt: skip
        if bare:
            say(f"legdsl: note: --param {text}: {bare.removeprefix('; ')}")
        bounds.append(Bound(axis.name, low, high, start))
    spans = declared_in(source, controller, [b.name for b in bounds])  # not after the tune
    for name, part in shared_owners(source, spans).items():
        say(f"legdsl: note: {name} is declared in shared part '{part}': the tuned file "
            f"changes it for every controller that includes '{part}'")  # fmt: skip
    for name, used in used_owners(source, spans).items():
        say(f"legdsl: note: {name} is declared in {used}: the tuned file overrides it in "
            f"controller '{controller.name}' and leaves {used} as it is")  # fmt: skip
    return bounds


def _unit_note(text: str, name: str, dim: Dim, written: str | None, value: float) -> str:
    """The sweep's note that bare numbers are SI (``bare_in_si``), where it helps: where the
    range in the file's unit (or the usual one) fits the file's ``value`` better than the bare
    range. It was said of every bare range, and its advice was wrong where the bare range was
    right: stroke=0.01:0.08 m, 3 cm in the file, 'write stroke=0.01cm:0.08cm', which was then
    refused for leaving the file's value out. Said where the bare range leaves the value out
    and the other holds it, or both hold it and the other is nearer its size (lean=-5:5 rad of
    a 2 deg lean), or the value is 0 (nothing to tell them apart by)."""
    note, usual = bare_in_si(text, name, dim, written), in_usual_unit(text, name, dim, written)
    if usual is None:
        return ""
    try:
        other = parse_axis("param", usual[1], {name: dim}).values
    except UsageError:  # a unit the note writes that cannot be read back: say it as it was
        return note
    low, high = parse_axis("param", text, {name: dim}).values
    bare_holds, other_holds = low <= value <= high, other[0] <= value <= other[1]
    if not other_holds or value == 0:
        return note if other_holds else ""

    def off(bounds: tuple[float, ...]) -> float:  # how far the bounds' size is from the value's
        return abs(math.log(max(abs(bounds[0]), abs(bounds[1])) / abs(value)))

    return note if not bare_holds or off(other) < off((low, high)) else ""


def _check_read(bounds: list[Bound], model: Model, controller: Controller) -> None:
    """Refuses a parameter nothing in the compiled controller depends on: no event, record,
    actuator setting or foot placement of any state reads it (declared and left unused, or
    read only where it cancels out), so no value of it changes a run. A tune of one ended
    after its generations with "the candidates' objectives no longer differ", unexplained."""
    from legdsl.lower.control import lower_controller

    lowered = lower_controller(model, controller)
    exprs: list[Any] = list(lowered.events.values())
    for body in lowered.bodies.values():
        exprs += [value for _, value in body.records]
        exprs += [setting.value for setting in body.settings]
        exprs += [goal for place in body.places for goal in place.goals]
    read = {str(s) for e in exprs for s in getattr(e, "free_symbols", ())}
    unread = [b.name for b in bounds if f"param_{b.name}" not in read]
    if unread:
        names = " and ".join(", ".join(unread).rsplit(", ", 1))
        them = "them" if len(unread) > 1 else "it"
        others = [c.name for c in controller.params if f"param_{c.name}" in read]
        raise UsageError(
            f"--param {unread[0]}: controller '{controller.name}' never reads {names} (compiled, "
            f"no event, record, actuator setting or foot placement of its states depends on "
            f"{them}), so no value can change a run and the tune would find nothing; tune "
            f"parameters it reads ({', '.join(others) or 'it reads none'})"
        )


def _table2_legs(row: str, model: Model, source: Path) -> dict[str, list[str]]:
    """The virtual legs ``--table2 ROW`` is measured on, found from the creature's hips; a row
    whose pairs this creature has not (a trot's diagonal pairs of a one-legged creature) is
    refused, naming the rows that fit it (it was an internal error, its advice an option of
    ``legdsl metrics`` that tune lacks)."""
    from legdsl.analysis.table2 import TABLE2

    try:
        return virtual_legs(row, model)[0]
    except MetricsError as e:
        why = str(e).partition(": give")[0]  # what it has; not metrics' --group, tune has none
        fits = []
        for other in TABLE2:
            with contextlib.suppress(MetricsError):
                virtual_legs(other, model)
                fits.append(repr(other))
        raise UsageError(
            f"--table2 {row!r}: {why}, so '{model.name}' in {source} cannot be measured as "
            f"{row!r}; give a row that fits it ({', '.join(fits) or 'none does'}), or leave "
            "--table2 out"
        ) from None


def _speed_input(name: str, controller: Controller, model: Model | None = None) -> Constant:
    """The controller's input ``speed``, a running speed: the objective is its error. Without
    one, the refusal says what to do (it named the lack alone): rename an input in m/s, declare
    one, or tune another controller of the ``model`` that has one."""
    speed = next((c for c in controller.inputs if c.name == "speed"), None)
    if speed is None:
        raise UsageError(
            f"tune: controller '{name}' has no input 'speed' to command (the objective is the "
            f"running speed's error from it); {_how_to_command(controller, model)}"
        )
    if speed.dim != KINDS["velocity"][0]:
        raise UsageError(
            f"tune: the input 'speed' of controller '{name}' is {describe(speed.dim)}, not a "
            "running speed (m/s), and the objective is the running speed's error; tune a "
            "controller whose speed is in m/s"
        )
    return speed


def _how_to_command(controller: Controller, model: Model | None) -> str:
    """What to do for a controller without an input ``speed``."""
    velocity = KINDS["velocity"][0]
    named = [c.name for c in controller.inputs if c.dim == velocity]
    if named:  # vel, v_des...: the tune commands 'speed' by name
        fix = f"rename its input '{named[0]}' (a speed in m/s) to 'speed'"
    else:
        fix = ("declare one in it, 'input speed = 1 m/s', and steer its gait by it (as "
               "creatures/hopper.leg's hop does)")  # fmt: skip
    others = [c.name for c in (model.controllers if model is not None else ())
              if any(i.name == "speed" and i.dim == velocity for i in c.inputs)]  # fmt: skip
    if others:
        fix += f", or tune a controller of the file that has one ({', '.join(others)})"
    return fix


def _check_search(args: argparse.Namespace, speeds: int = 1, model: Model | None = None) -> None:
    """The objective's weights, the runs' times and CMA-ES's options (``args.time`` and
    ``args.t_from`` become seconds); ``speeds`` is how many runs a candidate has, ``model``
    the creature whose step the runs take."""
    from legdsl.analysis.table2 import TABLE2

    dask_address(args.dask)
    if args.table2 is not None and args.table2 not in TABLE2:
        raise UsageError(f"--table2 {args.table2!r}: Table 2 has {', '.join(map(repr, TABLE2))}")
    for flag, weight in (("--energy-weight", args.energy_weight),
                         ("--table2-weight", args.table2_weight),
                         ("--spread-weight", args.spread_weight),
                         ("--pitch-weight", args.pitch_weight)):  # fmt: skip
        if not (math.isfinite(weight) and weight >= 0):
            raise UsageError(f"{flag} {weight:g}: give a weight of 0 or more")
    time_text = str(args.time)  # as written, for the caret
    args.time = seconds("--time", args.time)
    args.t_from = seconds("--from", args.t_from, "nonnegative")
    for flag, value in (("--generations", args.generations), ("--jobs", args.jobs)):
        if value < 1:  # which one ('--generations, --jobs and --time must be positive')
            raise UsageError(f"{flag} {value}: must be more than zero; give 1 or more")
    if not args.t_from < args.time:  # no speed measured: every candidate would score alike
        raise UsageError(
            f"tune: --from {args.t_from:g} is not a time within the runs (--time {args.time:g}), "
            "so no candidate's speed would be measured; give --from from 0 to before --time "
            "(seconds; --from is 3 unless given)"
        )
    if model is not None:
        _check_steps(args.time, time_text, model)
    if not 1 <= args.seed < 2**32:  # cma reads 0 as "from the clock", numpy no other
        raise UsageError(
            f"--seed {args.seed}: give a whole number from 1 to {2**32 - 1} (CMA-ES would take "
            "0 as a seed from the clock, and the tune could not be repeated or resumed)"
        )
    if args.popsize is not None and args.popsize < 2:  # CMA-ES ranks candidates
        raise UsageError(
            f"--popsize {args.popsize}: CMA-ES needs at least 2 candidates per generation; "
            "give --popsize 2 or more (or leave it out for CMA-ES's own)"
        )
    _at_most(args, speeds)


def _check_steps(time: float, text: str, model: Model) -> None:
    """``--time`` against the creature's step, in tune's words (it was told in the Python
    API's, 'run_many(): runs[0]: time=1e+300 is ... give time=3.6e+12 or less, or a longer step
    (dt=, ...)', an option tune lacks): a run shorter than one step, or of more steps than a
    run can count (the closing runs last twice --time)."""
    from legdsl.lang.scaling import MOST_STEPS
    from legdsl.pipeline.options import check_run_options
    from legdsl.pipeline.scaled import run_options
    from legdsl.sim.stability import below

    options = run_options(model, duration=time)
    dt, own = options.dt, model.simulation.dt is not None
    step = f"dt {dt:g} s, " + ("the file's simulation block's" if own else "the runner's default")
    if dt > time:
        raise PointedError(
            f"a run shorter than one step ({step}); give --time {dt:g} or more, or a shorter "
            "dt in the file's simulation block (a tune has no --dt)", "--time", text, 0, len(text),
        )  # fmt: skip
    if 2 * time / dt > MOST_STEPS:
        raise PointedError(
            f"the closing runs, twice --time, would be {2 * time / dt:.3g} steps ({step}), more "
            f"than a run can count ({MOST_STEPS:.3g}); give --time {below(MOST_STEPS * dt / 2)} "
            "or less, or a longer dt in the file's simulation block (a tune has no --dt)",
            "--time", text, 0, len(text),
        )  # fmt: skip
    try:
        check_run_options(options, flags=False)
    except UsageError as e:  # the rest are the file's, its simulation block checked
        raise UsageError(f"tune: {e}") from None


def _at_most(args: argparse.Namespace, speeds: int) -> None:
    """Refuses a search larger than a tune takes, naming the option: --popsize 100000000 was
    'out of memory: ... a shorter --time, fewer --jobs', --popsize 10000000 ran minutes
    without a line, --generations 1000000000 told 'about 122240633 s left'. A tune runs at
    most as many runs as a sweep (``MAX_RUNS``)."""
    for flag, value, most in (("--popsize", args.popsize, MAX_POPSIZE),
                              ("--generations", args.generations, MAX_GENERATIONS)):  # fmt: skip
        if value is not None and value > most:
            own = " (or leave it out for CMA-ES's own, 4 + 3 ln(parameters))"
            raise UsageError(f"{flag} {value}: more than a tune takes ({most:,}); give {flag} "
                             f"{most} or fewer{own if flag == '--popsize' else ''}")  # fmt: skip
    n = len(args.param or ()) or 1
    popsize = args.popsize if args.popsize is not None else 4 + int(3 * math.log(n))
    runs = args.generations * popsize * speeds
    if runs > MAX_RUNS:
        raise UsageError(
            f"--generations {args.generations}: {args.generations:,} generations of {popsize} "
            f"candidates at {speeds} speed{'s' if speeds > 1 else ''} are {runs:,} runs, more "
            f"than a tune takes ({MAX_RUNS:,}); give fewer --generations or a smaller --popsize"
        )


def _speeds(text: str, dim: Dim) -> tuple[float, ...]:
    """``--speeds V,V,...`` in m/s: each a commanded speed (the speed error is relative to
    it; a 0's, in place, to the slowest other); a negative one commands running backwards."""
    try:
        speeds = parse_axis("grid", f"speed={text}", {"speed": dim}).values
    except PointedError as e:  # pointed into --grid speed=TEXT, the option it was written for
        why = e.why.replace("write speed=", "write ").replace("value once", "speed once")
        raise e.moved("--speeds", text, -len("speed="), why) from None
    except UsageError as e:  # it names --grid, the option it was written for
        why = str(e).partition(": ")[2]
        if "write NAME" in why:
            why = "write the speeds as V,V,... (m/s, or each with its unit: 2m/s,3m/s)"
        raise UsageError(f"--speeds {text}: {why}") from None
    if not any(speeds):
        raise UsageError(
            f"--speeds {text}: a speed of 0 has no relative speed error to tune against on its "
            "own (its drift is taken relative to the slowest other speed); add a speed other "
            "than 0 (m/s)"
        )
    twice = sorted({f"{v:g}" for v in speeds if speeds.count(v) > 1})
    if twice:  # it ran, scored and reported each twice
        raise UsageError(f"--speeds {text}: {', '.join(twice)} m/s is given more than once; "
                         "give each speed once")  # fmt: skip
    return speeds


def _weight(text: str) -> float:
    """A ``--...-weight`` as argparse reads it: a plain number (its range is checked with the
    other options', ``_check_search``); one with a unit is told what a weight is."""
    return plain_number(
        text, "a weight is a plain number (every term of the objective is dimensionless)"
    )
