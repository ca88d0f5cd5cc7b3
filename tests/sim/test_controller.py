"""Controllers: lowering (roles, swaps, actions), the kinematic solve, and a hopper that hops at speed."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from conftest import CREATURES

from legdsl.analysis.metrics import compute_metrics
from legdsl.check.source import check_model
from legdsl.cli import main
from legdsl.lower.control import lower_controller
from legdsl.pipeline.generated import load_controller, load_dynamics
from legdsl.sim.kinematics import FootPlacer, clip_step, solve_small
from legdsl.sim.machine import InputChange, StateMachine
from legdsl.sim.run_loop import RunOptions
from legdsl.sim.simulate import Simulation

HOPPER = CREATURES / "hopper.leg"
FIGURE_4 = ("FLIGHT", "LOADING", "COMPRESSION", "THRUST", "UNLOADING")

TWO_LEGS = """
creature walker {
  planar
  body trunk free { mass 10 kg  inertia 0.5 kg*m^2  initial x = 0 m, z = 1.0 m }
  body a_leg on trunk via prismatic a { length 0.5 m  com 0.25 m  mass 0.5 kg  inertia 0.01 kg*m^2 }
  body b_leg on trunk via prismatic b { length 0.5 m  com 0.25 m  mass 0.5 kg  inertia 0.01 kg*m^2 }
  contact a_toe on a_leg at tip
  contact b_toe on b_leg at tip
  leg left { joints a  foot a_toe  alias spring = a_spring }
  leg right { joints b  foot b_toe  alias spring = b_spring }
  actuator a_spring on a spring(k = 2000 N/m, rest = 0 m)
  actuator b_spring on b spring(k = 2000 N/m, rest = 0 m)
  ground { normal spring(k = 2e5 N/m, b = 20 N*s/m)  tangent spring(k = 1e5 N/m, b = 100 N*s/m) }
}
controller run {
  param push = 2 cm
  roles active = left, idle = right
  action shorten(leg) { leg.spring.rest = -5 cm }
  table {
    state FLIGHT on liftoff(active): swap active idle; active.spring.rest = 0 m; shorten(idle)
    state STANCE on touchdown(active): record landed = time; active.spring.rest = push
  }
}
"""


def test_roles_are_specialised_per_binding_and_swapped_on_entry(tmp_path: Path) -> None:
    source = tmp_path / "walker.leg"
    source.write_text(TWO_LEGS)
    model = check_model(source)
    lowered = lower_controller(model, model.controllers[0])
    assert lowered.bindings == (
        (("active", ("left",)), ("idle", ("right",))),
        (("active", ("right",)), ("idle", ("left",))),
    )
    flight, stance = 0, 1
    assert lowered.after_entry[(0, flight)] == 1 and lowered.after_entry[(1, flight)] == 0
    assert lowered.after_entry[(0, stance)] == 0  # no swap on entering STANCE
    # FLIGHT under binding 1 (active = right after the swap): the right leg extends, the left shortens.
    settings = {(s.actuator, s.key): float(s.value) for s in lowered.bodies[(1, flight)].settings}
    assert settings == {("b_spring", "rest"): 0.0, ("a_spring", "rest"): -0.05}
    # The event of STANCE while waiting under binding 0 watches the left foot only.
    assert {str(x) for x in lowered.events[(0, stance)].free_symbols} == {"leg_left_touching"}
    assert [name for name, _ in lowered.bodies[(0, stance)].records] == ["landed"]


def test_a_let_local_can_be_passed_to_a_nested_action(tmp_path: Path) -> None:
    # The walk that finds the swaps inlines actions too; it used to evaluate every
    # argument and failed on a `let` local it had not bound ("unresolved name d").
    source = tmp_path / "walker.leg"
    source.write_text(
        TWO_LEGS.replace(
            "action shorten(leg) { leg.spring.rest = -5 cm }",
            "action set_rest(leg, v) { leg.spring.rest = v }\n"
            "  action shorten(leg) { let d = -5 cm; set_rest(leg, d) }",
        )
    )
    model = check_model(source)
    lowered = lower_controller(model, model.controllers[0])
    settings = {(s.actuator, s.key): float(s.value) for s in lowered.bodies[(1, 0)].settings}
    assert settings == {("b_spring", "rest"): 0.0, ("a_spring", "rest"): -0.05}
    assert lowered.after_entry[(0, 0)] == 1  # the swap is still found


def _hop(generated: Path, time: float, **inputs: float) -> tuple[Simulation, object]:
    model = check_model(HOPPER)
    dyn = load_dynamics(model, HOPPER, generated)
    control = load_controller(model, "hop", HOPPER, generated)
    schedule = inputs.pop("schedule", None)
    machine = StateMachine(model, control, inputs, schedule=schedule)  # type: ignore[arg-type]
    sim = Simulation(model, dyn, RunOptions(duration=time), machine)
    return sim, sim.run()


def test_the_hopper_cycles_through_figure_4_and_hops(generated: Path) -> None:
    _, result = _hop(generated, 3.0)
    assert result.status == "ok", result.message
    states = [e["state"] for e in result.events if e["kind"] == "state"]
    assert len(states) >= 16
    start = states.index("FLIGHT")
    for k, state in enumerate(states[start:]):
        assert state == FIGURE_4[k % 5], f"state {k} is {state}"
    flights = result.trajectory.contact[:, 0] == 0
    assert flights.any() and (~flights).any()


@pytest.mark.parametrize("speed", [0.5, 1.0])
def test_the_hopper_holds_the_commanded_speed(generated: Path, speed: float) -> None:
    _, result = _hop(generated, 8.0, speed=speed)
    assert result.status == "ok", result.message
    metrics = compute_metrics(result.trajectory, t_from=3.0)
    measured = metrics.value("running_speed")
    assert measured == pytest.approx(speed, rel=0.05)


def test_a_speed_schedule_changes_the_command_during_the_run(generated: Path) -> None:
    sim, result = _hop(generated, 9.0, speed=0.5, schedule=[InputChange(4.0, "speed", 1.0)])
    assert result.status == "ok", result.message
    tr = result.trajectory
    assert np.all(tr.speed_command[tr.t < 4.0] == 0.5) and np.all(
        tr.speed_command[tr.t >= 4.0] == 1.0
    )
    after = compute_metrics(tr, t_from=6.0)
    assert after.value("running_speed") == pytest.approx(1.0, rel=0.05)


def test_place_puts_the_foot_where_it_was_asked(generated: Path) -> None:
    model = check_model(HOPPER)
    dyn = load_dynamics(model, HOPPER, generated)
    sim = Simulation(model, dyn, RunOptions())
    placer = FootPlacer(model, iterations=4)
    goal = 0.2  # the foot 20 cm ahead of the hip
    setpoint = placer.solve(sim, "main", ("x",), [goal], ("hip_servo",))[0]
    sim.q[model.dofs[3].q_index] = setpoint  # put the hip where the servo will take it
    foot = dyn.contact_positions(sim.q)[0]
    hip = dyn.body_poses(sim.q)[1][0]
    assert foot[0] - hip[0] == pytest.approx(goal, abs=1e-9)
    assert setpoint == pytest.approx(-math.asin(goal / 0.8), abs=1e-9)  # a straight 0.8 m leg


def test_the_placer_solve_agrees_with_lapack_and_stops_at_a_singular_matrix() -> None:
    """kinematics.solve_small (the placer's Newton step; machine.c repeats it) against
    numpy.linalg.solve, on the sizes a placement takes, pivoting included."""
    rng = np.random.default_rng(3)
    for n in (1, 2, 3):
        for _ in range(200):
            a = rng.normal(size=(n, n))
            b = rng.normal(size=n)
            if np.linalg.cond(a) > 1e6:
                continue
            got = solve_small(a.tolist(), b.tolist())
            assert got is not None
            np.testing.assert_allclose(got, np.linalg.solve(a, b), rtol=1e-9, atol=1e-12)
    assert solve_small([[0.0, 1.0], [1.0, 0.0]], [2.0, 3.0]) == [3.0, 2.0]  # a row swap
    assert solve_small([[1.0, 2.0], [2.0, 4.0]], [1.0, 1.0]) is None  # singular
    assert solve_small([[0.0]], [1.0]) is None
    assert math.isnan(clip_step(math.nan)) and clip_step(1.0) == 0.3 and clip_step(-1.0) == -0.3


def test_cli_rejects_unknown_inputs_and_runs_with_a_schedule(
    tmp_path: Path, generated: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    args = ["run", str(HOPPER), "--controller", "hop", "--generated", str(generated)]
    assert main([*args, "--set", "sped=1m/s", "--time", "0.1"]) == 2
    assert "no input or parameter 'sped'" in capsys.readouterr().err
    hopper = ["run", str(HOPPER), "--generated", str(generated)]  # --controller given once
    assert main([*hopper, "--controller", "trot", "--time", "0.1"]) == 2
    out = tmp_path / "run"
    code = main(
        [
            *args,
            "--set",
            "speed=0.5m/s",
            "--set",
            "speed=1m/s@0.5s",
            "--time",
            "1",
            "--out",
            str(out),
        ]
    )
    assert code == 0
    import json

    info = json.loads((out / "run.json").read_text())
    assert info["inputs"]["speed"] == 0.5
    assert info["settings"]["schedule"] == [{"t": 0.5, "input": "speed", "value": 1.0}]
    assert any(e["kind"] == "state" for e in info["events"])


def test_only_the_records_the_table_reaches_are_the_controllers(tmp_path: Path) -> None:
    # raibert's trim_step_speed records `step_speed`; the hopper never calls it, so
    # the name stays free for the hopper's own parameter and adds no controller state.
    header = "controller hop {"
    text = HOPPER.read_text(encoding="utf-8").replace(
        header, header + "\n  param step_speed = 1 m/s"
    )
    leg = tmp_path / "hopper.leg"
    leg.write_text(text, encoding="utf-8")
    model = check_model(leg)
    (hop,) = [c for c in model.controllers if c.name == "hop"]
    assert "speed_trim" in hop.record_names  # trim_speed is called, its record is kept
    assert "step_speed" not in hop.record_names
    assert {c.name: c.value for c in hop.params}["step_speed"] == pytest.approx(1.0)
