"""``LEGDSL_COMPILE_JOBS=abc`` or ``=-3`` was silently taken as one process per core, where
``LEGDSL_BACKEND=fortran`` is refused: a value that is no count of processes is refused
now, saying what to give."""

from __future__ import annotations

import os

import pytest

from legdsl.lang.errors import UsageError
from legdsl.pipeline.compile import compile_jobs


@pytest.mark.parametrize("value", ["abc", "-3", "0", "2.5", "٣"])
def test_a_value_that_is_no_count_of_processes_is_refused(
    monkeypatch: pytest.MonkeyPatch, value: str
) -> None:
    monkeypatch.setenv("LEGDSL_COMPILE_JOBS", value)
    with pytest.raises(UsageError) as e:
        compile_jobs()
    assert str(e.value).startswith(f"LEGDSL_COMPILE_JOBS={value}: give the number of processes")
    assert "docs/compiler.md" in str(e.value)


@pytest.mark.parametrize(("value", "jobs"), [("1", 1), (" 3 ", 3), ("", os.cpu_count() or 1)])
def test_a_count_or_nothing_is_taken(
    monkeypatch: pytest.MonkeyPatch, value: str, jobs: int
) -> None:
    monkeypatch.setenv("LEGDSL_COMPILE_JOBS", value)
    assert compile_jobs() == jobs
