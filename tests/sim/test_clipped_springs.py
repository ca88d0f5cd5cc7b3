"""What a spring or servo with a ``max`` holds: the potential of its force as it is clipped
(``legdsl.sim.actuators.stored``), in both backends' ``elastic`` and ``leg_spring_energy``.

Reported from outside: a passive, undamped pendulum held 90 deg from its rest by
``spring(k = 1000 N*m/rad, max = 5 N*m)`` was reported at 1233.7 J of elastic energy at the
start (1/2 k d^2) and its total energy rising from 1292.6 J to 7107.6 J in 3 s, though the
spring never pushed harder than 5 N*m and the motion kept its energy; a 5 N*m servo's peaked
at 7542 J."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from runtime_helpers import needs_c_compiler

from legdsl.cli import main
from legdsl.sim.actuators import stored
from legdsl.sim.trajectory import Trajectory

CLIPPED = """\
creature clipped {
  planar
  body base fixed at (0 m, 2 m) { mass 1 kg  inertia 0.01 kg*m^2 }
  body arm on base via revolute sh {
    length 1 m  com 0.8 m  mass 2 kg  inertia 0.05 kg*m^2
    initial 90 deg
  }
  body tip on arm via prismatic ext at tip {
    length 0.2 m  com 0.1 m  mass 0.5 kg  inertia 0.002 kg*m^2
    initial 10 cm
  }
  body arm2 on base via revolute el at (0.5 m, 0 m) {
    length 1 m  com 0.5 m  mass 1 kg  inertia 0.05 kg*m^2
    initial -90 deg
  }
  contact toe on tip at tip
  leg main { joints sh, ext  foot toe }
  actuator clip on sh spring(k = 1000 N*m/rad, rest = 180 deg, b = DAMPING N*m*s/rad, max = 5 N*m)
  actuator slide on ext spring(k = 2000 N/m, rest = 0 m, b = DAMPING N*s/m, max = 30 N)
  actuator hold on el servo(kp = 400 N*m/rad, kv = 0 N*m*s/rad, setpoint = 0 deg, max = 2 N*m)
}
"""


def _run(tmp_path: Path, backend: str, damping: str) -> Trajectory:
    leg = tmp_path / f"clipped_{damping}.leg"
    leg.write_text(CLIPPED.replace("DAMPING", damping), encoding="utf-8")
    out = tmp_path / f"run_{backend}_{damping}"
    code = main(["run", str(leg), "--time", "2", "--integrator", "rk4", "--record-rate", "0",
                 "--backend", backend, "--generated", str(tmp_path / "gen"), "--out", str(out)])  # fmt: skip
    assert code == 0
    return Trajectory.load(out)


def test_stored_is_the_potential_of_the_clipped_force() -> None:
    assert stored(1000.0, math.pi / 2, None) == pytest.approx(0.5 * 1000 * (math.pi / 2) ** 2)
    assert stored(1000.0, math.pi / 2, 5.0) == pytest.approx(5 * (math.pi / 2 - 5 / 2000))
    assert stored(1000.0, 0.004, 5.0) == 0.5 * 1000.0 * 0.004 * 0.004  # inside: unchanged
    for gain in (1000.0, -1000.0, 0.0):
        for limit in (5.0, 0.0):
            force = np.clip(-gain * np.linspace(-0.02, 0.02, 4001), -limit, limit)
            held = np.array([stored(gain, d, limit) for d in np.linspace(-0.02, 0.02, 4001)])
            # its slope is minus the force the actuator applies, and it is 0 at the rest
            assert np.allclose(-np.gradient(held, 1e-5), force, atol=1e-5 * abs(gain) + 1e-9)
            assert stored(gain, 0.0, limit) == 0.0


@pytest.mark.parametrize("backend", ["python", pytest.param("c", marks=needs_c_compiler)])
def test_an_undamped_clipped_spring_and_servo_keep_the_total_energy(
    tmp_path: Path, backend: str
) -> None:
    tr = _run(tmp_path, backend, "0")
    clip, slide, hold = (
        5 * (math.pi / 2 - 5 / 2000),
        30 * (0.1 - 30 / 4000),
        2 * (math.pi / 2 - 2 / 800),
    )
    assert tr.elastic[0] == pytest.approx(clip + slide + hold, rel=1e-12)
    assert tr.leg_spring_energy[0, 0] == pytest.approx(clip + slide, rel=1e-12)
    total = tr.kinetic + tr.potential + tr.elastic
    # conservative: what it had at the start, to RK4's accuracy (it rose 6620 J from 1825 J)
    assert np.ptp(tr.elastic) > 10.0
    assert np.max(np.abs(total - total[0])) < 1e-5 * total[0]


@pytest.mark.parametrize("backend", ["python", pytest.param("c", marks=needs_c_compiler)])
def test_a_damped_clipped_spring_only_takes_energy_away(tmp_path: Path, backend: str) -> None:
    """The clip applies to the spring's and the damper's force together: what that force differs
    from the clipped spring force by always opposes the motion, so the total never rises."""
    tr = _run(tmp_path, backend, "3")
    total = tr.kinetic + tr.potential + tr.elastic
    # to RK4's accuracy where a force bends at the clip
    assert np.max(total - total[0]) < 1e-5 * total[0]
    assert np.max(np.diff(total)) < 1e-6 * total[0]
    assert total[-1] < total[0] - 2.0  # the dampers took 2.7 J
