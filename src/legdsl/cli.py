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


def _cmd_export(args: argparse.Namespace) -> int:
    from .checker import check_model
    from .export import default_path, export_text, write_atomic

    model = check_model(args.file, args.creature)
    text = export_text(model, args.format)
    if args.output == "-":
        sys.stdout.write(text)
        return 0
    out = args.output or default_path(model, args.format)
    write_atomic(out, text)
    print(f"wrote {out} ({args.format.upper()}, creature '{model.name}', {model.nv} DOF)")
    return 0


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
        "--format", required=True, choices=("mjcf", "urdf"), help="MJCF (MuJoCo XML) or URDF"
    )
    e.add_argument(
        "-o",
        "--output",
        metavar="OUT",
        help="output file (default: NAME.xml or NAME.urdf here; '-' for standard output)",
    )
    e.add_argument("--creature", help="which creature, if the file has several")
    _COMMANDS["export"] = _cmd_export

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
