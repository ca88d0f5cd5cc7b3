"""The hopper's speed command (creatures/hopper.leg, controller `hop`): each stride aims at
most `max_step` (1.5 m/s) beyond the last stride's aim from standing or hopping in place, and
`moving_step` (0.3 m/s) once moving, so 4 m/s from standing comes in ten strides. Placed for
2 m/s at once, the hopper fell in its first stride, and aiming 1.5 m/s further every stride,
in its second from 2.5 m/s up. A command within reach runs exactly as without the limit, to
the bit."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from conftest import CREATURES

from legdsl.pipeline.session import RunSession
from legdsl.sim.run_loop import RunOptions
from legdsl.sim.trajectory import ARRAYS

UNLIMITED = ["max_step=100m/s", "moving_step=100m/s"]


def _run(generated: Path, settings: list[str], time: float):  # type: ignore[no-untyped-def]
    session = RunSession.from_file(CREATURES / "hopper.leg", generated=generated)
    return session.run("hop", settings, options=RunOptions(duration=time), backend="c").result


@pytest.mark.parametrize("speed", [2.0, -2.0, 4.0, -4.0])
def test_up_to_four_metres_a_second_from_standing_holds(generated: Path, speed: float) -> None:
    result = _run(generated, [f"speed={speed}m/s"], 20.0)
    assert result.status == "ok", result.message
    tr = result.trajectory
    later = tr.t >= 10.0
    x, t = tr.com[later, 0], tr.t[later]
    assert (x[-1] - x[0]) / (t[-1] - t[0]) == pytest.approx(speed, rel=0.03)


def test_without_the_limit_two_metres_a_second_falls_at_once(generated: Path) -> None:
    result = _run(generated, ["speed=2m/s", *UNLIMITED], 5.0)
    assert result.status == "fell" and result.trajectory.t[-1] < 1.5, result.message


def test_aiming_one_and_a_half_metres_a_second_further_every_stride_falls(
    generated: Path,
) -> None:
    result = _run(generated, ["speed=2.5m/s", "moving_step=1.5m/s"], 5.0)
    assert result.status == "fell" and result.trajectory.t[-1] < 1.5, result.message


def test_three_metres_a_second_asked_while_hopping_in_place_holds(generated: Path) -> None:
    result = _run(generated, ["speed=0m/s", "speed=3m/s@5s"], 20.0)
    assert result.status == "ok", result.message
    assert result.trajectory.com[-1, 0] > 25.0  # 3 m/s for most of the last 15 s


@pytest.mark.parametrize("settings", [["speed=1.5m/s"], ["speed=1m/s", "speed=1.25m/s@4s"]])
def test_a_command_within_reach_runs_as_without_the_limit(
    generated: Path, settings: list[str]
) -> None:
    limited = _run(generated, settings, 8.0).trajectory
    plain = _run(generated, [*settings, *UNLIMITED], 8.0).trajectory
    for name in ARRAYS:
        assert np.array_equal(getattr(limited, name), getattr(plain, name)), name
