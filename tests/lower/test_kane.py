"""The generated dynamics against sympy.physics.mechanics (Kane's method) on small trees.

Each tree is written as .leg text, compiled, and built again here by hand
with KanesMethod from the same numbers: frames, points and loads, nothing
from legdsl but the text. Joint torques enter Kane as real torque and force
pairs (on the child and, reversed, on the parent), so the comparison also
checks what tau means. At random states and torques the generated mass
matrix, bias forces and accelerations must agree to 1e-10 relative.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import sympy as sp
from conftest import compile_text
from sympy.physics.mechanics import (
    KanesMethod,
    Particle,
    Point,
    ReferenceFrame,
    RigidBody,
    dynamicsymbols,
    inertia,
)

G = 9.81
RTOL = 1e-10

Oracle = Callable[..., Any]


def kane_oracle(
    frame: ReferenceFrame,
    q: list[Any],
    u: list[Any],
    kd: list[Any],
    bodies: list[RigidBody | Particle],
    loads: list[tuple[Any, Any]],
    taus: list[Any],
    extra: tuple[list[Any], Callable[[np.ndarray], list[float]]] = ([], lambda q: []),
) -> Oracle:
    """(q, u, tau) -> (M, forcing) with M u' = forcing, evaluated numerically.

    ``extra`` is more symbols and how to compute their values from q.
    """
    kane = KanesMethod(frame, q_ind=q, u_ind=u, kd_eqs=kd)
    kane.kanes_equations(bodies, loads)
    symbols, values = extra
    f = sp.lambdify(
        (q, u, taus, symbols), [kane.mass_matrix, kane.forcing], modules="numpy", cse=True
    )
    return lambda qv, uv, tv: f(qv, uv, tv, values(qv))


def joint_torque(tau: Any, axis: Any, child: ReferenceFrame, parent: ReferenceFrame | None) -> list:
    loads = [(child, tau * axis)]
    return loads + ([(parent, -tau * axis)] if parent is not None else [])


def body(name: str, frame: ReferenceFrame, com: Point, mass: float, moments: tuple) -> RigidBody:
    ixx, iyy, izz, *products = moments
    ixy, iyz, izx = products or (0, 0, 0)
    return RigidBody(name, com, frame, mass, (inertia(frame, ixx, iyy, izz, ixy, iyz, izx), com))


def compare(module: Any, oracle: Oracle, sample: Callable[[np.random.Generator], tuple]) -> None:
    rng = np.random.default_rng(7)
    for _ in range(5):
        q, v = sample(rng)
        tau = rng.uniform(-3, 3, module.NV)
        m_kane, forcing = (np.array(a, dtype=float) for a in oracle(q, v, tau))
        forcing = forcing.ravel()
        _, h_kane = (np.array(a, dtype=float) for a in oracle(q, v, 0 * tau))
        m_ours = np.array(module.mass_matrix(list(q)))
        h_ours = np.array(module.bias_forces(list(q), list(v)))
        qdd_ours = np.array(module.forward_dynamics(list(q), list(v), list(tau)))
        qdd_kane = np.linalg.solve(m_kane, forcing)
        assert_close(m_ours, m_kane, "mass matrix")
        assert_close(h_ours, -h_kane.ravel(), "bias forces")
        assert_close(qdd_ours, qdd_kane, "accelerations")


def assert_close(ours: np.ndarray, ref: np.ndarray, what: str) -> None:
    err = np.abs(ours - ref).max() / max(np.abs(ref).max(), 1e-300)
    assert err < RTOL, f"{what}: relative error {err:.2e}\nours {ours}\nKane {ref}"


# ---------------------------------------------------------------------- a planar double pendulum
PENDULUM = """
creature pendulum {
  planar
  gravity 9.81 m/s^2
  body base fixed at (0 m, 1.5 m) { mass 2 kg  inertia 0.1 kg*m^2 }
  body upper on base via revolute shoulder at (0.1 m, -0.05 m) {
    length 0.5 m  com 0.23 m  mass 1.2 kg  inertia 0.031 kg*m^2
  }
  body lower on upper via revolute elbow at tip {
    length 0.4 m  com (0.02 m, -0.17 m)  mass 0.8 kg  inertia 0.017 kg*m^2
  }
}
"""


def test_planar_double_pendulum_matches_kane(tmp_path: Path) -> None:
    model, module = compile_text(tmp_path, PENDULUM)
    assert model.q_names == ("shoulder", "elbow")
    q1, q2 = dynamicsymbols("q1 q2")
    u1, u2 = dynamicsymbols("u1 u2")
    t1, t2 = sp.symbols("t1 t2")
    world = ReferenceFrame("N")
    upper = world.orientnew("A", "Axis", (q1, world.y))
    lower = upper.orientnew("B", "Axis", (q2, upper.y))
    origin = Point("O")
    origin.set_vel(world, 0)
    shoulder = origin.locatenew("S", 0.1 * world.x + (1.5 - 0.05) * world.z)
    shoulder.set_vel(world, 0)
    upper_com = shoulder.locatenew("Ac", -0.23 * upper.z)
    upper_com.v2pt_theory(shoulder, world, upper)
    elbow = shoulder.locatenew("E", -0.5 * upper.z)
    elbow.v2pt_theory(shoulder, world, upper)
    lower_com = elbow.locatenew("Bc", 0.02 * lower.x - 0.17 * lower.z)
    lower_com.v2pt_theory(elbow, world, lower)
    bodies = [
        body("upper", upper, upper_com, 1.2, (0.031, 0.031, 0.031)),
        body("lower", lower, lower_com, 0.8, (0.017, 0.017, 0.017)),
    ]
    loads = [
        (upper_com, -1.2 * G * world.z),
        (lower_com, -0.8 * G * world.z),
        *joint_torque(t1, world.y, upper, None),
        *joint_torque(t2, upper.y, lower, upper),
    ]
    oracle = kane_oracle(
        world, [q1, q2], [u1, u2], [q1.diff() - u1, q2.diff() - u2], bodies, loads, [t1, t2]
    )

    def sample(rng: np.random.Generator) -> tuple:
        return rng.uniform(-3, 3, 2), rng.uniform(-2, 2, 2)

    compare(module, oracle, sample)


# ------------------------------------------- a planar free body with a hinge and an oblique slide
HOPPER = """
creature hopper {
  planar
  gravity 9.81 m/s^2
  body trunk free { mass 3 kg  inertia 0.05 kg*m^2  com (0.03 m, 0.02 m) }
  body thigh on trunk via revolute hip at (-0.1 m, -0.05 m) {
    length 0.3 m  com 0.12 m  mass 1.1 kg  inertia 0.009 kg*m^2
  }
  body shank on thigh via prismatic leg at tip {
    direction (0.6, -0.8)  length 0.35 m  com 0.15 m  mass 0.4 kg  inertia 0.004 kg*m^2
  }
}
"""


def test_planar_chain_with_prismatic_joint_matches_kane(tmp_path: Path) -> None:
    model, module = compile_text(tmp_path, HOPPER)
    assert model.q_names == ("x", "z", "pitch", "hip", "leg")
    x, z, pitch, hip, leg = q = list(dynamicsymbols("x z pitch hip leg"))
    u = list(dynamicsymbols("u0:5"))
    taus = list(sp.symbols("tau0:5"))
    world = ReferenceFrame("N")
    trunk = world.orientnew("T", "Axis", (pitch, world.y))
    thigh = trunk.orientnew("H", "Axis", (hip, trunk.y))
    origin = Point("O")
    origin.set_vel(world, 0)
    root = origin.locatenew("P", x * world.x + z * world.z)
    root.set_vel(world, u[0] * world.x + u[1] * world.z)
    trunk_com = root.locatenew("Tc", 0.03 * trunk.x + 0.02 * trunk.z)
    trunk_com.v2pt_theory(root, world, trunk)
    hip_point = root.locatenew("Hp", -0.1 * trunk.x - 0.05 * trunk.z)
    hip_point.v2pt_theory(root, world, trunk)
    thigh_com = hip_point.locatenew("Hc", -0.12 * thigh.z)
    thigh_com.v2pt_theory(hip_point, world, thigh)
    slide = 0.6 * thigh.x - 0.8 * thigh.z
    shank_origin = hip_point.locatenew("S", -0.3 * thigh.z + leg * slide)
    shank_origin.set_vel(world, shank_origin.pos_from(origin).dt(world).subs(_rates(q, u)))
    on_thigh = hip_point.locatenew("St", -0.3 * thigh.z + leg * slide)  # fixed in the thigh
    on_thigh.v2pt_theory(hip_point, world, thigh)
    shank_com = shank_origin.locatenew("Sc", 0.15 * slide)
    shank_com.v2pt_theory(shank_origin, world, thigh)
    bodies = [
        body("trunk", trunk, trunk_com, 3.0, (0.05, 0.05, 0.05)),
        body("thigh", thigh, thigh_com, 1.1, (0.009, 0.009, 0.009)),
        body("shank", thigh, shank_com, 0.4, (0.004, 0.004, 0.004)),
    ]
    loads = [
        (trunk_com, -3.0 * G * world.z),
        (thigh_com, -1.1 * G * world.z),
        (shank_com, -0.4 * G * world.z),
        (root, taus[0] * world.x + taus[1] * world.z),
        (trunk, taus[2] * world.y),
        *joint_torque(taus[3], trunk.y, thigh, trunk),
        (shank_origin, taus[4] * slide),
        (on_thigh, -taus[4] * slide),
    ]
    kd = [qi.diff() - ui for qi, ui in zip(q, u, strict=True)]
    oracle = kane_oracle(world, q, u, kd, bodies, loads, taus)

    def sample(rng: np.random.Generator) -> tuple:
        return rng.uniform(-1.5, 1.5, 5), rng.uniform(-2, 2, 5)

    compare(module, oracle, sample)


def rotation(q: np.ndarray) -> list[float]:
    """The rotation matrix (row-major) of the unit quaternion q[3:7]."""
    w, x, y, z = q[3:7]
    return [
        *(1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)),
        *(2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)),
        *(2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)),
    ]


def _rates(q: list[Any], u: list[Any]) -> dict[Any, Any]:
    return {qi.diff(): ui for qi, ui in zip(q, u, strict=True)}


# ---------------------------------------- a 3D free body with a gimbal leg (skewed second axis)
STRIDER = """
creature strider {
  spatial
  gravity 9.81 m/s^2
  body trunk free {
    mass 4 kg  com (0.02 m, -0.01 m, 0.03 m)
    inertia ((0.3 kg*m^2, 0.01 kg*m^2, 0.02 kg*m^2), (0.01 kg*m^2, 0.4 kg*m^2, 0.03 kg*m^2), (0.02 kg*m^2, 0.03 kg*m^2, 0.5 kg*m^2))
  }
  body thigh on trunk via gimbal hip at (0.2 m, 0.1 m, -0.05 m) {
    axes (1, 0, 0), (0, 0.6, 0.8)
    length 0.4 m  com 0.18 m  mass 1.5 kg  inertia (0.05, 0.048, 0.004) kg*m^2
  }
  body shank on thigh via prismatic knee at tip {
    length 0.4 m  com 0.2 m  mass 0.7 kg  inertia (0.012, 0.011, 0.0012) kg*m^2
  }
}
"""


def test_gimbal_leg_on_3d_free_body_matches_kane(tmp_path: Path) -> None:
    """MuJoCo's free-joint coordinates: v = (world linear velocity, body angular velocity)."""
    model, module = compile_text(tmp_path, STRIDER)
    assert model.q_names[:7] == ("x", "y", "z", "qw", "qx", "qy", "qz")
    assert model.v_names[:6] == ("vx", "vy", "vz", "wx", "wy", "wz")
    x, y, z, e0, e1, e2, e3, a1, a2, knee = q = list(dynamicsymbols("x y z e0:4 a1 a2 knee"))
    u = list(dynamicsymbols("u0:9"))
    taus = list(sp.symbols("tau0:9"))
    world = ReferenceFrame("N")
    trunk = ReferenceFrame("B")
    # The trunk's orientation as nine numbers (its axes in the world, computed from the
    # quaternion below) and its angular velocity as the body-axes speeds: Kane needs no more.
    dcm = sp.Matrix(3, 3, sp.symbols("r0:9"))
    trunk.orient_explicit(world, dcm)
    trunk.set_ang_vel(world, u[3] * trunk.x + u[4] * trunk.y + u[5] * trunk.z)
    inner = trunk.orientnew("H1", "Axis", (a1, trunk.x))
    skew_axis = 0.6 * inner.y + 0.8 * inner.z
    thigh = inner.orientnew("H2", "Axis", (a2, skew_axis))
    origin = Point("O")
    origin.set_vel(world, 0)
    root = origin.locatenew("P", x * world.x + y * world.y + z * world.z)
    root.set_vel(world, u[0] * world.x + u[1] * world.y + u[2] * world.z)
    trunk_com = root.locatenew("Bc", 0.02 * trunk.x - 0.01 * trunk.y + 0.03 * trunk.z)
    trunk_com.v2pt_theory(root, world, trunk)
    hip = root.locatenew("Hp", 0.2 * trunk.x + 0.1 * trunk.y - 0.05 * trunk.z)
    hip.v2pt_theory(root, world, trunk)
    thigh_com = hip.locatenew("Hc", -0.18 * thigh.z)
    thigh_com.v2pt_theory(hip, world, thigh)
    slide = -thigh.z  # the shank's default direction, down its link
    shank_origin = hip.locatenew("S", -0.4 * thigh.z + knee * slide)
    shank_origin.set_vel(
        world, hip.vel(world) + shank_origin.pos_from(hip).dt(world).subs(_rates(q[7:], u[6:]))
    )
    on_thigh = hip.locatenew("St", -0.4 * thigh.z + knee * slide)
    on_thigh.v2pt_theory(hip, world, thigh)
    shank_com = shank_origin.locatenew("Sc", 0.2 * slide)
    shank_com.v2pt_theory(shank_origin, world, thigh)
    bodies = [
        body("trunk", trunk, trunk_com, 4.0, (0.3, 0.4, 0.5, 0.01, 0.03, 0.02)),
        body("thigh", thigh, thigh_com, 1.5, (0.05, 0.048, 0.004)),
        body("shank", thigh, shank_com, 0.7, (0.012, 0.011, 0.0012)),
    ]
    loads = [
        (trunk_com, -4.0 * G * world.z),
        (thigh_com, -1.5 * G * world.z),
        (shank_com, -0.7 * G * world.z),
        # the root's generalized forces: a world force at the origin and a body-axes torque
        (root, taus[0] * world.x + taus[1] * world.y + taus[2] * world.z),
        (trunk, taus[3] * trunk.x + taus[4] * trunk.y + taus[5] * trunk.z),
        *joint_torque(taus[6], trunk.x, inner, trunk),
        *joint_torque(taus[7], skew_axis, thigh, inner),
        (shank_origin, taus[8] * slide),
        (on_thigh, -taus[8] * slide),
    ]
    w = (u[3], u[4], u[5])
    quat_rates = [  # 0.5 q ⊗ (0, w_body)
        -(e1 * w[0] + e2 * w[1] + e3 * w[2]) / 2,
        (e0 * w[0] + e2 * w[2] - e3 * w[1]) / 2,
        (e0 * w[1] + e3 * w[0] - e1 * w[2]) / 2,
        (e0 * w[2] + e1 * w[1] - e2 * w[0]) / 2,
    ]
    kd = [x.diff() - u[0], y.diff() - u[1], z.diff() - u[2]]
    kd += [e.diff() - r for e, r in zip((e0, e1, e2, e3), quat_rates, strict=True)]
    kd += [a1.diff() - u[6], a2.diff() - u[7], knee.diff() - u[8]]
    oracle = kane_oracle(world, q, u, kd, bodies, loads, taus, (list(dcm), rotation))

    def sample(rng: np.random.Generator) -> tuple:
        quat = rng.standard_normal(4)
        pos = rng.uniform(-1, 1, 3)
        joints = rng.uniform(-1.2, 1.2, 3)
        return np.concatenate([pos, quat / np.linalg.norm(quat), joints]), rng.uniform(-2, 2, 9)

    compare(module, oracle, sample)


@pytest.mark.parametrize("text", [PENDULUM, HOPPER, STRIDER], ids=["pendulum", "hopper", "strider"])
def test_state_derivative_is_velocity_and_forward_dynamics(tmp_path: Path, text: str) -> None:
    model, module = compile_text(tmp_path, text)
    rng = np.random.default_rng(3)
    q = list(rng.uniform(-1, 1, model.nq))
    v = list(rng.uniform(-1, 1, model.nv))
    tau = list(rng.uniform(-1, 1, model.nv))
    qdot, vdot = module.state_derivative(q, v, tau)
    assert vdot == module.forward_dynamics(q, v, tau)
    assert len(qdot) == model.nq
    if model.nq == model.nv:
        assert qdot == v
    else:
        w, x, y, z = q[3:7]
        wx, wy, wz = v[3:6]
        expected = [v[0], v[1], v[2]]
        expected += [
            -0.5 * (x * wx + y * wy + z * wz),
            0.5 * (w * wx + y * wz - z * wy),
            0.5 * (w * wy + z * wx - x * wz),
            0.5 * (w * wz + x * wy - y * wx),
        ]
        assert qdot == pytest.approx(expected + v[6:], rel=1e-15, abs=1e-15)
