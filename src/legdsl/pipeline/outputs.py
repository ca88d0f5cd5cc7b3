"""The one rule for every file a command names with ``-o`` (or ``--video``).

Its name ends in the suffix of what is written into it (``.png``, ``.html``, ``.mp4``,
``.xml``...); a name without it is refused, saying the name to write: writers that choose the
format by the name (matplotlib, ffmpeg) would otherwise write another file than the one named,
or nothing. Standard output (``-``, ``/dev/stdout``) and other devices and pipes are written as
given. When the output is standard output, the command's messages go to standard error, so
that what is read from standard output is exactly the file.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path
from typing import TextIO

from legdsl.files import is_device, process_fd
from legdsl.lang.errors import UsageError

PICTURES = (".png", ".svg", ".pdf")  # what matplotlib writes as the name says


def is_stream(path: str | Path) -> bool:
    """Whether ``path`` is ``-``, a device or a pipe, or a descriptor of this process."""
    return str(path) == "-" or is_device(Path(path)) or process_fd(Path(path)) is not None


def named_as(path: str | Path, flag: str, suffixes: tuple[str, ...], what: str) -> Path:
    """``path``, if its name ends in one of ``suffixes`` (or it is a stream); else refused
    with the name to write (``suffixes[0]`` added, or put in place of the wrong one)."""
    out = Path(path)
    if str(path) == "-":
        raise UsageError(f"{flag} -: for standard output write {flag} /dev/stdout")
    if out.suffix.lower() in suffixes or is_stream(path):
        return out
    better = out.with_suffix(suffixes[0]) if out.suffix else out.with_name(out.name + suffixes[0])
    raise UsageError(f"{flag} {path}: this writes {what}; name it {better}")


def to_stdout(path: str | Path | None) -> bool:
    """Whether writing ``path`` writes this process's standard output (``-``, /dev/stdout,
    or the very file the shell sent standard output to)."""
    if path is None:
        return False
    if str(path) == "-" or process_fd(Path(path)) == 1:
        return True
    try:
        named, ours = os.stat(path), os.fstat(1)
    except (OSError, ValueError):
        return False
    return (named.st_dev, named.st_ino) == (ours.st_dev, ours.st_ino)


def messages_for(*outputs: str | Path | None) -> TextIO:
    """Where a command's messages go: standard error if one of its outputs is standard
    output, else standard output."""
    return sys.stderr if any(to_stdout(p) for p in outputs) else sys.stdout
