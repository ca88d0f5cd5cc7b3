"""``integral(INPUT)``: an input's commands added up over the run's time, exactly, on both
backends; the shipped controllers aim at ``heading + integral(turn_rate)``, so a turn rate
changed mid-run turns on from the heading reached (``heading + turn_rate * time`` jumped by
the new rate times the whole run's time), and a controller taking over carries it on."""

from __future__ import annotations

import math
import random

import numpy as np
import pytest
from conftest import CREATURES, GENERATED

from legdsl.pipeline.session import RunSession
from legdsl.sim.machine import Integral
from legdsl.sim.run_loop import RunOptions
from legdsl.sim.trajectory import ARRAYS


def test_an_unchanged_command_integrates_to_its_value_times_the_time_bit_for_bit() -> None:
    rng = random.Random(7)
    for _ in range(1000):
        value, t = rng.uniform(-5, 5), rng.uniform(0, 100)
        assert Integral().value(value, t) == value * t


def test_changes_add_up_what_each_value_held_for() -> None:
    integral = Integral()
    integral.change(2.0, 2.0, 1.0)  # a command repeating the value changes nothing
    assert (integral.total, integral.since) == (0.0, 0.0)
    integral.change(2.0, -1.0, 3.0)
    integral.change(-1.0, 4.0, 4.0)
    assert integral.value(4.0, 6.0) == pytest.approx(2.0 * 3 - 1.0 * 1 + 4.0 * 2)


def _yaw_at(result, t: float) -> float:
    traj = result.trajectory
    return math.degrees(float(traj.root_rpy[int(np.abs(traj.t - t).argmin()), 2]))


def _trot(backend: str, settings: list[str], switch: list[str] | None = None):
    if backend == "c":
        from legdsl.sim.c_library import available

        if available() is not None:
            pytest.skip(f"needs a C compiler: {available()}")
    session = RunSession.from_file(CREATURES / "quadruped.leg", generated=GENERATED)
    options = RunOptions(duration=3.5)
    return session.run(
        "trot", settings, options=options, backend=backend, switches=switch or ()
    ).result


@pytest.fixture(scope="module")
def turned_back():
    settings = ["turn_rate=20deg/s", "turn_rate=-20deg/s@2s"]
    return {backend: _trot(backend, settings) for backend in ("python", "c")}


def test_a_turn_rate_changed_mid_run_turns_on_from_the_heading_reached(turned_back) -> None:
    result = turned_back["python"]
    assert result.status == "ok", result.message
    # 40 deg at 2 s, then back at 20 deg/s: the aim is 30 deg at 2.5 s and 20 deg at 3 s
    # (turn_rate * time would have aimed at -40 deg at 2 s and -60 deg at 3 s)
    assert 30 < _yaw_at(result, 2.0) < 45
    assert min(_yaw_at(result, t) for t in np.arange(2.0, 2.5, 0.05)) > 25
    assert 10 < _yaw_at(result, 3.0) < 35


def test_the_c_backend_integrates_as_python_does(turned_back) -> None:
    py, c = turned_back["python"], turned_back["c"]
    assert (py.status, py.steps, py.events) == (c.status, c.steps, c.events)
    for name in ARRAYS:
        assert getattr(py.trajectory, name).tobytes() == getattr(c.trajectory, name).tobytes()


@pytest.mark.parametrize("backend", ["python", "c"])
def test_a_controller_taking_over_carries_the_integral_on(backend: str) -> None:
    # 20 deg/s for 1 s, then straight on at 20 deg: the pace taking over at 2 s keeps that
    # heading (its own integral from 0 would aim at 0 deg)
    settings = ["turn_rate=20deg/s", "turn_rate=0deg/s@1s"]
    result = _trot(backend, settings, ["2s=pace"])
    assert result.status == "ok", result.message
    assert all(12 < _yaw_at(result, t) < 28 for t in (1.5, 2.5, 3.0, 3.5))
