"""``legdsl`` (the console script) and ``python -m legdsl``: the command line.

The command line's modules are imported here, inside ``main``, so that a Ctrl-C while
they load (the first second of a command) is told as one line, as later, not as a
traceback of the import.

numpy's OpenBLAS starts a thread per core, each with buffers of its own, for arithmetic on
matrices that legdsl never has (its largest is a creature's mass matrix): under ``ulimit -v``
those buffers were what could not be had (``legdsl run`` at 200 MB: "OpenBLAS error: Memory
allocation still failed", exit 1, nothing said by legdsl), and a sweep's processes each
started as many threads again. One thread, unless the user asks for more.
"""

import os
import signal
import sys
import time


class _CtrlC:
    """Ctrl-C in the console script: a KeyboardInterrupt, then none for a second. Held down
    (or pressed again) as the command unwinds, each one was raised where it landed: in the
    cleanup of a ``finally``, or in a ``__del__`` that printed "Exception ignored" and its
    traceback. One so lost is raised again by the next Ctrl-C a second later."""

    def __init__(self) -> None:
        self.raised_at = float("-inf")

    def __call__(self, signum: int, frame: object) -> None:
        if time.monotonic() - self.raised_at >= 1.0:
            self.raised_at = time.monotonic()
            raise KeyboardInterrupt


def main() -> int:
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")  # read when numpy is first imported
    if signal.getsignal(signal.SIGINT) is signal.default_int_handler:  # not ignored (nohup)
        signal.signal(signal.SIGINT, _CtrlC())
    try:
        from legdsl.cli import main as command_line
    except KeyboardInterrupt:
        print("legdsl: interrupted", file=sys.stderr)
        return 130  # legdsl.cli.common.EXIT_INTERRUPTED, which could not be imported
    except (MemoryError, SystemError):  # a memory limit (ulimit -v) too low to load numpy:
        # the import machinery then fails as SystemError ("... without setting an exception")
        print("legdsl: out of memory: raise the memory limit (ulimit -v)", file=sys.stderr)
        return 2
    # A second Ctrl-C as an interrupted command ends (flushing its output, or in Python's exit
    # handlers) was a traceback after "legdsl: interrupted": the command is over by then.
    try:
        return command_line(process_ends=True)
    except KeyboardInterrupt:  # it has said "interrupted" already
        return 130
    finally:
        signal.signal(signal.SIGINT, signal.SIG_IGN)


if __name__ == "__main__":
    sys.exit(main())
