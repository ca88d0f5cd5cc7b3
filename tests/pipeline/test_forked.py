"""Work done in other processes, and done here whatever they could not do."""

from __future__ import annotations

import multiprocessing
import os
import pickle
import sys
import threading
import time
from pathlib import Path

import pytest

from legdsl.pipeline.forked import Forked

PARENT = os.getpid()


def _square(n: int) -> bytes:
    return pickle.dumps((n * n, os.getpid()))


def _dies_elsewhere(item: tuple[int, int]) -> bytes:
    n, parent = item  # the parent's pid handed over: a spawned process imports this anew
    if os.getpid() != parent:
        os._exit(3)  # killed, or out of memory: no answer, no exception
    return _square(n)


def _lowering_imported(n: int) -> bytes:
    return pickle.dumps(("legdsl.lower.control" in sys.modules, os.getpid()))


def _refuses(n: int) -> bytes:
    raise ValueError(f"no {n}")


def _large_noted(item: tuple[int, str]) -> bytes:
    n, notes = item
    with open(notes, "a", encoding="utf-8") as f:
        f.write(f"{n}\n")
    return pickle.dumps((n, b"x" * 1_000_000))  # more than a pipe holds


def _results(forked: Forked, count: int) -> list[tuple[int, int]]:
    try:
        return [pickle.loads(forked.result(k)) for k in range(count)]
    finally:
        forked.close()


@pytest.mark.parametrize("processes", [1, 2, 5])
def test_each_item_is_worked_in_another_process(processes: int) -> None:
    answers = _results(Forked(_square, range(5), processes), 5)
    assert [value for value, _ in answers] == [0, 1, 4, 9, 16]
    workers = {pid for _, pid in answers}  # forked, or spawned where threads run (pytest -n)
    assert PARENT not in workers and len(workers) == min(processes, 5)


def test_a_process_that_dies_leaves_its_items_to_this_one() -> None:
    answers = _results(Forked(_dies_elsewhere, [(n, PARENT) for n in range(4)], 2), 4)
    assert answers == [(n * n, PARENT) for n in range(4)]


def test_processes_that_cannot_start_leave_everything_to_this_one(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    def refused(self: object) -> None:
        raise OSError(12, "Cannot allocate memory")

    monkeypatch.setattr(multiprocessing.context.ForkProcess, "start", refused)
    monkeypatch.setattr(multiprocessing.context.SpawnProcess, "start", refused)
    monkeypatch.setattr(multiprocessing.context.ForkServerProcess, "start", refused)  # threaded
    answers = _results(Forked(_square, range(3), 2), 3)
    assert answers == [(n * n, PARENT) for n in range(3)]


def test_an_exception_in_another_process_is_raised_here() -> None:
    forked = Forked(_refuses, range(2), 1)
    try:
        with pytest.raises(ValueError, match="no 0"):
            forked.result(0)
    finally:
        forked.close()


def test_a_process_works_all_its_items_while_this_one_is_busy(tmp_path: Path) -> None:
    """The compiler reads the controllers only once it has lowered the dynamics: a process
    that sent each result (some 300 KB, more than a pipe holds) as it came stood still after
    the first until then."""
    notes = tmp_path / "worked"
    forked = Forked(_large_noted, [(n, str(notes)) for n in range(3)], 1)
    try:
        deadline = time.monotonic() + 30  # no result read meanwhile, as while lowering
        while time.monotonic() < deadline and not (
            notes.exists() and len(notes.read_text().split()) == 3
        ):
            time.sleep(0.05)
        assert notes.read_text().split() == ["0", "1", "2"]
        assert [pickle.loads(forked.result(k))[0] for k in range(3)] == [0, 1, 2]
    finally:
        forked.close()


def test_a_threaded_process_imports_the_lowering_once_not_in_each_process() -> None:
    """Where this process has threads (a notebook's kernel, a Dask worker, a test runner),
    forking may deadlock: the processes were spawned, and each imported the compiler's
    lowering again (sympy: some 1.5 s a process, a fifth of the test suite's time). They come
    from a fork server, which imported it once: it is there before their work is unpickled
    (this work's module imports none of it)."""
    held = threading.Event()
    thread = threading.Thread(target=held.wait)
    thread.start()
    try:
        for _ in range(2):  # the server started by the first, used again by the second
            forked = Forked(_lowering_imported, [0, 1], 2)
            answers = [pickle.loads(forked.result(k)) for k in range(2)]
            forked.close()
            assert all(imported and pid != os.getpid() for imported, pid in answers), answers
    finally:
        held.set()
        thread.join()
