"""The 3D biped runs (creatures/biped.leg, controller `run`): Figure 4 with active and idle
legs that swap at each flight, eq. (3) placement in both directions, eq. (4) posture in
pitch and roll, and a heading servo. Short runs (a few strides) keep this under ~15 s."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from conftest import CREATURES

from legdsl.analysis.metrics import compute_metrics
from legdsl.check.source import check_model
from legdsl.pipeline.generated import load_controller, load_dynamics
from legdsl.sim.machine import StateMachine
from legdsl.sim.run_loop import RunOptions, RunResult
from legdsl.sim.simulate import Simulation

BIPED = CREATURES / "biped.leg"
FIGURE_4 = ("FLIGHT", "LOADING", "COMPRESSION", "THRUST", "UNLOADING")
SETTLE = 3.0  # s: the run starts from rest; its speed is measured from here on


def _run(generated: Path, speed: float, time: float) -> RunResult:
    model = check_model(BIPED)
    dyn = load_dynamics(model, BIPED, generated)
    control = load_controller(model, "run", BIPED, generated)
    machine = StateMachine(model, control, {"speed": speed})
    return Simulation(model, dyn, RunOptions(duration=time), machine).run()


@pytest.fixture(scope="module")
def run_1_5(generated: Path) -> RunResult:
    return _run(generated, 1.5, 7.0)


def test_the_biped_runs_without_falling(run_1_5: RunResult) -> None:
    assert run_1_5.status == "ok", run_1_5.message
    tr = run_1_5.trajectory
    assert tr.t[-1] == pytest.approx(7.0, abs=0.01)
    assert tr.root_pos[:, 2].min() > 0.55  # the trunk stays up
    assert np.abs(np.degrees(tr.root_rpy[:, :2])).max() < 25  # roll and pitch
    assert np.abs(np.degrees(tr.root_rpy[:, 2])).max() < 10  # heading 0 held
    assert tr.com[-1, 0] > 7.0  # it went somewhere


def test_the_states_cycle_in_order_and_the_legs_take_turns(run_1_5: RunResult) -> None:
    events = run_1_5.events
    states = [e["state"] for e in events if e["kind"] == "state"]
    assert len(states) >= 50  # 10 steps and more
    for k, state in enumerate(states):
        assert state == FIGURE_4[k % 5], f"state {k} is {state}"
    # Each LOADING is entered at the touchdown of the active leg: the foot that touched
    # down last before it alternates, left (the first active leg), right, left...
    feet = []
    last = None
    for e in events:
        if e["kind"] == "touchdown":
            last = e["contact"]
        elif e["kind"] == "state" and e["state"] == "LOADING":
            feet.append(last)
    assert len(feet) >= 10
    assert feet == [("toe_l", "toe_r")[k % 2] for k in range(len(feet))]
    # ...and the idle foot never touches: no sample has both feet down.
    assert not (run_1_5.trajectory.contact.sum(axis=1) == 2).any()


def test_the_speed_holds_at_1_5_m_s(run_1_5: RunResult) -> None:
    metrics = compute_metrics(run_1_5.trajectory, t_from=SETTLE)
    assert metrics.n_strides >= 3
    assert metrics.value("running_speed") == pytest.approx(1.5, rel=0.05)


def test_the_speed_holds_at_3_m_s(generated: Path) -> None:
    result = _run(generated, 3.0, 6.0)
    assert result.status == "ok", result.message
    metrics = compute_metrics(result.trajectory, t_from=SETTLE)
    assert metrics.n_strides >= 2
    assert metrics.value("running_speed") == pytest.approx(3.0, rel=0.05)
    assert math.isfinite(metrics.value("roll_magnitude"))


def test_a_steady_turn_runs_a_5_m_circle(generated: Path) -> None:
    """speed / turn_rate = 1.5 m/s / 0.3 rad/s: a circle of 5 m radius (a third of a lap here)."""
    model = check_model(BIPED)
    dyn = load_dynamics(model, BIPED, generated)
    control = load_controller(model, "run", BIPED, generated)
    machine = StateMachine(model, control, {"speed": 1.5, "turn_rate": 0.3})
    result = Simulation(model, dyn, RunOptions(duration=8.0), machine).run()
    assert result.status == "ok", result.message
    tr = result.trajectory
    late = tr.t >= SETTLE
    x, y = tr.com[late, 0], tr.com[late, 1]
    # least-squares circle: x^2 + y^2 + D x + E y + F = 0
    d, e, f = np.linalg.lstsq(np.c_[x, y, np.ones_like(x)], -(x**2 + y**2), rcond=None)[0]
    radius = math.sqrt(d * d / 4 + e * e / 4 - f)
    assert radius == pytest.approx(5.0, rel=0.1)
    heading_error = np.angle(np.exp(1j * (tr.root_rpy[late, 2] - 0.3 * tr.t[late])))
    assert np.degrees(np.abs(heading_error)).max() < 10
