"""The hopper's speed command from standing (creatures/hopper.leg, controller `hop`): each
stride aims at most `max_step` (1.5 m/s) beyond the last stride's aim, so 2 m/s from standing
comes in two steps; placed for 2 m/s at once, the hopper fell in its first stride. A command
within reach runs exactly as without the limit, to the bit."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from conftest import CREATURES

from legdsl.pipeline.session import RunSession
from legdsl.sim.run_loop import RunOptions
from legdsl.sim.trajectory import ARRAYS

UNLIMITED = "max_step=100m/s"


def _run(generated: Path, settings: list[str], time: float):  # type: ignore[no-untyped-def]
    session = RunSession.from_file(CREATURES / "hopper.leg", generated=generated)
    return session.run("hop", settings, options=RunOptions(duration=time), backend="c").result


@pytest.mark.parametrize("speed", [2.0, -2.0])
def test_two_metres_a_second_from_standing_holds(generated: Path, speed: float) -> None:
    result = _run(generated, [f"speed={speed}m/s"], 20.0)
    assert result.status == "ok", result.message
    tr = result.trajectory
    later = tr.t >= 10.0
    x, t = tr.com[later, 0], tr.t[later]
    assert (x[-1] - x[0]) / (t[-1] - t[0]) == pytest.approx(speed, rel=0.03)


def test_without_the_limit_two_metres_a_second_falls_at_once(generated: Path) -> None:
    result = _run(generated, ["speed=2m/s", UNLIMITED], 5.0)
    assert result.status == "fell" and result.trajectory.t[-1] < 1.5, result.message


@pytest.mark.parametrize("settings", [["speed=1.5m/s"], ["speed=1m/s", "speed=2.5m/s@4s"]])
def test_a_command_within_reach_runs_as_without_the_limit(
    generated: Path, settings: list[str]
) -> None:
    limited = _run(generated, settings, 8.0).trajectory
    plain = _run(generated, [*settings, UNLIMITED], 8.0).trajectory
    for name in ARRAYS:
        assert np.array_equal(getattr(limited, name), getattr(plain, name)), name
