"""``legdsl run``: its options (numbers with units), and a run that ends well whatever happens.

SIGTERM (and SIGHUP, SIGQUIT, SIGXCPU) ends a run as Ctrl-C does, and a second Ctrl-C waits until the run directory is
whole: what was recorded is always written.
"""

from __future__ import annotations

import argparse
import contextlib
import os
import signal
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import Any

from legdsl.cli.common import (
    EXIT_DIVERGED,
    EXIT_FELL,
    EXIT_INTERRUPTED,
    EXIT_TERMINATED,
    Command,
)
from legdsl.cli.process import ENDING_SIGNALS, exit_status, sigterm_unwinds
from legdsl.lang.errors import Diagnostic, Span, UsageError
from legdsl.signals import handled

_SIMULATION_OPTIONS: tuple[tuple[str, float | None, str | None, str], ...] = (
    ("--dt", 0.0004, None, "integration step in s, or with its unit: 0.4ms (default: the creature's simulation block, else 0.0004, the paper's)"),
    ("--control-dt", 0.002, None, "control interval in s, or with its unit: 2ms (default: the simulation block, else 0.002)"),
    ("--record-rate", 200.0, None, "samples per second to record, or 100Hz (default: the simulation block, else 200; 0 records every step)"),
    ("--drop", None, "H", "start with the lowest foot H metres above the ground (or 30cm)"),
    ("--fall-height", None, "Z", "the root below Z metres is a fall (default 30%% of its height over its feet at the start); off: none is (a creature that crawls or lies on the ground)"),
    ("--fall-tilt", 60.0, "DEG", "the root tilted beyond DEG degrees (or 1rad) is a fall (default 60); off: none is"),
)  # fmt: skip


class _Interrupts:
    """SIGINT and the ending signals (SIGTERM, SIGHUP...) for the length of a run: the first one while simulating ends the
    simulation (the run loop turns Ctrl-C's ``KeyboardInterrupt`` and SIGTERM's
    ``Interrupted`` into the status ``interrupted``); any other, until the run directory is
    whole, is noted and not obeyed. One handler from start to end, so that a second Ctrl-C
    sent a moment after the first cannot land between two handlers and lose the run."""

    def __init__(self, out: Path) -> None:
        self.out = out
        self.simulating = True
        self.started = False  # the simulation has started: a run stopped now is still written
        self.stopped = False  # the simulation was told to stop
        self.late: list[str] = []  # the signals noted and not obeyed

    def __call__(self, signum: int, frame: Any) -> None:
        from legdsl.sim.run_loop import Interrupted

        if self.simulating and not self.stopped:
            self.stopped = True
            if signum == signal.SIGINT:
                raise KeyboardInterrupt
            raise Interrupted(signal.Signals(signum).name)
        self.late.append(signal.Signals(signum).name)
        if not self.started:  # stopped while preparing (a compiler that hung): nothing to write
            return
        print(
            f"legdsl: finishing {self.out}/ first; it takes a moment", file=sys.stderr, flush=True
        )

    @contextlib.contextmanager
    def installed(self) -> Iterator[_Interrupts]:
        with handled((signal.SIGINT, *ENDING_SIGNALS), self):
            yield self


def cmd_run(args: argparse.Namespace) -> int:
    import math

    from legdsl.pipeline.options import (
        RUN_NUMERIC,
        check_drop,
        check_fall_tilt,
        check_output_dir,
        check_run_options,
        os_error,
        read_run_option,
        space_note,
    )
    from legdsl.pipeline.report import ProgressBar
    from legdsl.pipeline.scaled import check_scale, check_scaled_defaults, run_options
    from legdsl.pipeline.session import RunSession, check_file
    from legdsl.pipeline.settings import refuse_repeated

    values: dict[str, Any] = {}  # in SI, --fall-height off and --fall-tilt off as OFF_VALUES
    for field, (flag, _) in RUN_NUMERIC.items():
        given = getattr(args, flag[2:].replace("-", "_"))
        values[field] = read_run_option(field, flag, given) if isinstance(given, str) else given
    tilt = values.pop("fall_tilt")
    if not isinstance(args.fall_tilt, str):
        tilt = math.radians(tilt)  # the default, in degrees
    check_fall_tilt(tilt)  # the option alone: before anything is compiled
    check_scale(args.scale)  # so is --scale (--scale 0 was refused after compiling)
    if args.out:  # checked before anything is compiled or simulated
        check_output_dir(args.out, "--out")
    model, syntax = check_file(args.file, args.creature, args.scene, args.controller)
    if args.scale is not None and args.animate:  # its run.json names the unscaled creature
        raise UsageError(
            "--animate with --scale is not supported (the player draws the creature of the "
            f"file, not the scaled one): write the scaled file with 'legdsl scale {args.file} --by "
            f"{args.scale:g} -o OUT.leg' and run it with --animate"
        )
    # dt, control_dt and record_rate not given come from the creature's simulation block
    options = run_options(model, args.scale, integrator=args.integrator, fall_tilt=tilt, **values)
    controller, settings, switches = args.controller, list(args.set), list(args.switch)
    unreached: list[str] = []  # --set texts for gait bands the run never reaches
    repeated = None  # the note on a --controller that repeats the scene's
    refuse_repeated(settings)
    if args.scene is not None:  # the scene's lines first: the command line's options add to them
        from legdsl.pipeline.scenes import find_scene, scene_plan

        scene = find_scene(model, args.scene)
        if args.scale is not None:  # the scene as the scaled file has it, for the scaled creature
            from legdsl.pipeline.scaled import scale_scene

            scene = scale_scene(scene, model, args.scale)
        controller, settings, switches = scene_plan(scene, model, settings, switches, unreached)
        chosen = (" (its gait table's band for the first command)" if scene.starts_by_band
                  else " (its 'controller' line)" if scene.bands else "")  # fmt: skip
        if args.controller not in (None, controller):  # a gait table's start is its first band's
            raise UsageError(
                f"--scene {scene.name} starts with controller {controller}{chosen}; "
                "leave out --controller (or change the scene)"
            )
        if args.controller is not None:  # repeated: the scene still chooses the others
            repeated = _controller_repeated(scene.name, controller, chosen, switches)
        if args.scale is not None and switches:
            raise UsageError(
                f"--scene {scene.name} switches controllers, which --scale does not support: "
                f"write the scaled file with 'legdsl scale {args.file} --by {args.scale:g} -o "
                "OUT.leg' and run its scene"
            )
        if scene.duration is not None and not isinstance(args.time, str):
            options.duration = scene.duration
    check_scaled_defaults(options, args.scale, values)
    check_run_options(options)  # the options together, and --drop: before anything is compiled
    if options.drop is not None:
        check_drop(options.drop, model, args.scale)
    with sigterm_unwinds():  # a compile of stale modules, its controller processes stopped
        session = RunSession.from_checked(model, args.file, syntax, args.generated, sys.stderr)
    sources = {}
    if args.scene is not None:  # a note names the scene's lines as written
        from legdsl.pipeline.scenes import scene_sources

        sources = scene_sources(scene, model.scene(args.scene))  # as the file says it, unscaled
    out = check_output_dir(args.out or Path("runs") / model.name, "--out")
    progress = ProgressBar() if sys.stderr.isatty() else None
    backend = {"backend": args.backend} if args.backend else {}
    with _Interrupts(out).installed() as interrupts:
        plan = session.prepare(controller, settings, args.path, options, args.scale, switches,
                               sources=sources, **backend)  # fmt: skip
        # notes on a run it will make: a refused one is told its mistake alone (the notes
        # advised a longer --time for a run refused for another reason)
        session.tell_before(controller, settings, options, unreached, sources)
        for note in (repeated, space_note(out, "--out", options, model)):
            if note is not None:
                print(f"legdsl: note: {note}", file=sys.stderr)
        interrupts.started = True
        try:
            simulated = plan.sim.run(progress)
        finally:  # a run stopped short (a fall, Ctrl-C, an error): its bar's line ended first
            if progress is not None:
                progress.end()
        run = plan.finish(simulated)
        interrupts.simulating = False  # from here on a signal waits for the directory
        run.scene = args.scene
        _say_writing(run, out)
        try:
            out = run.write(out)
        except OSError as e:
            raise os_error("the run directory", out, e) from None
    print(run.summary())
    print(f"  written to {os.path.join(out, '')} (trajectory.npz, trajectory.csv, run.json)")
    session.tell_after(run)
    if args.animate:
        from legdsl.export.animate import animate_result

        animate_result(out, session.model, run.result, session.dynamics)
    result = run.result
    if result.status == "interrupted" or interrupts.late:
        print(f"legdsl: {result.message or 'interrupted'}; {out}/ is complete", file=sys.stderr)
        first = result.cause if result.status == "interrupted" else interrupts.late[0]
        return exit_status(first)
    if result.status == "diverged":
        print(f"legdsl: {result.message}{_quoted(result.fault_span)}", file=sys.stderr)
        return EXIT_DIVERGED
    if result.status == "fell":
        print(
            f"legdsl: the creature fell at t = {result.sim_time:.3f} s: {result.message}",
            file=sys.stderr,
        )
        return EXIT_FELL
    return 0


def _quoted(span: Span | None) -> str:
    """The line of a failed control law and a caret under it, as a mistake in the file is
    shown ('' where there is none, or its file cannot be read now)."""
    if span is None or span.line <= 0:
        return ""
    try:
        text = Path(span.file).read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError):
        return ""
    rendered = Diagnostic(span, "").render({span.file: text})
    return rendered[rendered.index("\n") :] if "\n" in rendered else ""


def _controller_repeated(scene: str, controller: str, chosen: str, switches: list[str]) -> str:
    """The note on ``--controller`` given with a ``--scene`` that starts with it: it only
    repeats the scene's choice (a gait table's still changes controllers: the run recorded
    'controller gallop' with the scene's run from 6 s, and nothing said so)."""
    said = f"--controller {controller} repeats the controller --scene {scene} starts with{chosen}"
    if not switches:
        return f"{said}; it may be left out"
    changes = ", ".join(f"{w.partition('=')[2]} at {w.partition('=')[0].removesuffix('s')} s"
                        for w in switches)  # fmt: skip
    return f"{said}; the scene still changes controllers ({changes}): --controller chooses only the first"


# What writing a run's files takes, measured (the CSV's text most of it): 10 to 18 MB/s, and
# twice the recording in memory (``legdsl.pipeline.options.ON_DISK``)
WRITTEN_PER_SECOND = 15e6
SAY_WRITING = 5.0  # s: a write this long is told before it starts (a 30 min run's: a minute)


def _say_writing(run: Any, out: Path) -> None:
    """A line before a long write: the bar had said "done" (or stopped at a Ctrl-C), and a
    30 min run's files then took a silent minute to write."""
    from legdsl.pipeline.options import ON_DISK

    tr = run.result.trajectory
    size = ON_DISK * len(tr) * tr.row_bytes()
    if size / WRITTEN_PER_SECOND >= SAY_WRITING:
        print(
            f"legdsl: writing {out}/ (about {size / 1e6:.0f} MB, "
            f"about {size / WRITTEN_PER_SECOND:.0f} s)",
            file=sys.stderr,
            flush=True,
        )


def add_run_parser(sub: Any) -> Command:
    r = sub.add_parser(
        "run",
        help="simulate a creature and record its motion",
        description="Compile the creature if its generated module is missing or stale, simulate it "
        "with its actuators and ground contact, and write trajectory.npz, trajectory.csv and run.json "
        "into the output directory. Exit status: 0 ok, 2 a mistake in the input, "
        f"{EXIT_DIVERGED} the simulation diverged, {EXIT_FELL} the creature fell, "
        f"{EXIT_INTERRUPTED} interrupted by Ctrl-C ({EXIT_TERMINATED} by SIGTERM, 128 + the "
        "signal's number by SIGHUP, SIGQUIT or SIGXCPU); the run "
        "directory is written in every case once the simulation starts, with what was recorded "
        "(a Ctrl-C during the compile leaves none).",
        epilog="Example: legdsl run creatures/quadruped.leg --time 3 --drop 0.3 --out runs/drop",
    )
    r.add_argument("file", metavar="FILE", help="a .leg file")
    r.add_argument(
        "--creature",
        help="which creature, if the file has several (not needed when only one has the "
        "--scene, or the --controller, asked for)",
    )
    r.add_argument("--controller", metavar="NAME", help="run this controller of the creature")
    r.add_argument(
        "--set",
        action="append",
        default=[],
        metavar="NAME=VALUE",
        help="set a controller input or parameter (speed=2.5m/s), change an input during the run "
        "(speed=5m/s@4s), set one controller's own (bound.k_speed=50ms, with --switch), or set "
        "an actuator input (hip_servo.setpoint=10deg); repeatable",
    )
    r.add_argument(
        "--scene",
        metavar="NAME",
        help="run the file's scene NAME (scene NAME { controller ...; set ...; at T switch ...; "
        "time T }); --set, --switch and --time given as well add to it or override it",
    )
    r.add_argument(
        "--switch",
        action="append",
        default=[],
        metavar="T=CONTROLLER",
        help="from time T on, drive the creature with another of its controllers (6s=gallop): it "
        "takes over at the next liftoff (into a flight, the body rising and turning slowly, within "
        "0.5 s if one comes; "
        "else any, within 1 s; for a creature standing 0.81 m, sqrt of its height ratio as long "
        "for others), in the state that matches the feet down, "
        "keeps the records whose names match (but those it declares 'own') and the commanded inputs, and "
        "--set NAME=V@T still applies (a command at T goes with the switch); repeatable",
    )
    r.add_argument(
        "--path",
        action="append",
        default=[],
        metavar="[NAME=]SHAPE",
        help="the path for the controller to follow, in place of the one its .leg file gives: "
        "a shape as written there ('circle(center = (0, 5) m, radius = 5 m, turn = left)', "
        "polyline(...), polygon(...), square(...)) or a file of waypoints, x,y in metres per line "
        "(waypoints.csv); NAME= picks one of several paths; repeatable",
    )
    r.add_argument(
        "--time",
        default=5.0,
        metavar="T",
        help="simulated time, a number of seconds or with its unit: 2s, 1min (default 5)",
    )
    r.add_argument("-o", "--out", metavar="DIR", help="output directory (default runs/CREATURE)")
    r.add_argument(
        "--integrator",
        choices=("euler", "rk4"),
        default="euler",
        help="semi-implicit Euler (default) or RK4",
    )
    r.add_argument(
        "--backend",
        choices=("python", "c", "auto"),
        default=None,
        help="take the steps in C, compiled from generated/NAME/*.c and cached, or in Python (the "
        "reference: bit-identical runs, tens of times slower); auto (the default, or "
        "$LEGDSL_BACKEND): C when a C compiler is found (docs/runtime.md)",
    )
    for flag, default, metavar, text in _SIMULATION_OPTIONS:
        r.add_argument(flag, default=default, metavar=metavar, help=text)
    # unless given, the creature's simulation block (if any) gives these (legdsl.pipeline.scaled)
    r.set_defaults(dt=None, control_dt=None, record_rate=None)
    r.add_argument(
        "--scale",
        type=_scale_factor,
        metavar="L",
        help="run as the creature scaled by L (Table 1 of Raibert & Hodgins 1991): the unscaled "
        "model with every input (--time, --dt, --control-dt, --record-rate, --set, --path, --drop) "
        "scaled by 1/L and its recorded outputs by L; the same as running the file 'legdsl scale' writes",
    )
    r.add_argument(
        "--generated",
        default="generated",
        metavar="DIR",
        help="where generated modules live (default generated/)",
    )
    r.add_argument(
        "--animate",
        action="store_true",
        help="also write the HTML player, DIR/animation.html (see legdsl animate)",
    )
    return cmd_run


def _scale_factor(text: str) -> float:  # imported when given: the parser is built at every start
    from legdsl.pipeline.scaled import scale_factor

    return scale_factor(text)
