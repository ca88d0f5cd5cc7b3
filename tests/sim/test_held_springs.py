"""A spring or servo whose stiffness and rest never change is no energy source
(``legdsl.sim.energy_check.held_springs``).

Reported from outside: a passive drop of a pogo (no controller) whose 5 g foot chatters on a
stiff ground at --dt 0.2 ms, twice the step the ground allows it: the total energy leapt from
78 J to 198 J between two samples, the trunk bounced higher than it was dropped from, and
the leg spring "did" 1129 J of positive work over the run (6 J at a sound step). The energy
check counted that work, and what the spring held, as sources, and the run was told ok. Such
a spring only gives back what it stored, which the total holds already."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from conftest import CREATURES
from runtime_helpers import needs_c_compiler

from legdsl.check.source import check_model
from legdsl.cli import main
from legdsl.pipeline.generated import load_controller, load_dynamics
from legdsl.sim.energy_check import HeldSpring, held_springs, unexplained_rise
from legdsl.sim.machine import StateMachine
from legdsl.sim.run_loop import RunOptions
from legdsl.sim.simulate import Simulation
from legdsl.sim.trajectory import empty

POGO = """\
creature sliderpogo {
  planar
  body trunk free {
    mass 5 kg  inertia 0.1 kg*m^2
    initial x = 0 m, z = 0.75 m, pitch = 0 deg
  }
  body carriage on trunk via prismatic lift at (0 m, 0 m) {
    length 0.1 m  com 0.05 m  mass 1 kg  inertia 0.002 kg*m^2
  }
  body arm on carriage via revolute swing at tip {
    length 0.3 m  com 0.15 m  mass 0.4 kg  inertia 0.003 kg*m^2
  }
  body foot on arm via prismatic ext at tip {
    length 0.3 m  com 0.15 m  mass 5 g  inertia 2e-5 kg*m^2
  }
  contact toe on foot at tip
  actuator lift_spring on lift spring(k = 4000 N/m, b = 40 N*s/m, rest = 0 m)
  actuator ext_spring on ext spring(k = 3e4 N/m, b = 10 N*s/m, rest = 0 m)
  actuator swing_servo on swing servo(kp = 100 N*m/rad, kv = 4 N*m*s/rad, max = 50 N*m)
  ground {
    normal spring(k = 5e4 N/m, b = 100 N*s/m)
    tangent spring(k = 3e4 N/m, b = 100 N*s/m)
  }
}
"""


def _run(tmp_path: Path, backend: str, dt: str) -> tuple[int, dict[str, object]]:
    leg = tmp_path / "pogo.leg"
    leg.write_text(POGO, encoding="utf-8")
    out = tmp_path / f"run_{backend}_{dt}"
    code = main(["run", str(leg), "--time", "0.3", "--dt", dt, "--backend", backend,
                 "--generated", str(tmp_path / "gen"), "--out", str(out)])  # fmt: skip
    return code, json.loads((out / "run.json").read_text())


@needs_c_compiler
def test_a_passive_drop_that_gains_energy_at_too_large_a_step_is_told_diverged(
    tmp_path: Path,
) -> None:
    said = {}
    for backend in ("python", "c"):
        code, info = _run(tmp_path, backend, "0.2ms")
        assert code == 3 and info["status"] == "diverged"
        said[backend] = info["message"]
    message = said["python"]
    assert said["c"] == message
    assert str(message).startswith(
        "the simulation diverged at t = 0.1550 s: the total energy rose from 78.31 J at "
        "t = 0.1500 s to 198.1 J at t = 0.1550 s (one sample later) with only 0 J of actuator "
        "work between (not counting 106 J of springs and servos whose stiffness and rest never "
        "change: they only give back what they stored)"
    )
    # the cause: the ground's normal spring on the 5 g foot, with the step it allows
    assert "the ground's normal spring on contact 'toe'" in str(message)
    assert "effective mass of 0.005 kg there, and explicit stability needs dt < 0.1 ms" in str(
        message
    )


def test_the_same_drop_at_a_sound_step_is_ok(tmp_path: Path) -> None:
    code, info = _run(tmp_path, "python", "0.05ms")
    assert code == 0 and info["status"] == "ok"


def _recording(kinetic: list[float], elastic: list[float], work: list[float], q: list[float]):
    n = len(kinetic)
    traj = empty(n, 1, 1, 0, 0, 1, total_mass=1.0, gravity=9.81)
    traj.t[:] = np.arange(n) * 0.005
    traj.com[:, 2] = 1.0  # a floor of 0.1 * 9.81 J
    traj.potential[:] = 5.0
    traj.kinetic[:], traj.elastic[:], traj.q[:, 0] = kinetic, elastic, q
    traj.work_positive[:, 0], traj.work_negative[:, 0] = work, 0.0
    return traj


def test_a_held_springs_work_is_no_source_but_what_it_gives_back_is_its_own() -> None:
    spring = HeldSpring(index=0, q_index=0, gain=60.0, target=0.0)  # 30 J held at q = 1
    # it releases the 30 J it held at the start: the kinetic energy rises by them
    released = _recording([1.0, 1.0, 11.0, 21.0, 31.0], [30.0, 30.0, 20.0, 10.0, 0.0],
                          [0.0, 0.0, 10.0, 20.0, 30.0],
                          [1.0, 1.0, (2 / 3) ** 0.5, (1 / 3) ** 0.5, 0.0])  # fmt: skip
    assert unexplained_rise(released, (spring,)) is None
    # at rest at its rest length, it "works" 30 J into motion: a step blowing up
    leapt = _recording([1.0, 1.0, 31.0, 31.0, 31.0], [0.0] * 5, [0.0, 0.0, 30.0, 30.0, 30.0],
                       [0.0] * 5)  # fmt: skip
    assert unexplained_rise(leapt) is None  # as a spring a controller moves could
    rise = unexplained_rise(leapt, (spring,))
    assert rise is not None and (rise.start, rise.end) == (1, 2)
    assert rise.work == 0.0 and rise.given_back == 30.0


@pytest.mark.parametrize("controller", ["hop", "jump"])
def test_only_springs_no_controller_sets_and_without_a_max_are_held(
    generated: Path, controller: str
) -> None:
    """The kangaroo's controllers set the ankle spring's rest, the tail base's and the neck
    servo's: its tail's two outer springs alone are held (the servos with a max are not)."""
    leg = CREATURES / "kangaroo.leg"
    model = check_model(leg)
    dyn = load_dynamics(model, leg, generated)
    machine = StateMachine(model, load_controller(model, controller, leg, generated), {})
    sim = Simulation(model, dyn, RunOptions(duration=0.1), machine)
    names = [sim.actuators.states[h.index].name for h in held_springs(sim)]
    assert names == ["tail_mid_spring", "tail_tip_spring"]
    alone = Simulation(model, dyn, RunOptions(duration=0.1))  # no controller: all but the max
    assert [sim.actuators.states[h.index].name for h in held_springs(alone)] == [
        a.name for a in model.actuators if a.kind != "force" and a.max is None
    ]
