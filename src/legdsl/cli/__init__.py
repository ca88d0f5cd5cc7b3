"""The ``legdsl`` command line.

User mistakes (``LegError``) are printed as ``file:line:col`` with the line and
a caret, and exit with status 2. Anything else is a bug in legdsl: it is
reported as such (with the traceback under ``--debug``) and exits with 70.
"""

from __future__ import annotations

import argparse
import contextlib
import sys
import traceback
from collections.abc import Sequence
from pathlib import Path
from typing import TextIO, cast

from legdsl import __version__
from legdsl.cli.common import (
    EXIT_INTERNAL,
    EXIT_USER_ERROR,
    Command,
    add_window,
    empty_argument,
    file_read_as_option,
    interrupted,
    negative_values_joined,
    options_with_a_value,
    os_refusal,
)
from legdsl.cli.metrics import add_metrics_parser
from legdsl.cli.outputs import cmd_export, cmd_plot
from legdsl.cli.parser import LegParser
from legdsl.cli.pointed import pointed
from legdsl.cli.process import (
    THREAD_REFUSED,
    QuietErrors,
    QuietWhenClosed,
    a_library_failed,
    cannot_import,
    current_directory_exists,
    exit_status,
    out_of_memory,
    run_held,
    streams_that_cannot_fail,
    term_unwinds,
)
from legdsl.cli.run import add_run_parser
from legdsl.lang.errors import LegError, UsageError, thread_refused

_COMMANDS: dict[str, Command] = {}


def _render(e: LegError) -> str:
    """The mistakes with their lines and carets, also those found after the check (an
    export's, a run's), which carry no source text: it is read from the file."""
    for d in e.diagnostics:
        name = d.span.file
        if d.span.line > 0 and name not in e.sources:
            with contextlib.suppress(OSError, UnicodeDecodeError):
                e.sources[name] = Path(name).read_text(encoding="utf-8-sig")
    return e.render()


def _cmd_check(args: argparse.Namespace) -> int:
    from legdsl.check.event_notes import never_entered
    from legdsl.check.leg_notes import leg_contact_notes
    from legdsl.pipeline.compile import check_lowered

    failed = False
    for path in args.files:
        try:
            models = check_lowered(path)
        except LegError as e:
            print(e.render(), file=sys.stderr)
            failed = True
            continue
        for m in models:
            ctl = (
                f", controllers: {', '.join(c.name for c in m.controllers)}"
                if m.controllers
                else ""
            )
            print(f"{path}: creature '{m.name}' is well-formed ({m.nv} DOF{ctl})")
            for note in [*leg_contact_notes(m), *never_entered(m)]:
                print(f"legdsl: note: {note}", file=sys.stderr)
    return EXIT_USER_ERROR if failed else 0


def _cmd_show(args: argparse.Namespace) -> int:
    from legdsl.check.event_notes import never_entered
    from legdsl.check.leg_notes import leg_contact_notes
    from legdsl.check.source import check_model
    from legdsl.ir.describe import describe_model

    if sys.stdout is None:  # its one product: said, not exit 0 with nothing shown
        raise UsageError("show prints the creature, and standard output is closed (>&-)")
    model = check_model(args.file, args.creature)
    print(describe_model(model), end="")
    for note in [*leg_contact_notes(model), *never_entered(model)]:
        print(f"legdsl: note: {note}", file=sys.stderr)
    return 0


def _cmd_compile(args: argparse.Namespace) -> int:
    import time
    from pathlib import Path

    from legdsl.pipeline.compile import (
        check_for_compile,
        compile_each,
        compile_jobs,
        refuse_same_names,
    )
    from legdsl.pipeline.generated import write_generated
    from legdsl.pipeline.report import CompileProgress

    if args.all == bool(args.files):
        print("legdsl compile: give .leg files or --all (not both)", file=sys.stderr)
        return EXIT_USER_ERROR
    files = sorted(Path("creatures").glob("*.leg")) if args.all else [Path(f) for f in args.files]
    if not files:
        print(
            "legdsl compile --all: no creatures/*.leg here; run it from the project root",
            file=sys.stderr,
        )
        return EXIT_USER_ERROR

    from legdsl.pipeline.options import check_output_dir, os_error

    check_output_dir(args.out, "--out")
    compile_jobs()  # a wrong $LEGDSL_COMPILE_JOBS is refused before any work

    shown = CompileProgress()
    progress = shown.line
    failed = False
    checked = []
    given: dict[Path, Path] = {}  # a file given twice (by two paths, say) is compiled once
    for path in files:
        given.setdefault(path.resolve(), path)
    for path in given.values():
        try:
            checked.append(check_for_compile(path, progress))
        except LegError as e:
            print(e.render(), file=sys.stderr)
            failed = True
    refuse_same_names(checked, args.out)  # before anything is written
    for file in checked:
        start = time.perf_counter()
        try:
            compiled = list(compile_each(file, progress, shown.done))
        except LegError as e:
            print(e.render(), file=sys.stderr)
            failed = True
            continue
        for c in compiled:
            try:
                where = write_generated(c, args.out)
            except OSError as e:
                raise os_error("the generated modules of", Path(args.out) / c.name, e) from None
            progress(f"{c.name}: wrote {where}/ ({time.perf_counter() - start:.2f} s in all)")
    return EXIT_USER_ERROR if failed else 0


def _parser() -> argparse.ArgumentParser:
    p = LegParser(
        prog="legdsl",
        description="Compile and run physically simulated legged creatures described in .leg files.",
        epilog="Example: legdsl check creatures/kangaroo.leg && legdsl show creatures/kangaroo.leg",
    )
    p.add_argument("--version", action="version", version=f"legdsl {__version__}")
    p.add_argument(
        "--debug", action="store_true", help="show Python tracebacks for internal errors"
    )
    sub = p.add_subparsers(dest="command", metavar="COMMAND", required=True)

    c = sub.add_parser(
        "check",
        help="check .leg files and report every mistake",
        description="Parse and check .leg files; every mistake is reported as file:line:col "
        "with the line and a caret. Exit status 0 when all files are well-formed, 2 otherwise.",
        epilog="Example: legdsl check creatures/*.leg",
    )
    c.add_argument("files", nargs="+", metavar="FILE", help=".leg files to check")
    _COMMANDS["check"] = _cmd_check

    s = sub.add_parser(
        "show",
        help="print a creature's link tree, degrees of freedom, legs and contacts",
        description="Print the link tree of a creature as an indented tree with each joint's "
        "type and coordinates, the total DOF and mass, its legs, contacts, actuators and controllers.",
        epilog="Example: legdsl show creatures/kangaroo.leg",
    )
    s.add_argument("file", metavar="FILE", help="a .leg file")
    s.add_argument("--creature", help="which creature, if the file has several")
    _COMMANDS["show"] = _cmd_show

    _COMMANDS["run"] = add_run_parser(sub)

    _COMMANDS["metrics"] = add_metrics_parser(sub)

    k = sub.add_parser(
        "compile",
        help="generate the equations of motion and the controllers of creatures as Python and C",
        description="Lower each creature and its controllers through sympy and write "
        "generated/NAME/ (dynamics.py and .c, control_CONTROLLER.py and .c), replacing the "
        "directory only once the new one is complete. Progress goes to stderr. --all "
        "compiles creatures/*.leg and is the command that updates the golden files.",
        epilog="Example: legdsl compile creatures/kangaroo.leg  (or: legdsl compile --all)",
    )
    k.add_argument("files", nargs="*", metavar="FILE", help=".leg files to compile")
    k.add_argument("--all", action="store_true", help="compile every creatures/*.leg")
    k.add_argument(
        "-o",
        "--out",
        "--generated",
        dest="out",
        default="generated",
        metavar="DIR",
        help="the directory to write NAME/ under (default: generated); -o and --generated are "
        "the same option, --generated named as in run, animate and the other commands that "
        "read the modules",
    )
    _COMMANDS["compile"] = _cmd_compile

    pl = sub.add_parser(
        "plot",
        help="draw a run like Figure 6 of the paper (PNG)",
        description="Draw the centre of mass's height, the body's pitch, the centre of mass's "
        "forward speed against its command and the joint angles of the first leg over time "
        "(a root welded to the world cannot pitch: its panel says so), with every stance phase "
        "of that leg between dashed lines (Figure 6 of Raibert & Hodgins 1991). Writes "
        "DIR/figure6.png by default.",
        epilog="Example: legdsl plot runs/kangaroo --from 3 --to 4",
    )
    pl.add_argument("dir", metavar="DIR", help="a run directory (legdsl run --out DIR)")
    pl.add_argument("-o", "--output", metavar="FILE.png", help="where to write the picture")
    add_window(pl)
    pl.add_argument(
        "--top",
        action="store_true",
        help="also draw a top view (top.png: the centre of mass's track); "
        "it is drawn anyway, with the path, for a run that followed a path",
    )
    _COMMANDS["plot"] = cmd_plot

    from legdsl.export.animate import add_animate_parser, add_export_motion_parser
    from legdsl.export.replay_cli import add_replay_parser

    _COMMANDS["animate"] = add_animate_parser(sub)
    _COMMANDS["export-motion"] = add_export_motion_parser(sub)
    _COMMANDS["replay"] = add_replay_parser(sub)
    from legdsl.api.sweep_cli import add_sweep_parser

    _COMMANDS["sweep"] = add_sweep_parser(sub)
    from legdsl.api.tune_cli import add_tune_parser

    _COMMANDS["tune"] = add_tune_parser(sub)

    e = sub.add_parser(
        "export",
        help="write a creature as MJCF (MuJoCo) or URDF",
        description="Write the creature's link tree, masses, inertias, joints (named as the "
        "legdsl coordinates), shapes and contact points as MJCF or URDF. The file is written "
        "whole or not at all (a temporary file is renamed over the target).",
        epilog="Example: legdsl export creatures/kangaroo.leg --format mjcf -o kangaroo.xml "
        "&& python -m mujoco.viewer --mjcf kangaroo.xml",
    )
    e.add_argument("file", metavar="FILE", help="a .leg file")
    e.add_argument(
        "--format",
        choices=("mjcf", "urdf"),
        help="MJCF (MuJoCo XML) or URDF (default: as -o's name says: .xml or .mjcf is MJCF, "
        ".urdf is URDF)",
    )
    e.add_argument(
        "-o",
        "--output",
        metavar="OUT",
        help="output file (default: NAME.xml or NAME.urdf here; '-' for standard output)",
    )
    e.add_argument("--creature", help="which creature, if the file has several")
    e.add_argument(
        "--base",
        choices=("world", "free"),
        default="world",
        help="URDF: 'free' makes a 3D free root the root link (a floating base as ROS tools and "
        "Pinocchio expect) instead of a 'floating' joint from a 'world' link (the default)",
    )
    e.add_argument(
        "--link-mass",
        metavar="MASS",
        help="URDF: give the intermediate links of composite joints this mass (e.g. 0.001g; a bare "
        "number is kg), for loaders that refuse moving massless links (MuJoCo's); default 0",
    )
    e.add_argument(
        "--anchor-pads",
        action=argparse.BooleanOptionalAction,
        default=None,
        help="MJCF: hold each contact on a small pad body on tangent slides, which carries the "
        "ground's tangential spring (the default); --no-anchor-pads writes exactly the model's "
        "link tree, for comparing dynamics (docs/export.md)",
    )
    _COMMANDS["export"] = cmd_export

    from legdsl.pipeline.scale_cli import add_scale_parser

    _COMMANDS["scale"] = add_scale_parser(sub)

    return p


def main(argv: Sequence[str] | None = None, process_ends: bool = False) -> int:
    streams_that_cannot_fail()
    if not current_directory_exists():
        print(
            "legdsl: the current directory was deleted while you were in it: "
            "cd to one that exists and run again",
            file=sys.stderr,
        )
        return EXIT_USER_ERROR
    stdout, stderr = sys.stdout, sys.stderr
    if stdout is None:  # started with standard output closed: print() writes nothing
        return _main(argv, process_ends)
    quiet = QuietWhenClosed(stdout)
    sys.stdout = cast(TextIO, quiet)
    if stderr is not None:
        sys.stderr = cast(TextIO, QuietErrors(stderr))
    try:
        try:
            status = _main(argv, process_ends)
        finally:  # --help's SystemExit too
            quiet.flush()  # here, not at exit, where a reader gone is exit status 120
    except OSError as e:  # standard output refused what was left of it (> /dev/full)
        print(f"legdsl: {os_refusal(e)}", file=sys.stderr)
        return EXIT_USER_ERROR
    finally:
        sys.stdout, sys.stderr = stdout, stderr
    return status


def _short_of_memory(e: MemoryError | ImportError | SystemError, command: str = "") -> str:
    """What a process short of memory is told: a library that could not be loaded (or a Python
    without it), the import machinery failing, an allocation refused (before any work: no
    shorter --time helps)."""
    if isinstance(e, ImportError):
        return cannot_import(e)
    if isinstance(e, SystemError):
        return a_library_failed(e)
    return out_of_memory(command)


def _tune_stopped_loading(argv: Sequence[str]) -> None:
    """A tune stopped as the commands' modules load (its first second or so) says, as one
    stopped later before its first runs does, that it wrote nothing (it said only "legdsl:
    interrupted", and the user could not tell what was kept)."""
    words = [w for w in argv if w != "--debug"]
    out = next((w.partition("=")[2] for w in words if w.startswith("--out=")), None)
    if out is None and "--out" in words[:-1]:
        out = words[words.index("--out") + 1]
    if words[:1] == ["tune"] and out:
        print("legdsl: tune: stopped before the file's own values were measured: nothing "
              f"written to {out}", file=sys.stderr)  # fmt: skip


def _main(argv: Sequence[str] | None, process_ends: bool) -> int:
    try:  # the parsers import their commands' modules: a Ctrl-C may come meanwhile
        from legdsl.sim.run_loop import Interrupted

        parser = _parser()
        given = negative_values_joined(sys.argv[1:] if argv is None else argv, parser)
        if "--debug" in given[1:]:  # the whole program's flag, taken after the command too
            given = ["--debug", *(w for w in given if w != "--debug")]
        if mistake := empty_argument(given, parser) or file_read_as_option(given):
            print(f"legdsl: {mistake}", file=sys.stderr)
            return EXIT_USER_ERROR
        args = parser.parse_args(given)
    except KeyboardInterrupt:
        _tune_stopped_loading(sys.argv[1:] if argv is None else argv)
        return interrupted(process_ends)
    except (MemoryError, ImportError, SystemError) as e:  # a memory limit (ulimit -v) too low
        print(f"legdsl: {_short_of_memory(e)}", file=sys.stderr)  # to load numpy and sympy,
        return EXIT_USER_ERROR  # or a Python without legdsl's dependencies
    try:
        if args.command in ("animate", "export-motion"):  # their outputs, checked first
            from legdsl.pipeline.options import check_output_file, not_an_input

            run = [Path(args.run) / n for n in ("trajectory.npz", "trajectory.csv", "run.json")]
            for flag, value in (("-o", args.output), ("--video", getattr(args, "video", None))):
                if value:
                    check_output_file(value, flag)
                    not_an_input(value, flag, run + ([Path(args.source)] if args.source else []))
        with term_unwinds(args.command), run_held(args):  # a run it draws from held still
            return _COMMANDS[args.command](args)
    except LegError as e:
        print(_render(e), file=sys.stderr)
        return EXIT_USER_ERROR
    except UsageError as e:  # a quantity's mistake with a caret under its fault
        said = pointed(str(e), given, options_with_a_value(parser, short=True))
        print(f"legdsl: {said}", file=sys.stderr)
        return EXIT_USER_ERROR
    except KeyboardInterrupt:
        return interrupted(process_ends)
    except Interrupted as e:
        print(f"legdsl: terminated ({e.signal})", file=sys.stderr)
        return exit_status(e.signal)
    except (MemoryError, ImportError, SystemError) as e:  # ImportError: a library loaded late
        if args.debug:  # (matplotlib for a plot) that could not be mapped under ulimit -v
            traceback.print_exc()
        print(f"legdsl: {_short_of_memory(e, args.command)}", file=sys.stderr)
        return EXIT_USER_ERROR
    except OSError as e:  # the file system refused: a path or permission of the user's
        if args.debug:
            traceback.print_exc()
        print(f"legdsl: {os_refusal(e, args.command)}", file=sys.stderr)
        if isinstance(sys.stdout, QuietWhenClosed):  # > /dev/full: told here, once
            sys.stdout.told(e)
        return EXIT_USER_ERROR
    except RecursionError:  # the parser refuses deep nesting; this is the net beneath it
        if args.debug:
            traceback.print_exc()
        print(
            "legdsl: an expression in the input, with the lets and signals it uses written "
            "out, is nested too deeply to be handled; compute it in fewer steps",
            file=sys.stderr,
        )
        return EXIT_USER_ERROR
    except Exception as e:  # a bug in legdsl, not in the user's file
        if args.debug:
            traceback.print_exc()
        elif thread_refused(e):  # batched runs' threads, under ulimit -v or ulimit -u
            print(f"legdsl: {THREAD_REFUSED}", file=sys.stderr)
            return EXIT_USER_ERROR
        else:
            print(
                f"legdsl: internal error ({type(e).__name__}: {e}); this is a bug in legdsl, "
                "not in your file. Run again with --debug for the traceback.",
                file=sys.stderr,
            )
        return EXIT_INTERNAL


if __name__ == "__main__":
    sys.exit(main())
