"""Passive runs conserve what physics says they must.

With gravity off and no joint forces, a free-floating creature keeps its
kinetic energy, linear momentum and angular momentum about the world origin;
under gravity its total energy stays put. A tiny RK4 integrates here (the
quaternion renormalised after each step), so only the generated module is
under test. Momenta come from the mass matrix: for the free root, (M v)[0:3]
is the world linear momentum and (M v)[3:6] the angular momentum about the
root origin in body axes (the generalized momenta of MuJoCo's free joint).
"""

from __future__ import annotations

import math
from pathlib import Path
from types import ModuleType

import numpy as np
import pytest
from conftest import compile_text, shipped_dynamics, shipped_model

# A small 3D creature: a trunk, a ball-jointed arm with a sliding forearm, a hinged tail.
FLOATER = """
creature floater {
  spatial
  gravity 0 m/s^2
  body trunk free {
    mass 3 kg  com (0.02 m, 0 m, 0.01 m)  inertia (0.05, 0.07, 0.09) kg*m^2
    initial x = 0.1 m, y = -0.2 m, z = 1 m, roll = 10 deg, pitch = -20 deg, yaw = 30 deg
    velocity vx = 0.3 m/s, vy = -0.2 m/s, vz = 0.1 m/s, wx = 1 rad/s, wy = -2 rad/s, wz = 0.5 rad/s
  }
  body arm on trunk via ball shoulder at (0.15 m, 0.1 m, 0.05 m) {
    length 0.3 m  com 0.14 m  mass 0.8 kg  inertia (0.008, 0.008, 0.0006) kg*m^2
    initial shoulder_x = 17 deg, shoulder_y = -29 deg, shoulder_z = 11 deg
    velocity shoulder_x = 1.5 rad/s, shoulder_y = -1 rad/s, shoulder_z = 2 rad/s
  }
  body forearm on arm via prismatic reach at tip {
    length 0.25 m  com 0.1 m  mass 0.3 kg  inertia (0.002, 0.002, 0.0001) kg*m^2
    velocity 0.2 m/s
  }
  body tail on trunk via revolute wag at (-0.2 m, 0 m, 0 m) {
    axis (0, 0.6, 0.8)  direction (-1, 0, 0)
    length 0.2 m  com 0.1 m  mass 0.4 kg  inertia (0.0004, 0.002, 0.002) kg*m^2
    velocity -3 rad/s
  }
}
"""


def rk4(dyn: ModuleType, q: list[float], v: list[float], dt: float, steps: int) -> tuple:
    """Integrate the passive creature (tau = 0) with classic RK4."""
    tau = [0.0] * dyn.NV
    free3d = dyn.NQ == dyn.NV + 1
    for _ in range(steps):
        k1q, k1v = dyn.state_derivative(q, v, tau)
        q2 = [a + 0.5 * dt * b for a, b in zip(q, k1q, strict=True)]
        v2 = [a + 0.5 * dt * b for a, b in zip(v, k1v, strict=True)]
        k2q, k2v = dyn.state_derivative(q2, v2, tau)
        q3 = [a + 0.5 * dt * b for a, b in zip(q, k2q, strict=True)]
        v3 = [a + 0.5 * dt * b for a, b in zip(v, k2v, strict=True)]
        k3q, k3v = dyn.state_derivative(q3, v3, tau)
        q4 = [a + dt * b for a, b in zip(q, k3q, strict=True)]
        v4 = [a + dt * b for a, b in zip(v, k3v, strict=True)]
        k4q, k4v = dyn.state_derivative(q4, v4, tau)
        sixth = dt / 6
        q = [
            a + sixth * (b + 2 * c + 2 * d + e)
            for a, b, c, d, e in zip(q, k1q, k2q, k3q, k4q, strict=True)
        ]
        v = [
            a + sixth * (b + 2 * c + 2 * d + e)
            for a, b, c, d, e in zip(v, k1v, k2v, k3v, k4v, strict=True)
        ]
        if free3d:
            norm = math.sqrt(sum(c * c for c in q[3:7]))
            q[3:7] = [c / norm for c in q[3:7]]
    return q, v


def momenta(dyn: ModuleType, q: list[float], v: list[float]) -> tuple[np.ndarray, np.ndarray]:
    """Linear momentum, and angular momentum about the world origin (3D free root)."""
    p = np.array(dyn.mass_matrix(q)) @ np.array(v)
    w, x, y, z = q[3:7]
    rot = np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )
    linear = p[0:3]
    return linear, rot @ p[3:6] + np.cross(np.array(q[0:3]), linear)


def relative_change(before: np.ndarray | float, after: np.ndarray | float) -> float:
    return float(np.linalg.norm(np.subtract(after, before)) / np.linalg.norm(before))


def test_free_floating_creature_keeps_energy_and_momenta(tmp_path: Path) -> None:
    model, dyn = compile_text(tmp_path, FLOATER)
    q, v = list(model.q0), list(model.v0)
    energy, (linear, angular) = dyn.kinetic_energy(q, v), momenta(dyn, q, v)
    assert np.allclose(linear, dyn.TOTAL_MASS * np.array(dyn.center_of_mass_velocity(q, v)))
    q2, v2 = rk4(dyn, q, v, 1e-4, 20_000)  # 2 s
    assert q2 != q  # it did move: the arm, the slide and the tail all swing
    linear2, angular2 = momenta(dyn, q2, v2)
    assert relative_change(energy, dyn.kinetic_energy(q2, v2)) < 1e-8
    assert relative_change(linear, linear2) < 1e-8
    assert relative_change(angular, angular2) < 1e-8


@pytest.mark.parametrize(
    ("name", "seconds"), [("kangaroo", 0.2), ("biped", 0.1), ("quadruped", 0.05)]
)
def test_shipped_creatures_keep_total_energy_under_gravity(name: str, seconds: float) -> None:
    """Falling and flailing with no damping and no ground: kinetic + potential energy is constant.

    Measured |change of energy| / |potential energy exchanged| at dt = 1e-4 s: 5e-15
    (kangaroo, 0.2 s), 5e-14 (biped, 0.1 s), 5e-14 (quadruped, 0.05 s), which is
    round-off; at dt = 1e-2 s it grows to 1e-11, 5e-10 and 1.5e-8, RK4's dt^4 error.
    """
    dyn = shipped_dynamics(name)
    rng = np.random.default_rng(11)
    q = list(shipped_model(name).q0)
    v = [float(x) for x in rng.uniform(-1, 1, dyn.NV)]
    start = dyn.kinetic_energy(q, v) + dyn.potential_energy(q)
    q2, v2 = rk4(dyn, q, v, 1e-4, round(seconds / 1e-4))
    end = dyn.kinetic_energy(q2, v2) + dyn.potential_energy(q2)
    exchanged = abs(dyn.potential_energy(q2) - dyn.potential_energy(q))
    assert exchanged > 0.1  # it fell: energy really moved from potential to kinetic
    assert abs(end - start) < 1e-9 * exchanged
