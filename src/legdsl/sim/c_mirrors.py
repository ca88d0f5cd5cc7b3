"""What the C runtime transliterates, and whether it still matches: the C backend's drift guard.

``codegen/c/runtime/step.c`` is a line-by-line transliteration of the Python step (actuators,
stops, ground, integrators, recording, the run loop), and ``machine.c`` of the state machine,
its sensors, the path tracker and the kinematic solve. Each module's functions are listed here
with the digest of their source text as it was when the C was last brought in line. When one
of them is edited (even a comment), its digest changes and the C twin steps aside: the C
backend (for the step) or the C state machine (for the controller) is not used and the Python
one runs, so a run never differs between backends; and ``tests/sim/test_c_backend.py`` fails,
naming the functions, until the C follows and the digest here is updated
(``python -m legdsl.sim.c_mirrors`` prints the current ones).
"""

from __future__ import annotations

import hashlib
import inspect
from collections.abc import Callable
from functools import lru_cache
from typing import Any

from legdsl.ir.model import Hip
from legdsl.sim import (
    actuators,
    contact,
    kinematics,
    machine,
    path_tracking,
    recorder,
    sensors,
    simulate,
    sizes,
    terrain_ahead,
)


def _step_functions() -> list[Callable[..., Any]]:
    s = simulate.Simulation
    g = contact.GroundContact
    return [
        actuators.ActuatorBank.apply, actuators.ActuatorBank.elastic_energy, actuators.stored,
        actuators.ActuatorBank.power, actuators.ActuatorBank.add_work,
        actuators.ActuatorState.set, actuators.ActuatorState.get,
        contact.pad_force, contact._pad_energy, g.surface, g.height, g._tangents, g.depth,
        g.force, g.yaw, g.about_normal, g.torsion, g.near, g.update, g._slip, g.elastic_energy,
        s.generalized_forces, s._add_torsion, s._contact_kinematics, s._qdot,
        s._advance_positions, s._normalise, s._accel, s.step, s.energy, s._check, s._begin,
        s._loop, sizes.divergence_speed, sizes.too_fast, recorder.record_row, recorder.rpy,
        Hip.point, Hip._turned,
    ]  # fmt: skip


def _machine_functions() -> list[Callable[..., Any]]:
    m, n = machine.StateMachine, sensors.Sensors
    return [
        m.__call__, m._enter, m._apply_schedule, m._call, m.speed_command, m._integral,
        machine.Integral.value, machine.Integral.change,
        n.observe, sensors._tick, n.read, n._value, n._body, n._leg, n._path, n._heading, n._to_heading,
        sensors.euler_rates, sensors.rpy, kinematics.FootPlacer.solve, kinematics.solve_small,
        kinematics.clip_step, path_tracking.PathTracker.update,
        path_tracking.PathGeometry.project, path_tracking.PathGeometry.at, path_tracking._wrap,
        path_tracking._goes_on,
        n._terrain, terrain_ahead._crossing, terrain_ahead.ahead, Hip.point, Hip.velocity, Hip._turned,
    ]  # fmt: skip


def digest(functions: list[Callable[..., Any]]) -> str:
    text = "\n".join(f"{f.__qualname__}\n{inspect.getsource(f)}" for f in functions)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


# The sources step.c and machine.c were brought in line with (see the module docstring).
STEP_DIGEST = "949712b63171fa5f"
MACHINE_DIGEST = "cfba065ac0c15d5e"


@lru_cache(maxsize=1)
def step_matches() -> bool:
    """Whether step.c still mirrors the Python step (read once per process)."""
    try:
        return digest(_step_functions()) == STEP_DIGEST
    except (OSError, TypeError):  # no source to read (a frozen install): trust the tests
        return True


@lru_cache(maxsize=1)
def machine_matches() -> bool:
    """Whether machine.c still mirrors the Python state machine (read once per process)."""
    try:
        return digest(_machine_functions()) == MACHINE_DIGEST
    except (OSError, TypeError):
        return True


if __name__ == "__main__":
    print(f'STEP_DIGEST = "{digest(_step_functions())}"')
    print(f'MACHINE_DIGEST = "{digest(_machine_functions())}"')
