"""Helpers for runtime tests: a .leg text compiled into a temporary generated tree and run through
the run session (``legdsl.pipeline.session``), as ``legdsl run`` does."""

from __future__ import annotations

import contextlib
import io
import os
from pathlib import Path

import numpy as np
import pytest

from legdsl.cli import main
from legdsl.pipeline.session import RunSession
from legdsl.sim.c_backend import available
from legdsl.sim.run_loop import RunOptions, RunResult
from legdsl.sim.trajectory import ARRAYS

# A module of C-backend runs: skipped, saying how to get one, where no C compiler is found.
needs_c_compiler = pytest.mark.skipif(
    available() is not None,
    reason=f"the C backend's tests need a C compiler: {available()} (apt-get install gcc)",
)

_CACHE: dict[str, RunSession] = {}


def child_pids(parent: int | None = None) -> set[int]:
    """The processes whose parent is ``parent`` (this process by default), zombies too: read
    from Linux's /proc."""
    parent = os.getpid() if parent is None else parent
    found = set()
    for stat in Path("/proc").glob("[0-9]*/stat"):
        with contextlib.suppress(OSError, IndexError, ValueError):
            if int(stat.read_text().rsplit(")", 1)[1].split()[1]) == parent:
                found.add(int(stat.parent.name))
    return found


def legdsl_in_process(argv: list[str]) -> tuple[int, str]:
    """``legdsl ARGV`` in this process: its exit status and what it wrote to stderr."""
    err, out = io.StringIO(), io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(out):
        try:
            code = main(argv)
        except SystemExit as e:  # argparse's own usage errors
            code = e.code if isinstance(e.code, int) else 2
    return code, err.getvalue()


COPIED = "was compiled before: its modules are copied from legdsl's cache"


def is_compile_notice(line: str) -> bool:
    """A line saying that a run's generated code was compiled, or copied from legdsl's cache:
    which of the two depends on what ran before in the same cache, not on the run."""
    return "; compiling " in line or COPIED in line


def compile_text(text: str, tmp: Path, name: str) -> RunSession:
    """A session on ``text`` (cached per text, so a module compiles once per test session)."""
    if text in _CACHE:
        return _CACHE[text]
    tmp.mkdir(parents=True, exist_ok=True)
    source = tmp / f"{name}.leg"
    source.write_text(text)
    _CACHE[text] = RunSession.from_file(source, generated=tmp / "generated")
    return _CACHE[text]


def run(session: RunSession, **options: object) -> RunResult:
    """A passive run (no controller) with these ``RunOptions``."""
    return session.run(options=RunOptions(**options)).result  # type: ignore[arg-type]


def assert_same(python: RunResult, c: RunResult) -> None:
    """The same run: status, message, steps, events, and every recorded array byte for byte."""
    assert (c.status, c.message, c.cause) == (python.status, python.message, python.cause)
    assert c.steps == python.steps and c.sim_time == python.sim_time
    assert c.events == python.events
    assert c.stop_time == python.stop_time
    for name in ARRAYS:
        a, b = getattr(python.trajectory, name), getattr(c.trajectory, name)
        assert a.shape == b.shape, name
        if a.tobytes() != b.tobytes():
            differ = np.argwhere(~((a == b) | (np.isnan(a) & np.isnan(b))))
            pytest.fail(f"{name} differs first at {differ[:1].tolist()}: {a[tuple(differ[0])]!r} "
                        f"(python) vs {b[tuple(differ[0])]!r} (c)")  # fmt: skip
