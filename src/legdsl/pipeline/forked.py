"""Work handed to other processes without a pool's threads: the compiler lowers a creature's
controllers there while it lowers the dynamics (``legdsl.pipeline.compile``).

``concurrent.futures.ProcessPoolExecutor`` feeds its processes from two threads of this one;
where a thread cannot start (``ulimit -v``: "can't start new thread") its manager dies and the
futures it held never finish, so ``legdsl run`` hung for ever. Here the processes are started
from this thread, each answers through its own pipe, and whatever a process could not do (it
would not start, or it died) is done here instead: the result is the same, only slower.
"""

from __future__ import annotations

import contextlib
import multiprocessing
import pickle
import signal
import sys
import threading
from collections.abc import Callable, Iterator, Sequence
from multiprocessing.connection import Connection
from typing import Any

Work = Callable[[Any], bytes]  # an item's result, pickled (what crosses the pipe)


# What a command takes as an order to stop: Ctrl-C and the signals that end it as SIGTERM does
# (a closed terminal, Ctrl-\\, ulimit -t's soft limit); all held back while a process starts.
STOPPING = tuple(
    getattr(signal, name)
    for name in ("SIGINT", "SIGTERM", "SIGHUP", "SIGQUIT", "SIGXCPU")
    if hasattr(signal, name)
)


@contextlib.contextmanager
def signals_held() -> Iterator[None]:
    """Ctrl-C and the ending signals held back while a process starts: an exception raised by
    their handlers in the fork's handlers (logging's lock, in this process or the new one) was
    printed as "Exception ignored" and dropped (a SIGTERM so lost let a compile finish, exit
    0), and one in the new process before it set its own handlers printed its traceback. They
    come once this is over; the new process starts with them blocked, sets its handlers, then
    unblocks them (``unblock_stopping``). Blocking holds back only this thread's share: in a
    process of several threads (a Jupyter kernel) another thread takes the signal and Python
    raised it here all the same, so the main thread's Ctrl-C handler (Python's, the console
    script's or a kernel's) is swapped for one that notes it, and called once this is over."""
    noted: list[int] = []
    handler = signal.getsignal(signal.SIGINT)  # Python's, the console script's or a kernel's
    main = threading.current_thread() is threading.main_thread()  # signal.signal's only thread
    swapped = handler if main and callable(handler) else None  # not SIG_IGN, SIG_DFL
    if swapped is not None:
        signal.signal(signal.SIGINT, lambda signum, frame: noted.append(signum))
    before = (
        signal.pthread_sigmask(signal.SIG_BLOCK, set(STOPPING))
        if hasattr(signal, "pthread_sigmask")
        else None
    )
    try:
        yield
    finally:
        if before is not None:
            signal.pthread_sigmask(signal.SIG_SETMASK, before)
        if swapped is not None:
            signal.signal(signal.SIGINT, swapped)
            if noted:
                swapped(signal.SIGINT, None)


def unblock_stopping() -> None:
    """In a process started under ``signals_held``, once its own handlers are set."""
    if hasattr(signal, "pthread_sigmask"):
        signal.pthread_sigmask(signal.SIG_UNBLOCK, set(STOPPING))


class Forked:
    """``work`` on ``items[k]`` in one of up to ``processes`` processes (item k in process
    k mod n, which answers its items in order); ``result(k)`` waits for it."""

    def __init__(self, work: Work, items: Sequence[Any], processes: int) -> None:
        self.work, self.items = work, items
        self._pipes: list[Connection | None] = []
        self._processes: list[multiprocessing.process.BaseProcess] = []
        # Forked (no import of sympy again) where this process has one thread; spawned where
        # it has more (a Dask worker compiling a stale creature), as forking a threaded
        # process may deadlock. (macOS forks unsafely under its system frameworks: Python
        # spawns there by default too.)
        alone = threading.active_count() == 1 and sys.platform.startswith("linux")
        context = (
            multiprocessing.get_context("fork") if alone else multiprocessing.get_context("spawn")
        )
        forked = context.get_start_method() == "fork"
        for first in range(min(processes, len(items))):
            try:
                reading, writing = context.Pipe(duplex=False)
                # a forked process holds copies of the reading ends made so far: it closes them,
                # so that with this process gone its writes fail (it held its own pipe open and
                # blocked for ever on a full one, orphaned, when a signal ended a compile)
                others = [*self._pipes, reading] if forked else []
                process = context.Process(
                    target=_answer,
                    args=(work, items[first::processes], writing, others),
                    daemon=True,
                )
                with signals_held():
                    process.start()
                    self._processes.append(process)  # before a Ctrl-C held back comes
                    self._pipes.append(reading)
            except (OSError, MemoryError, RuntimeError):  # no memory or processes left
                break
            except BaseException:  # Ctrl-C: those started are stopped, not left lowering
                self.close()
                raise
            writing.close()  # here: so that a process that dies is an end of file

    def result(self, k: int) -> bytes:
        """Item k's result: from its process, or worked here if it has none (or lost it)."""
        pipe = self._pipes[k % len(self._pipes)] if self._pipes else None
        if pipe is not None:
            try:
                failed, answer = pickle.loads(pipe.recv_bytes())
            except (EOFError, OSError):  # the process died (out of memory, killed)
                self._pipes[k % len(self._pipes)] = None
            else:
                if failed:
                    raise answer
                return answer
        return self.work(self.items[k])

    def close(self) -> None:
        """Stop the processes (those still working after an error here) and close the pipes."""
        for process in self._processes:
            if process.is_alive():  # SIGKILL: one forked with a handler that notes SIGTERM
                process.kill()  # (a run writing its files) would not stop, nor say so
        for process in self._processes:
            while True:  # every one reaped, also under a Ctrl-C held down
                try:
                    process.join()
                    break
                except KeyboardInterrupt:  # the first is already unwinding
                    continue
        for pipe in self._pipes:
            if pipe is not None:
                pipe.close()


def _answer(
    work: Work, items: Sequence[Any], pipe: Connection, inherited: Sequence[Connection]
) -> None:
    """In the process: each item's result in turn, or the exception that stopped it; once the
    command that forked it is gone (nobody reads), it ends quietly."""
    for reading in inherited:
        reading.close()
    # A forked process inherits the command's handlers: one that notes a signal and goes on
    # (a run writing its directory) kept it working past close()'s terminate(), then blocked
    # for ever on a pipe no one read, and close() waited for it. Ctrl-C is the command's to
    # handle (it stops this process); the ending signals end it.
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    for name in ("SIGTERM", "SIGHUP", "SIGQUIT", "SIGXCPU"):
        if hasattr(signal, name):
            signal.signal(getattr(signal, name), signal.SIG_DFL)
    unblock_stopping()
    try:
        for item in items:
            try:
                answer = (False, work(item))
            except Exception as e:  # raised again where the result is asked for
                pipe.send_bytes(pickle.dumps((True, e)))
                return
            pipe.send_bytes(pickle.dumps(answer))
    except BrokenPipeError:  # the command ended (a signal, a kill): nobody reads
        return
