"""What every ``legdsl`` command shares: exit statuses, numbers given with their units, and
the argv mistakes argparse would misread."""

from __future__ import annotations

import argparse
import errno
import re
import signal
import sys
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

from legdsl.lang.errors import UsageError
from legdsl.lang.units import UnitError, looks_like_unit, parse_unit

EXIT_USER_ERROR = 2
EXIT_DIVERGED = 3
EXIT_FELL = 4
EXIT_INTERRUPTED = 130  # Ctrl-C (SIGINT), as shells report it; the run directory is written
EXIT_TERMINATED = 143  # SIGTERM; likewise
EXIT_INTERNAL = 70

Command = Callable[[argparse.Namespace], int]


def numeric(args: argparse.Namespace, dest: str, flag: str, spec: Any) -> Any:
    """The option's value in SI: parsed (with its unit) when given as text, else the default."""
    from legdsl.pipeline.options import read_numeric

    value = getattr(args, dest)
    return read_numeric(flag, value, spec) if isinstance(value, str) else value


def file_read_as_option(argv: Sequence[str]) -> str | None:
    """What to say of a file whose name starts with '-' (``legdsl run -hop.leg``), which
    argparse reads as options (there ``-h`` given 'op.leg'), or None if there is none."""
    for arg in argv:
        if arg == "--":
            return None
        if arg.startswith("-") and len(arg) > 2 and (arg.endswith(".leg") or Path(arg).exists()):
            return (
                f"{arg}: a name that starts with '-' reads as an option; write ./{arg} "
                "(or put -- before it)"
            )
    return None


def empty_argument(argv: Sequence[str], parser: argparse.ArgumentParser) -> str | None:
    """What to say of an empty argument, mostly an unset shell variable (``--out "$DIR"``):
    ``--out ''`` wrote into the default directory, a sweep's into the current one, and
    ``legdsl run ''`` said "cannot read .: Is a directory"; or None if there is none."""
    takes_value = options_with_a_value(parser, short=True)
    for i, arg in enumerate(argv):
        option = arg[:-1] if arg.startswith("--") and arg.endswith("=") else None
        if arg == "" and i and argv[i - 1] in takes_value:
            option = argv[i - 1]
        if option in takes_value:
            return f"{option} was given an empty value (an unset shell variable?): give one"
        if arg == "":
            return "an argument is empty (an unset shell variable?): give a file or a value"
    return None


# '-5s', '-1ms', '-.5', '-inf': a negative value, not an option
_NEGATIVE = re.compile(r"-(?:\.?\d|inf|nan)", re.IGNORECASE)


def negative_values_joined(argv: Sequence[str], parser: argparse.ArgumentParser) -> list[str]:
    """``argv`` with each negative value given to an option that takes one written as
    ``--time=-5s``: argparse reads a '-5s' after ``--time`` as another option ("expected
    one argument"), where legdsl's own check of the value says what is wrong with it."""
    takes_value = options_with_a_value(parser)
    out: list[str] = []
    for i, arg in enumerate(argv):
        if arg == "--":
            return out + list(argv[i:])
        if out and out[-1] in takes_value and _NEGATIVE.match(arg):
            out[-1] = f"{out[-1]}={arg}"
        elif _unit_apart(out, arg, takes_value):  # '--time 2 s' is '--time 2s', as in a file
            out[-1] += arg
        else:
            out.append(arg)
    return out


_PLAIN_NUMBER = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?")


def _unit_apart(out: Sequence[str], arg: str, takes_value: set[str]) -> bool:
    """Whether ``arg`` is a unit written apart from the number an option was just given
    (``--time 2 s``, ``--set speed=2 m/s``, ``--dt=0.4 ms``), or a word meant as one (``--fps
    30 fps``): argparse took it for another argument ("unrecognized arguments: s"); a file
    reads '2 s' as '2s'."""
    if not out:
        return False
    last = out[-1]
    if last.startswith("--"):
        flag, given, number = last.partition("=")
        if not given or flag not in takes_value:
            return False
    elif len(out) >= 2 and out[-2] in takes_value:
        number = re.split("[=@]", last)[-1]
    else:
        return False
    if not _PLAIN_NUMBER.fullmatch(number):
        return False
    try:
        parse_unit(arg)
    except UnitError:  # 'sec', 'fps': meant as a unit, and the option's check says which
        return looks_like_unit(arg, fuzzy=False) and not Path(arg).exists()
    return True


def options_with_a_value(parser: argparse.ArgumentParser, short: bool = False) -> set[str]:
    """The long options (and the short ones too) of ``parser`` and its subcommands that take
    exactly one value."""
    found: set[str] = set()
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for sub in action.choices.values():
                found |= options_with_a_value(sub, short)
        elif action.nargs is None:
            found.update(o for o in action.option_strings if short or o.startswith("--"))
    return found


def os_refusal(e: OSError, command: str = "run") -> str:
    """What the file system's refusal ``e`` means for the user of ``command``: a full disk or
    a quota says what to free; anything else is a path or a permission."""
    from legdsl.files import REFUSED_WRITES, refused

    if e.errno in (errno.EMFILE, errno.ENFILE):  # ulimit -n, not a path: the path is fine
        return f"{e.strerror}: raise the limit of open files (ulimit -n) and run again"
    if e.errno == errno.ENOMEM:
        from legdsl.cli.process import out_of_memory

        return out_of_memory(command)
    if e.errno in REFUSED_WRITES:
        where = f"cannot write {e.filename}: " if e.filename else ""
        return f"{where}{refused(e, e.filename or '').strerror}, or give another place to write"
    if e.errno == errno.EPIPE:  # '-o /dev/stdout | head': not the path, nor its permissions
        where = f"{e.filename}: " if e.filename else ""
        return (f"{where}the pipe's reader stopped reading before all was written (as "
                "'| head' does), so what it got is cut short")  # fmt: skip
    if e.errno == errno.EBADF and e.filename:  # -o /dev/stdin, a stream opened only to read
        return (f"cannot write {e.filename}: the stream it names is not open for writing; "
                "give a file")  # fmt: skip
    where = f" ({e.filename})" if e.filename else ""
    return f"{e.strerror or e}{where}; check the path and its permissions"


def read_window(args: argparse.Namespace) -> None:
    """--from and --to as seconds (a unit is welcome: 3s, 500ms); the end after the start."""
    from legdsl.pipeline.options import WINDOW

    args.t_from = numeric(args, "t_from", "--from", WINDOW)
    args.t_to = numeric(args, "t_to", "--to", WINDOW)
    if args.t_to is not None and args.t_to <= args.t_from:
        raise UsageError(f"--to {args.t_to:g}s must come after --from {args.t_from:g}s")


def interrupted(process_ends: bool) -> int:
    """Says a command was interrupted. In the console script, whose process ends after it, a
    Ctrl-C held down is ignored from here: the unwound command's objects are freed after this,
    and a KeyboardInterrupt raised in one's ``__del__`` printed a traceback."""
    if process_ends:
        signal.signal(signal.SIGINT, signal.SIG_IGN)
    print("legdsl: interrupted", file=sys.stderr)
    return EXIT_INTERRUPTED


def add_window(p: argparse.ArgumentParser) -> None:
    """--from and --to: the part of a run to measure or draw."""
    p.add_argument("--from", dest="t_from", default=0.0, metavar="T",
                   help="start of the window in s (default 0)")  # fmt: skip
    p.add_argument("--to", dest="t_to", default=None, metavar="T",
                   help="end of the window in s (default: the end of the run)")  # fmt: skip
