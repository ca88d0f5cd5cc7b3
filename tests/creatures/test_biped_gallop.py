"""The biped's two gallops (creatures/biped.leg, controllers `gallop` and `gallop_human`):
the stance split into single, double and single support. Short runs keep this near 10 s."""

from __future__ import annotations

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
GALLOP = ("FLIGHT", "SINGLE_1", "DOUBLE", "SINGLE_2")
SETTLE = 2.5  # s: the run starts from rest


def _run(generated: Path, controller: str, time: float) -> RunResult:
    model = check_model(BIPED)
    dyn = load_dynamics(model, BIPED, generated)
    control = load_controller(model, controller, BIPED, generated)
    machine = StateMachine(model, control, {"speed": 1.5})
    return Simulation(model, dyn, RunOptions(duration=time), machine).run()


@pytest.fixture(scope="module")
def runs(generated: Path) -> dict[str, RunResult]:
    """One 6 s run of each gallop at 1.5 m/s, shared by every test below."""
    return {name: _run(generated, name, 6.0) for name in ("gallop", "gallop_human")}


@pytest.fixture(params=["gallop", "gallop_human"])
def gallop(request: pytest.FixtureRequest, runs: dict[str, RunResult]) -> tuple[str, RunResult]:
    return request.param, runs[request.param]


def test_the_gallop_does_not_fall(gallop: tuple[str, RunResult]) -> None:
    name, result = gallop
    assert result.status == "ok", f"{name}: {result.message}"
    tr = result.trajectory
    assert tr.t[-1] == pytest.approx(6.0, abs=0.01)
    assert tr.root_pos[:, 2].min() > 0.5
    assert tr.com[-1, 0] > 5.0


def test_the_states_cycle_single_double_single(gallop: tuple[str, RunResult]) -> None:
    name, result = gallop
    states = [e["state"] for e in result.events if e["kind"] == "state"]
    assert len(states) >= 24, name  # six strides and more
    for k, state in enumerate(states):
        assert state == GALLOP[k % 4], f"{name}: state {k} is {state}"


def test_double_support_occurs_and_the_speed_holds(gallop: tuple[str, RunResult]) -> None:
    name, result = gallop
    tr = result.trajectory
    late = tr.t >= SETTLE
    assert (tr.contact[late].astype(bool).sum(axis=1) == 2).mean() > 0.05, name
    metrics = compute_metrics(tr, t_from=SETTLE)
    assert metrics.value("double_support_duration") > 0.02, name
    assert metrics.value("single_support_duration") > 0.0, name
    assert metrics.value("running_speed") == pytest.approx(1.5, rel=0.15), name
    assert np.isfinite(metrics.value("pitch_magnitude"))


def test_the_human_gallop_pitches_much_less(runs: dict[str, RunResult]) -> None:
    """The paper: "Pitching of the body in response to swinging of the legs is greatly
    reduced in the second form of galloping" (20 s runs: 9.1 against 1.9 deg)."""
    pitch = {
        name: compute_metrics(result.trajectory, t_from=SETTLE).value("pitch_magnitude")
        for name, result in runs.items()
    }
    assert pitch["gallop"] > 6
    assert pitch["gallop_human"] < pitch["gallop"] / 3
