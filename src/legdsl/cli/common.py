"""What every ``legdsl`` command shares: exit statuses, and numbers given with their units."""

from __future__ import annotations

import argparse
from collections.abc import Callable
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
