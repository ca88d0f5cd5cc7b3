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
from collections.abc import Callable
from pathlib import Path
from typing import TextIO

from legdsl.files import is_device, process_fd
from legdsl.lang.errors import UsageError

PICTURES = (".png", ".svg", ".pdf")  # what matplotlib writes as the name says


def is_stream(path: str | Path) -> bool:
    """Whether ``path`` is ``-``, a device or a pipe, or a descriptor of this process."""
    return str(path) == "-" or is_device(Path(path)) or process_fd(Path(path)) is not None


def not_standard_output(given: str | Path, flag: str) -> None:
    """A directory a command writes its files into (``run --out``, ``compile -o``, ``sweep
    --out``, ``tune --out``) named ``-``: refused with a caret, where ``-`` made a directory
    named '-' and said nothing of it (``export -o -`` writes standard output, ``plot -o -`` is
    refused)."""
    if str(given) == "-":
        raise UsageError(
            f"{flag} -: a directory of files cannot go to standard output; give a directory "
            f"name (./- for a directory named '-')\n    {flag} -\n    {' ' * (len(flag) + 1)}^"
        )


def new_directory(path: str | Path) -> Path | None:
    """The outermost missing directory above the file ``path`` (writing the file makes it and
    those under it, as ``legdsl run --out`` makes its run directory), or None when the file's
    folder exists: the command that writes the file says it made it (``made_note``)."""
    top, parent = None, Path(path).parent
    while not parent.exists() and not parent.is_symlink() and parent.parent != parent:
        top, parent = parent, parent.parent
    return top


def made_note(made: Path | None, path: str | Path) -> str:
    """``made directory DIR/``: said before a command's "wrote" line where writing ``path``
    made ``made`` (``new_directory``), so that a mistyped folder (``-o /nonexistent/x.glb``)
    is seen; "" where it made none."""
    if made is None:
        return ""
    folder = Path(path).parent
    return f"made directory {made}/" if folder == made else f"made directories {made}/ to {folder}/"


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


def not_a_stream(path: str | Path, flag: str) -> None:
    """A video's format is its name's (.mp4 or .gif) and ffmpeg seeks in an .mp4: a stream
    (/dev/stdout, a pipe) is refused (it was told to write '/dev/stdout.mp4')."""
    if is_stream(path):
        raise UsageError(
            f"{flag} {path}: a video is written to a file named .mp4 or .gif (its format is "
            f"its name's, and a stream has none); give a file, e.g. {flag} run.mp4"
        )


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


# Address space a library takes beyond what a command has taken before it loads it (measured
# under ulimit -v on 2 cores): matplotlib with its fonts and a figure drawn (80 MB for legdsl
# plot of a hopper's run), usd-core with its threads (930 MB; below, it dies of a segmentation
# fault or an abort, with nothing said). Below ROOM_TO_LOAD (28 MB left: legdsl plot spun for
# ever), a picture drawn after the work is not tried; above it, its failure is caught.
ROOM_TO_DRAW = 80 * 2**20
ROOM_TO_LOAD = 40 * 2**20
ROOM_FOR_USD = 1000 * 2**20


class OutOfRoom(UsageError):
    """``room_for``'s refusal."""


def room_for(what: str, needed: int) -> None:
    """Refuse (``UsageError``) to do ``what`` where ``ulimit -v`` leaves less than ``needed``
    bytes: short of memory while it loads a library, Python can spin for ever without
    answering SIGTERM, and OpenBLAS or usd-core end the process with nothing written."""
    from legdsl.sim.recorder import address_space_left

    left = address_space_left()
    if left is not None and left < needed:
        raise OutOfRoom(
            f"out of memory to {what}: the memory limit (ulimit -v) leaves {left // 2**20} MB "
            f"where it takes about {needed // 2**20} MB; raise it and run again"
        )


def drawn_if_room(what: str, draw: Callable[[], object]) -> str | None:
    """Draw a picture that follows work already written (a sweep's heat map, a tune's
    convergence plot): None when drawn, else why not, where too little memory to load or run
    matplotlib would end the command before it said that the work is whole."""
    try:
        room_for(what, ROOM_TO_LOAD)
        draw()
    except OutOfRoom as e:
        return str(e)
    except ImportError as e:  # a shared object that could not be mapped under ulimit -v
        said = f"cannot load {e.name or 'matplotlib'}"
        return f"{said} to {what}: raise the memory limit (ulimit -v) and run again"
    except (MemoryError, SystemError):  # SystemError: the import machinery short of memory
        return f"out of memory to {what}: raise the memory limit (ulimit -v) and run again"
    return None
