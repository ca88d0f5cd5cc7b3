"""Ctrl-C in a process of several threads (a Jupyter kernel: its Ctrl-C is a SIGINT to the
kernel, which any of its threads may take) while legdsl starts processes."""

from __future__ import annotations

import os
import signal
import threading
import time
from collections.abc import Iterator
from contextlib import contextmanager

import pytest
from runtime_helpers import child_pids

from legdsl.pipeline import forked
from legdsl.pipeline.forked import Forked
from legdsl.signals import signals_held


def test_ctrl_c_taken_by_another_thread_is_held_back_too() -> None:
    """The block covered only the thread that held it: another thread took the SIGINT and
    Python raised KeyboardInterrupt inside the held block all the same."""
    go = threading.Event()
    other = threading.Thread(target=lambda: (go.wait(), os.kill(os.getpid(), signal.SIGINT)))
    other.start()  # before the block: its mask lets SIGINT in
    reached = False
    with pytest.raises(KeyboardInterrupt), signals_held():
        go.set()
        other.join()
        for _ in range(1000):  # many bytecodes: where the signal would land
            time.sleep(0.0001)
        reached = True
    assert reached


def test_ctrl_c_held_back_under_a_handler_of_its_own_is_given_to_it_after() -> None:
    """Under the console script's handler (or a kernel's) the hold noted nothing: the handler
    was left in place and raised inside the held block."""
    taken: list[int] = []

    def own(signum: int, frame: object) -> None:
        taken.append(signum)

    handler = signal.signal(signal.SIGINT, own)
    try:
        with signals_held():
            threading.Thread(target=os.kill, args=(os.getpid(), signal.SIGINT)).start()
            for _ in range(1000):
                time.sleep(0.0001)
            assert taken == []
        assert taken == [signal.SIGINT]
        assert signal.getsignal(signal.SIGINT) is own
    finally:
        signal.signal(signal.SIGINT, handler)


def _answer_now(item: int) -> bytes:
    return str(item).encode()


def sleepy(item: object) -> bytes:
    time.sleep(30)
    return b""


def test_ctrl_c_as_processes_start_leaves_none_behind(monkeypatch: pytest.MonkeyPatch) -> None:
    """Ctrl-C landing as the second process starts (raised where the hold ends): the first
    was left lowering, orphaned, in a notebook's kernel."""
    held = forked.signals_held
    starts = []

    @contextmanager
    def interrupted_at_the_second() -> Iterator[None]:
        with held():
            yield
        starts.append(1)
        if len(starts) == 2:
            raise KeyboardInterrupt

    monkeypatch.setattr(forked, "signals_held", interrupted_at_the_second)
    before = child_pids()
    with pytest.raises(KeyboardInterrupt):
        Forked(sleepy, [1, 2], 2)
    assert child_pids() - before == set()


def test_ctrl_c_while_closing_comes_after_every_process_is_reaped_and_closed(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """A Ctrl-C landing in ``close``: in ``join`` it was swallowed (the join tried again), and
    between a child's reaping and its note it left the process "still running" to
    multiprocessing; in the finalizer that closes a process's own pipes, which the garbage
    collector ran later, it was "Exception ignored in: <Finalize object, dead>" and lost
    (random API interrupts, seed 17400). Now it comes after all is closed."""
    work = Forked(_answer_now, range(2), 2)
    assert [work.result(k) for k in range(2)] == [b"0", b"1"]
    join = type(work._processes[0]).join

    sent: list[int] = []

    def interrupted_join(self: object, timeout: float | None = None) -> None:
        if not sent:  # one Ctrl-C, in the first join
            sent.append(signal.SIGINT)
            os.kill(os.getpid(), signal.SIGINT)
        join(self, timeout)  # type: ignore[arg-type]

    monkeypatch.setattr(type(work._processes[0]), "join", interrupted_join)
    with pytest.raises(KeyboardInterrupt):
        work.close()
    for process in work._processes:
        with pytest.raises(ValueError, match="process object is closed"):
            process.is_alive()  # closed: its finalizer ran inside close(), held
