"""What every ``legdsl`` command shares: exit statuses, and numbers given with their units."""

from __future__ import annotations

import argparse
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

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
