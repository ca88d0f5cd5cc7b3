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
from multiprocessing.context import ForkContext, ForkServerContext, SpawnContext
from typing import Any

from legdsl.signals import signals_held, unblock_stopping

Work = Callable[[Any], bytes]  # an item's result, pickled (what crosses the pipe)


@contextlib.contextmanager
def _main_not_imported(forked: bool) -> Iterator[None]:
    """A spawned process imports this one's ``__main__`` again (as ``__mp_main__``), by its
    file or module name, to find what it is given by name; a script without an ``if __name__
    == "__main__"`` guard then ran again whole in it (its prints, its runs) when a thread of its
    own made legdsl spawn. The work given is legdsl's own, so the main module is left out: its
    name and file are hidden while the process starts."""
    main = sys.modules.get("__main__")
    if forked or main is None:
        yield
        return
    saved = {k: getattr(main, k) for k in ("__spec__", "__file__") if hasattr(main, k)}
    main.__spec__ = None
    if "__file__" in saved:
        del main.__file__
    try:
        yield
    finally:
        for name, value in saved.items():
            setattr(main, name, value)


def _context(
    work: Work,
) -> ForkContext | ForkServerContext | SpawnContext:
    """Forked (no import of sympy again) where this process has one thread. Where it has more
    (a notebook's kernel, a Dask worker, a test runner), forking may deadlock: the processes
    come from a fork server, a process of one thread started once for this one, which imports
    the work's module (sympy, the lowering) once and forks each from itself; spawned each
    imported them again, some 1.5 s a process, a fifth of the test suite's time. (macOS
    forks unsafely under its system frameworks; Python spawns there by default, as here.)"""
    if not sys.platform.startswith("linux"):
        return multiprocessing.get_context("spawn")
    if threading.active_count() == 1:
        return multiprocessing.get_context("fork")
    context = multiprocessing.get_context("forkserver")
    # Taken where the server starts, once (one already running, the caller's own, is used as
    # it is): the compiler's lowering, whatever work comes first, and the work's own module
    # (its default, the caller's __main__, ran a script again).
    context.set_forkserver_preload(
        ["legdsl.pipeline.compile", getattr(work, "func", work).__module__]
    )
    return context


class Forked:
    """``work`` on ``items[k]`` in one of up to ``processes`` processes (item k in process
    k mod n, which answers its items in order); ``result(k)`` waits for it."""

    def __init__(self, work: Work, items: Sequence[Any], processes: int) -> None:
        self.work, self.items = work, items
        self._pipes: list[Connection | None] = []
        self._processes: list[multiprocessing.process.BaseProcess] = []
        context = _context(work)
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
                with signals_held(), _main_not_imported(forked):
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
        """Stop the processes (those still working after an error here), reap them and close
        the pipes, with Ctrl-C and the ending signals held (they come after; a killed process
        is reaped at once). A Ctrl-C that landed in ``join`` between the child's reaping and
        its note left it "still running" to multiprocessing for good; one that landed in the
        finalizer that closes a process's own pipes, which the garbage collector ran whenever
        it came, was "Exception ignored in: <Finalize object, dead>", a traceback, and lost."""
        with signals_held():
            for process in self._processes:
                if process.is_alive():  # SIGKILL: one forked with a handler that notes SIGTERM
                    process.kill()  # (a run writing its files) would not stop, nor say so
            for process in self._processes:
                process.join()
                with contextlib.suppress(ValueError):  # one reaped by another (SIGCHLD ignored)
                    process.close()  # its finalizer, now
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
    answers = []
    for item in items:
        try:
            answers.append(pickle.dumps((False, work(item))))
        except Exception as e:  # raised again where the result is asked for
            answers.append(pickle.dumps((True, e)))
            break
    # Sent once all are worked: a result is more than a pipe holds (a controller's some
    # 300 KB, a pipe 64 KB), and the command reads only once its own work is done (the
    # dynamics), so sending each as it came held this process still until then.
    try:
        for answer in answers:
            pipe.send_bytes(answer)
    except BrokenPipeError:  # the command ended (a signal, a kill): nobody reads
        return
