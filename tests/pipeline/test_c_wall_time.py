"""A C run's wall time is its run loop's: the drift guard's one-time read of the Python
sources (``legdsl.sim.c_mirrors``, ~40 ms) is done before the clock starts, so ``legdsl run``'s
real-time factor is the benchmark's (it was 3 to 18 times lower in a fresh process)."""

from __future__ import annotations

import time
from collections.abc import Callable
from pathlib import Path

import pytest

from legdsl.pipeline.options import RunOptions
from legdsl.pipeline.session import RunSession
from legdsl.sim import c_mirrors

ROOT = Path(__file__).resolve().parents[2]


def test_the_drift_guard_is_read_before_the_run_is_timed(
    generated: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    session = RunSession.from_file(ROOT / "creatures" / "hopper.leg", generated=generated)
    real = c_mirrors.digest

    def slow(functions: list[Callable[..., object]]) -> str:
        time.sleep(0.5)  # a fresh process's read, made long enough to see
        return real(functions)

    monkeypatch.setattr(c_mirrors, "digest", slow)
    c_mirrors.machine_matches.cache_clear()
    try:
        run = session.run("hop", options=RunOptions(duration=0.2), backend="c")
    finally:
        c_mirrors.machine_matches.cache_clear()  # the next reader reads the real sources
    assert run.result.status == "ok"
    assert run.result.wall_time < 0.25, run.result.wall_time


def test_the_summary_says_the_wall_time_is_the_simulations(generated: Path) -> None:
    """A run along 200,000 waypoints said 'wall time 3.31 s' and took 3 minutes (its path
    report after the run): the row says what it times, the simulating alone."""
    session = RunSession.from_file(ROOT / "creatures" / "hopper.leg", generated=generated)
    run = session.run("hop", options=RunOptions(duration=0.05))
    (row,) = [r for r in run.summary().splitlines() if r.strip().startswith("wall time")]
    assert f"{run.result.wall_time:.2f} s simulating (real-time factor" in row
