"""The biped's speed command (creatures/biped.leg, controller `run`): each stride aims at most
`max_step` (2.5 m/s) beyond the speed measured over the last step at the controller's first
liftoff, and `moving_step` (0.5 m/s) beyond the last stride's aim after, so 4.5 m/s from
standing comes in five strides. Placed for 4 m/s at once, the biped fell at 2.7 s. A command
within reach runs exactly as without the limit, to the bit; a controller taking over from
another counts its first reach from the speed it finds (docs/biped.md, "Measurements"). The
speed table's 4 and 4.5 m/s rows are checked in test_doc_tables.py."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from conftest import CREATURES
from runtime_helpers import needs_c_compiler

from legdsl.pipeline.session import RunSession
from legdsl.sim.run_loop import RunOptions, RunResult
from legdsl.sim.trajectory import ARRAYS

pytestmark = needs_c_compiler

UNLIMITED = ["max_step=100m/s", "moving_step=100m/s"]


def _run(
    generated: Path, settings: list[str], time: float, switches: tuple[str, ...] = ()
) -> RunResult:
    session = RunSession.from_file(CREATURES / "biped.leg", generated=generated)
    options = RunOptions(duration=time)
    return session.run("run", settings, options=options, switches=switches, backend="c").result


def test_without_the_limit_four_metres_a_second_from_standing_falls(generated: Path) -> None:
    result = _run(generated, ["speed=4m/s", *UNLIMITED], 5.0)
    assert result.status == "fell" and result.trajectory.t[-1] < 3.5, result.message


def test_four_metres_a_second_asked_while_running_in_place_holds(generated: Path) -> None:
    result = _run(generated, ["speed=0m/s", "speed=4m/s@3s"], 14.0)
    assert result.status == "ok", result.message
    tr = result.trajectory
    later = tr.t >= 9.0
    x, t = tr.com[later, 0], tr.t[later]
    assert (x[-1] - x[0]) / (t[-1] - t[0]) == pytest.approx(4.0, rel=0.03)


def test_each_stride_aims_at_most_half_a_metre_a_second_further(generated: Path) -> None:
    """From standing at 4 m/s the aims recorded at the first FLIGHTs are 2.5, 3, 3.5 and
    4 m/s: each read from a run stopped just after that FLIGHT began."""
    session = RunSession.from_file(CREATURES / "biped.leg", generated=generated)
    whole = session.run("run", ["speed=4m/s"], options=RunOptions(duration=2.0), backend="c")
    flights = [e["t"] for e in whole.result.events if e.get("state") == "FLIGHT"]
    aims = []
    for t in flights[:5]:
        options = RunOptions(duration=t + 0.01)
        plan = session.prepare("run", ["speed=4m/s"], options=options, backend="c")
        assert plan.sim.run().status == "ok"
        machine = plan.sim.controller
        aims.append(dict(zip(machine.module.RECORDS, machine.records, strict=True))["speed_aim"])
    assert aims == pytest.approx([2.5, 3.0, 3.5, 4.0, 4.0])


@pytest.mark.parametrize(
    "settings", [["speed=2.5m/s"], ["speed=1.5m/s", "speed=2m/s@3s", "speed=1.6m/s@5s"]]
)
def test_a_command_within_reach_runs_as_without_the_limit(
    generated: Path, settings: list[str]
) -> None:
    limited = _run(generated, settings, 7.0).trajectory
    plain = _run(generated, [*settings, *UNLIMITED], 7.0).trajectory
    for name in ARRAYS:
        assert np.array_equal(getattr(limited, name), getattr(plain, name)), name


def test_taking_over_from_the_gallop_counts_from_the_speed_it_finds(generated: Path) -> None:
    """Back from a 1.5 m/s gallop, 3.5 m/s is within `max_step` of the measured speed: the run
    places its first foot for 3.5 m/s, as without the limit (from standing it would not)."""
    settings = ["speed=1.5m/s", "speed=3.5m/s@4s"]
    switches = ("0.1s=gallop", "4s=run")
    limited = _run(generated, settings, 6.0, switches).trajectory
    plain = _run(generated, [*settings, "run.max_step=100m/s", "run.moving_step=100m/s"], 6.0,
                 switches).trajectory  # fmt: skip
    for name in ARRAYS:
        assert np.array_equal(getattr(limited, name), getattr(plain, name)), name
