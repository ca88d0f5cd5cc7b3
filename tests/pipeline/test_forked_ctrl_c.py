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
