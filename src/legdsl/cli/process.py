"""How a command's process meets what is around it: a reader of its standard output that
leaves early, and SIGTERM while it writes an output through a temporary file."""

from __future__ import annotations

import contextlib
import os
import signal
from collections.abc import Iterator
from typing import Any, TextIO


class QuietWhenClosed:
    """Standard output that goes quiet when its reader leaves (``legdsl run ... | head -1``):
    the command still writes its files (a run's player, an export), and its exit status is
    the work's, not a "Broken pipe" after half of it."""

    def __init__(self, stream: TextIO) -> None:
        self._stream = stream
        self.reader_left = False

    def write(self, text: str) -> int:
        if not self.reader_left:
            try:
                return self._stream.write(text)
            except BrokenPipeError:
                self._left()
        return len(text)

    def flush(self) -> None:
        if not self.reader_left:
            try:
                self._stream.flush()
            except BrokenPipeError:
                self._left()

    def _left(self) -> None:
        self.reader_left = True
        # what is still buffered is flushed at exit too: send it nowhere, quietly
        with contextlib.suppress(OSError, ValueError):
            devnull = os.open(os.devnull, os.O_WRONLY)
            os.dup2(devnull, self._stream.fileno())
            os.close(devnull)

    def __getattr__(self, name: str) -> Any:
        return getattr(self._stream, name)


# Readers that write one output through a temporary file and, for a video, an ffmpeg, and the
# commands with worker processes: SIGTERM unwinds them as Ctrl-C does (the temporary file
# removed, ffmpeg and the workers stopped, a tune's best so far written), where Python's
# default would end the process on the spot and leave them behind. (``run`` has its own.)
TERM_UNWINDS = ("animate", "export-motion", "replay", "plot", "sweep", "tune")


@contextlib.contextmanager
def sigterm_unwinds() -> Iterator[None]:
    from legdsl.sim.run_loop import Interrupted

    def unwind(signum: int, frame: Any) -> None:
        raise Interrupted("SIGTERM")

    try:
        previous = signal.signal(signal.SIGTERM, unwind)
    except ValueError:  # not the main thread (main() called from a thread): leave it be
        yield
        return
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, previous)
