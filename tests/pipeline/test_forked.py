"""Work done in other processes, and done here whatever they could not do."""

from __future__ import annotations

import multiprocessing
import os
import pickle

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


def _refuses(n: int) -> bytes:
    raise ValueError(f"no {n}")


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
    answers = _results(Forked(_square, range(3), 2), 3)
    assert answers == [(n * n, PARENT) for n in range(3)]


def test_an_exception_in_another_process_is_raised_here() -> None:
    forked = Forked(_refuses, range(2), 1)
    try:
        with pytest.raises(ValueError, match="no 0"):
            forked.result(0)
    finally:
        forked.close()
