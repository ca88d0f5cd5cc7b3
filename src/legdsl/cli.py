"""The ``legdsl`` command line.

User mistakes (``LegError``) are printed as ``file:line:col`` with the line and
a caret, and exit with status 2. Anything else is a bug in legdsl: it is
reported as such (with the traceback under ``--debug``) and exits with 70.
"""

from __future__ import annotations

import argparse
import sys
import traceback
from collections.abc import Callable, Sequence

from . import __version__
from .errors import LegError

EXIT_USER_ERROR = 2
EXIT_INTERNAL = 70

Command = Callable[[argparse.Namespace], int]
_COMMANDS: dict[str, Command] = {}


def _cmd_check(args: argparse.Namespace) -> int:
    from .checker import check_file

    failed = False
    for path in args.files:
        try:
            models = check_file(path)
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
    return EXIT_USER_ERROR if failed else 0


def _cmd_show(args: argparse.Namespace) -> int:
    from .checker import check_model
    from .describe import describe_model

    print(describe_model(check_model(args.file, args.creature)), end="")
    return 0


def _cmd_compile(args: argparse.Namespace) -> int:
    import time
    from pathlib import Path

    from .driver import compile_file, write_generated

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

    def progress(message: str) -> None:
        print(f"legdsl: {message}", file=sys.stderr, flush=True)

    failed = False
    for path in files:
        start = time.perf_counter()
        try:
            compiled = compile_file(path, progress)
        except LegError as e:
            print(e.render(), file=sys.stderr)
            failed = True
            continue
        for c in compiled:
            where = write_generated(c, args.out)
            progress(f"{c.name}: wrote {where}/ ({time.perf_counter() - start:.2f} s in all)")
    return EXIT_USER_ERROR if failed else 0


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
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

    k = sub.add_parser(
        "compile",
        help="generate the equations of motion of creatures as Python modules",
        description="Lower each creature through sympy (articulated-body dynamics, bias forces, "
        "mass matrix, contact kinematics) and write generated/NAME/dynamics.py, replacing the "
        "directory only once the new one is complete. Progress goes to stderr. --all compiles "
        "creatures/*.leg and is the command that updates the golden files.",
        epilog="Example: legdsl compile creatures/kangaroo.leg  (or: legdsl compile --all)",
    )
    k.add_argument("files", nargs="*", metavar="FILE", help=".leg files to compile")
    k.add_argument("--all", action="store_true", help="compile every creatures/*.leg")
    k.add_argument(
        "--out",
        default="generated",
        metavar="DIR",
        help="where to write NAME/ (default: generated)",
    )
    _COMMANDS["compile"] = _cmd_compile

    return p


def main(argv: Sequence[str] | None = None) -> int:
    parser = _parser()
    args = parser.parse_args(argv)
    try:
        return _COMMANDS[args.command](args)
    except LegError as e:
        print(e.render(), file=sys.stderr)
        return EXIT_USER_ERROR
    except KeyboardInterrupt:
        print("legdsl: interrupted", file=sys.stderr)
        return 130
    except Exception as e:  # a bug in legdsl, not in the user's file
        if args.debug:
            traceback.print_exc()
        else:
            print(
                f"legdsl: internal error ({type(e).__name__}: {e}); this is a bug in legdsl, "
                "not in your file. Run again with --debug for the traceback.",
                file=sys.stderr,
            )
        return EXIT_INTERNAL


if __name__ == "__main__":
    sys.exit(main())
