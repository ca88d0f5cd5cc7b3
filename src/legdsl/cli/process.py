"""How a command's process meets what is around it: a reader of its standard output that
leaves early, and SIGTERM while it writes an output through a temporary file."""

from __future__ import annotations

import contextlib
import io
import os
import signal
import sys
from collections.abc import Iterator
from typing import Any, TextIO

from legdsl.signals import handled

# what each command can ask less of, in its own options: `animate` was told legdsl run's
# --time and --record-rate, when its --fps (the frames it stores) is what helps; a video's
# frames are --fps times --slow-motion a second (1e12 was told --fps alone)
LESS_OF = {
    "run": "a shorter --time, a lower --record-rate",
    "plot": "a shorter window: --from T, --to T",
    "metrics": "a shorter window: --from T, --to T",
    "animate": "fewer frames: a lower --fps, e.g. --fps 10, or a video's lower --slow-motion",
    "export-motion": "fewer keyframes: a lower --fps, e.g. --fps 10",
    "sweep": "a shorter --time, fewer --jobs",
    "tune": "a shorter --time, a smaller --popsize, fewer --jobs",  # each holds a generation
}
OUT_OF_MEMORY_TO_LOAD = (
    "out of memory to load legdsl and its libraries (numpy, sympy): raise the memory limit "
    "(ulimit -v) and run again"
)


def out_of_memory(command: str) -> str:
    """What a command short of memory is told to ask less of ("": legdsl itself, loading);
    one without such options (check, compile) only to raise the limit."""
    if not command:
        return OUT_OF_MEMORY_TO_LOAD
    if command not in LESS_OF:
        return "out of memory: raise the memory limit (ulimit -v) and run again"
    return f"out of memory: raise the memory limit (ulimit -v) or ask for less ({LESS_OF[command]})"


def streams_that_cannot_fail() -> None:
    """Standard error closed (``2>&-``): messages go nowhere, where print() would send them to
    standard output (into an export written there). An encoding without é or °
    (PYTHONIOENCODING=ascii): those characters written as escapes, not an error after the work.
    A closed descriptor (``>&-``) gets /dev/null, so that no file opened later takes its number."""
    from legdsl.files import keep_standard_descriptors

    keep_standard_descriptors()
    if sys.stderr is None:
        sys.stderr = open(os.devnull, "w")  # noqa: SIM115 - for the life of the process
    for stream in (sys.stdout, sys.stderr):
        if isinstance(stream, io.TextIOWrapper) and stream.errors == "strict":
            stream.reconfigure(errors="backslashreplace")


def cannot_import(e: ImportError) -> str:
    """What to do when a library legdsl needs cannot be loaded: usually another Python than the
    one legdsl was installed in; under ``ulimit -v``, too little memory to map it."""
    said = str(e).strip().splitlines()[-1] if str(e).strip() else type(e).__name__
    if (e.name or "").partition(".")[0] == "legdsl":  # a name one of its modules lacks
        return (
            f"cannot load {e.name} ({said}): legdsl's own files do not match one another (an "
            "upgrade cut short, or files edited while it ran): run it again, or reinstall "
            "legdsl (pip install --force-reinstall legdsl)"
        )
    return (
        f"cannot load {e.name or 'a library legdsl needs'} ({said}): install legdsl's "
        "dependencies in this Python (pip install legdsl), or raise the memory limit "
        "(ulimit -v) if one is set"
    )


THREAD_REFUSED = (
    "a thread could not start (out of memory, or the limit of processes): raise the memory "
    "limit (ulimit -v) or the limit of processes (ulimit -u), or ask for fewer threads"
)


def a_library_failed(e: SystemError) -> str:
    """Python's own "returned NULL without setting an exception": a C library that could not
    allocate as it loaded (under ``ulimit -v`` the import machinery itself fails this way), not
    a fault of the user's file; the words Python said are kept in case memory is not why."""
    return (
        f"out of memory while loading a library (Python said: {e}): raise the memory limit "
        "(ulimit -v) and run again"
    )


def current_directory_exists() -> bool:
    """False in a directory removed under the shell (``cd d; rm -rf ../d``), where every
    relative path would fail later as a file "not found" in '.'."""
    try:
        os.getcwd()
    except FileNotFoundError:
        return False
    return True


class QuietWhenClosed:
    """Standard output that goes quiet when its reader leaves (``legdsl run ... | head -1``):
    the command still writes its files (a run's player, an export), and its exit status is
    the work's, not a "Broken pipe" after half of it."""

    def __init__(self, stream: TextIO) -> None:
        self._stream = stream
        self.reader_left = False
        # the first write refused, kept: argparse's --help swallows the OSError it gets
        self.refused: OSError | None = None
        self.said = False  # whether the refusal was told already (else it was told twice)

    def write(self, text: str) -> int:
        if not self.reader_left:
            try:
                return self._stream.write(text)
            except OSError as e:
                self._failed(e)
        return len(text)

    def flush(self) -> None:
        if not self.reader_left:
            try:
                self._stream.flush()
            except OSError as e:
                self._failed(e)
        if self.refused is not None and not self.said:
            raise self.refused

    def told(self, e: OSError) -> None:
        """The command's refusal ``e`` was told the user: if it is this stream's, the flush
        at the end does not tell it again."""
        self.said = self.said or e is self.refused

    def _failed(self, e: OSError) -> None:
        if isinstance(e, BrokenPipeError):
            self._left()
            return
        raise self._refusal(e) from None  # > /dev/full, a full disk: say which file it was

    def _refusal(self, e: OSError) -> OSError:
        self.refused = self.refused or OSError(e.errno, e.strerror, "standard output")
        return self.refused

    def _left(self) -> None:
        self.reader_left = True
        # what is still buffered is flushed at exit too: send it nowhere, quietly
        with contextlib.suppress(OSError, ValueError):
            devnull = os.open(os.devnull, os.O_WRONLY)
            os.dup2(devnull, self._stream.fileno())
            os.close(devnull)

    def __getattr__(self, name: str) -> Any:
        return getattr(self._stream, name)


class QuietErrors(QuietWhenClosed):
    """Standard error that goes quiet when it cannot be written (``legdsl compile 2>&1 | head
    -1``, ``2>/dev/full``): a message lost is no reason to stop the work (the compile stopped
    at its second line with a Broken pipe, exit 1, and wrote nothing)."""

    def _failed(self, e: OSError) -> None:
        self._left()


# Readers that write one output through a temporary file and, for a video, an ffmpeg, and the
# commands with worker processes: SIGTERM unwinds them as Ctrl-C does (the temporary file
# removed, ffmpeg and the workers stopped, a tune's best so far written), where Python's
# default would end the process on the spot and leave them behind (a compile's controller
# processes). (``run`` has its own, and unwinds so while it compiles.)
TERM_UNWINDS = ("animate", "export-motion", "replay", "plot", "sweep", "tune", "compile")


# Signals that end a command as SIGTERM does, where Python's default would kill it on the
# spot with nothing written: a closed terminal (SIGHUP), Ctrl-\\ (SIGQUIT) and the CPU-time
# limit of ``ulimit -t`` (SIGXCPU, sent at the soft limit, before the hard one's SIGKILL).
ENDING_SIGNALS = tuple(
    getattr(signal, name)
    for name in ("SIGTERM", "SIGHUP", "SIGQUIT", "SIGXCPU")
    if hasattr(signal, name)
)


def exit_status(cause: str) -> int:
    """128 plus the number of the signal named ``cause``, as shells report a signal's death;
    130 (Ctrl-C) for any other cause."""
    try:
        return 128 + signal.Signals[cause].value
    except KeyError:
        return 130


# Commands that read a run directory and may write what they draw into it (figure6.png,
# animation.html, metrics.json, motion.glb; not replay, which may only show it, for minutes)
DRAW_INTO_RUNS = ("plot", "animate", "export-motion", "metrics")


@contextlib.contextmanager
def run_held(args: Any) -> Iterator[None]:
    """For a command that draws from a run, the run directory's lock meanwhile
    (``legdsl.files.writing_alone``), which a new run into it takes to replace its files and
    remove what was drawn from the one before: the new run waits, so a picture of the old run
    is never left beside it (``plot`` reading run A while run B replaced it wrote A's
    figure6.png beside B's trajectory)."""
    from pathlib import Path

    from legdsl.files import writing_alone

    folder = Path(getattr(args, "run", None) or getattr(args, "dir", None) or "")
    with contextlib.ExitStack() as held:
        if args.command in DRAW_INTO_RUNS and folder.name and folder.is_dir():
            with contextlib.suppress(OSError):  # a file system without locks: drawn unheld
                held.enter_context(writing_alone(folder))
        yield


def term_unwinds(command: str) -> contextlib.AbstractContextManager[None]:
    """``sigterm_unwinds`` for a command of ``TERM_UNWINDS``, else nothing."""
    return sigterm_unwinds() if command in TERM_UNWINDS else contextlib.nullcontext()


@contextlib.contextmanager
def sigterm_unwinds() -> Iterator[None]:
    """An ending signal raises ``Interrupted``, once: the command is unwinding to its end then,
    and another (SIGTERM held down) is not obeyed. Raised again, it could land as the context
    began to exit, before the handlers went back, and leave them installed in a generator
    left for the collector ("Exception ignored in: <generator object sigterm_unwinds>", a
    traceback after "legdsl: terminated"; CI under load)."""
    from legdsl.sim.run_loop import Interrupted

    unwinding = False

    def unwind(signum: int, frame: Any) -> None:
        nonlocal unwinding
        if not unwinding:
            unwinding = True
            raise Interrupted(signal.Signals(signum).name)

    with handled(ENDING_SIGNALS, unwind):
        yield
