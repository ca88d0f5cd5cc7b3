"""Ctrl-C and the signals that end a command, held back while something must not be cut in
half: a process starting (``legdsl.pipeline.forked``, ``legdsl.api.workers``), the public
API's first import (``legdsl.__getattr__``) and the libraries imported when first needed
(``import_held``). It sits below every stage, as ``files`` does."""

from __future__ import annotations

import contextlib
import importlib
import signal
import sys
import threading
from collections.abc import Iterable, Iterator
from types import ModuleType
from typing import Any

# What a command takes as an order to stop: Ctrl-C and the signals that end it as SIGTERM does
# (a closed terminal, Ctrl-\\, ulimit -t's soft limit).
STOPPING = tuple(
    getattr(signal, name)
    for name in ("SIGINT", "SIGTERM", "SIGHUP", "SIGQUIT", "SIGXCPU")
    if hasattr(signal, name)
)


@contextlib.contextmanager
def signals_held() -> Iterator[None]:
    """Ctrl-C and the ending signals held back while a process starts, or the API is first
    imported (one landing mid-import left sympy or lark half-initialised, and the next call
    failed: sympy's RecursionError, a syntax tree with lark's Trees for rows). While a
    process starts, an exception raised by their handlers in the fork's handlers (logging's
    lock, in this process or the new one) was printed as "Exception ignored" and dropped (a
    SIGTERM so lost let a compile finish, exit 0), and one in the new process before it set
    its own handlers printed its traceback. They come once this is over; the new process
    starts with them blocked, sets its handlers, then unblocks them (``unblock_stopping``).
    Blocking holds back only this thread's share: in a process of several threads (a Jupyter
    kernel) another thread takes the signal and Python raised it here all the same, so the
    main thread's Ctrl-C handler (Python's, the console script's or a kernel's) is swapped for
    one that notes it, and called once this is over."""
    noted: list[int] = []
    handler = signal.getsignal(signal.SIGINT)  # Python's, the console script's or a kernel's
    main = threading.current_thread() is threading.main_thread()  # signal.signal's only thread
    swapped = handler if main and callable(handler) else None  # not SIG_IGN, SIG_DFL
    if swapped is not None:
        signal.signal(signal.SIGINT, lambda signum, frame: noted.append(signum))
    try:
        with blocked(STOPPING):
            yield
    finally:
        if swapped is not None:
            signal.signal(signal.SIGINT, swapped)
            if noted:
                swapped(signal.SIGINT, None)


@contextlib.contextmanager
def blocked(signals: Iterable[int]) -> Iterator[None]:
    """``signals`` kept out of this thread meanwhile (its signal mask): one that comes is
    delivered once this is over, to whatever handler is then in place."""
    before = (
        signal.pthread_sigmask(signal.SIG_BLOCK, set(signals))
        if hasattr(signal, "pthread_sigmask")
        else None
    )
    try:
        yield
    finally:
        if before is not None:
            signal.pthread_sigmask(signal.SIG_SETMASK, before)


def unblock_stopping() -> None:
    """In a process started under ``signals_held``, once its own handlers are set."""
    if hasattr(signal, "pthread_sigmask"):
        signal.pthread_sigmask(signal.SIG_UNBLOCK, set(STOPPING))


def import_held(name: str) -> ModuleType:
    """``import name`` with the stopping signals held until it is whole, for a module imported
    when first needed whose import takes a library (the compiler's sympy and jinja2,
    matplotlib). A Ctrl-C caught in a notebook mid-import left the library half-made, and the
    next call in that process failed ("module 'sympy' has no attribute 'core'", random API
    interrupt seed 15700); now it comes once the import is over."""
    module = sys.modules.get(name)
    if module is not None:  # imported whole before: nothing to hold
        return module
    with signals_held():
        return importlib.import_module(name)


@contextlib.contextmanager
def handled(signals: tuple[int, ...], handler: Any) -> Iterator[None]:
    """``handler`` for each of ``signals`` meanwhile, but for one ignored when the process
    started (``nohup``, a background job's SIGINT and SIGQUIT): that one stays ignored.
    SIGINT too: it was taken over all the same, so ``legdsl run ... &`` from a script (SIGINT
    ignored) was stopped by a SIGINT while simulating, though not while compiling."""
    previous: dict[int, Any] = {}
    try:
        for sig in signals:
            if signal.getsignal(sig) is not signal.SIG_IGN:
                previous[sig] = signal.signal(sig, handler)
    except ValueError:  # not the main thread (main() called from a thread): leave them be
        pass
    try:
        yield
    finally:
        _restore(previous)


def _restore(previous: dict[int, Any]) -> None:
    """The handlers ``previous`` put back, all of them, then what ``handler`` raised meanwhile.
    Blocked as they go back, but one that came just before runs ``handler`` at the next
    bytecode, which may be anywhere in here: its exception cut the restoring short and left
    the rest installed, to raise again after the command had ended (SIGTERM held down:
    "legdsl: terminated", then a traceback at the exit); so it is done again until whole."""
    raised: BaseException | None = None
    while True:
        try:
            with blocked(previous):
                for sig, before in previous.items():
                    signal.signal(sig, before)
            break
        except BaseException as e:  # the handler's own, for a signal that came just before
            raised = raised or e
    if raised is not None:
        raise raised
