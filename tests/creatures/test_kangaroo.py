"""The kangaroo's hop controller (creatures/kangaroo.leg, 'Kangaroo control' of the paper).

docs/kangaroo.md has the 20 s runs; these tests run a few strides: the
kangaroo leaves the ground, the state machine cycles in Figure 4 order, and
at 2 and 3 m/s it hops and holds the commanded speed within 5% from 3 to 5 s.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from conftest import CREATURES

from legdsl.check.source import check_model
from legdsl.pipeline.generated import load_controller, load_dynamics
from legdsl.sim.machine import StateMachine
from legdsl.sim.run_loop import RunOptions
from legdsl.sim.simulate import Simulation

KANGAROO = CREATURES / "kangaroo.leg"
FIGURE_4 = ("FLIGHT", "LOADING", "COMPRESSION", "THRUST", "UNLOADING")


def _hop(generated: Path, time: float, **inputs: float):  # type: ignore[no-untyped-def]
    model = check_model(KANGAROO)
    dyn = load_dynamics(model, KANGAROO, generated)
    control = load_controller(model, "hop", KANGAROO, generated)
    machine = StateMachine(model, control, inputs)
    return Simulation(model, dyn, RunOptions(duration=time), machine).run()


@pytest.fixture(scope="module")
def first_hops(generated: Path):  # type: ignore[no-untyped-def]
    return _hop(generated, 1.0, speed=5.0)


def test_the_kangaroo_leaves_the_ground(first_hops) -> None:  # type: ignore[no-untyped-def]
    assert first_hops.status == "ok", first_hops.message
    tr = first_hops.trajectory
    toe = tr.contact[:, tr.contact_names.index("toe")]
    tail = tr.contact[:, tr.contact_names.index("tail_end")]
    airborne = (toe == 0) & (tail == 0)
    # the longest flight after the first stance lasts more than 0.1 s
    runs = np.diff(np.flatnonzero(np.diff(np.r_[0, airborne.astype(int), 0])))[::2]
    dt = tr.t[1] - tr.t[0]
    assert runs.max() * dt > 0.1
    assert tr.com[:, 2].max() > tr.com[0, 2] + 0.1  # the hop rises well above standing


def test_the_state_machine_cycles_in_figure_4_order(first_hops) -> None:  # type: ignore[no-untyped-def]
    states = [e["state"] for e in first_hops.events if e["kind"] == "state"]
    assert states[:6] == [*FIGURE_4, "FLIGHT"]
    for a, b in zip(states, states[1:], strict=False):
        assert FIGURE_4.index(b) == (FIGURE_4.index(a) + 1) % 5


@pytest.mark.parametrize("speed", [2.0, 3.0])
def test_the_kangaroo_hops_and_holds_its_speed(generated: Path, speed: float) -> None:
    run = _hop(generated, 5.0, speed=speed)
    assert run.status == "ok", run.message
    tr = run.trajectory
    late = tr.t >= 3.0
    # hops: the toe leaves the ground at least once per 0.5 s, and is down only part of the time
    toe = tr.contact[late, tr.contact_names.index("toe")] > 0
    liftoffs = np.flatnonzero(np.diff(toe.astype(int)) == -1)
    assert len(liftoffs) >= 4
    assert 0.15 < toe.mean() < 0.6
    # holds speed: the mean forward speed of the mass centre from 3 s within 5% of the command
    x = tr.com[late, 0]
    mean = (x[-1] - x[0]) / (tr.t[late][-1] - tr.t[late][0])
    assert abs(mean - speed) < 0.05 * speed, mean
    # and the machine went round in Figure 4 order the whole time
    states = [e["state"] for e in run.events if e["kind"] == "state"]
    assert len(states) > 5 * 8
    for a, b in zip(states, states[1:], strict=False):
        assert FIGURE_4.index(b) == (FIGURE_4.index(a) + 1) % 5
