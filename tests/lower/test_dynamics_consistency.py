"""The generated functions of each shipped creature agree with one another.

The mass matrix (CRBA) against the one implied by the articulated-body
algorithm, the bias forces (RNEA) against forward dynamics, Jacobians and
velocities against finite differences of positions, energies against the
mass matrix and the bias forces. Positions are moved along a velocity with
the free root's quaternion advanced exactly, so every finite difference is
taken in the same coordinates as v.
"""

from __future__ import annotations

import math
from types import ModuleType

import numpy as np
import pytest
from conftest import SHIPPED, shipped_dynamics, shipped_model

STEP = 1e-6  # central differences: error ~ STEP**2


def random_state(name: str, seed: int) -> tuple[list[float], list[float], list[float]]:
    model = shipped_model(name)
    rng = np.random.default_rng(seed)
    q = np.array(model.q0) + rng.uniform(-0.6, 0.6, model.nq)
    if model.nq == model.nv + 1:
        q[3:7] /= np.linalg.norm(q[3:7])
    v = rng.uniform(-1.5, 1.5, model.nv)
    tau = rng.uniform(-5, 5, model.nv)
    return [float(x) for x in q], [float(x) for x in v], [float(x) for x in tau]


def advance(module: ModuleType, q: list[float], v: list[float], dt: float) -> list[float]:
    """q moved for dt at constant velocity v (exactly, for the free root's quaternion)."""
    if module.NQ == module.NV:
        return [qi + dt * vi for qi, vi in zip(q, v, strict=True)]
    w, x, y, z = q[3:7]
    wx, wy, wz = (dt * c for c in v[3:6])
    angle = math.sqrt(wx * wx + wy * wy + wz * wz)
    c = math.cos(angle / 2)
    s = math.sin(angle / 2) / angle if angle > 0 else 0.5
    dw, dx, dy, dz = c, s * wx, s * wy, s * wz
    quat = [  # q ⊗ dq: the rotation dq in body axes
        w * dw - x * dx - y * dy - z * dz,
        w * dx + x * dw + y * dz - z * dy,
        w * dy - x * dz + y * dw + z * dx,
        w * dz + x * dy - y * dx + z * dw,
    ]
    pos = [q[k] + dt * v[k] for k in range(3)]
    rest = [qi + dt * vi for qi, vi in zip(q[7:], v[6:], strict=True)]
    return pos + quat + rest


def derivative(module: ModuleType, f, q: list[float], v: list[float]) -> np.ndarray:  # type: ignore[no-untyped-def]
    ahead = np.array(f(advance(module, q, v, STEP)), dtype=float)
    behind = np.array(f(advance(module, q, v, -STEP)), dtype=float)
    return (ahead - behind) / (2 * STEP)


def unit(n: int, j: int) -> list[float]:
    return [1.0 if k == j else 0.0 for k in range(n)]


def assert_close(
    ours: np.ndarray, ref: np.ndarray, rtol: float, what: str, scale: float | None = None
) -> None:
    """Agreement relative to the largest reference entry (or to ``scale``)."""
    scale = scale or max(float(np.abs(ref).max()), 1e-12)
    err = float(np.abs(np.asarray(ours) - np.asarray(ref)).max()) / scale
    assert err < rtol, f"{what}: relative error {err:.2e}"


@pytest.mark.parametrize("name", SHIPPED)
def test_crba_mass_matrix_is_the_inverse_of_aba(name: str) -> None:
    dyn = shipped_dynamics(name)
    q, v, _ = random_state(name, 1)
    mass = np.array(dyn.mass_matrix(q))
    assert mass.shape == (dyn.NV, dyn.NV)
    assert np.array_equal(mass, mass.T)
    assert np.linalg.eigvalsh(mass).min() > 0
    free = np.array(dyn.forward_dynamics(q, v, [0.0] * dyn.NV))
    columns = [np.array(dyn.forward_dynamics(q, v, unit(dyn.NV, j))) - free for j in range(dyn.NV)]
    inverse = np.column_stack(columns)
    assert_close(inverse @ mass, np.eye(dyn.NV), 1e-9, "M^-1 (from ABA) times M (from CRBA)")


@pytest.mark.parametrize("name", SHIPPED)
def test_rnea_bias_forces_match_aba(name: str) -> None:
    dyn = shipped_dynamics(name)
    for seed in range(3):
        q, v, tau = random_state(name, seed)
        mass = np.array(dyn.mass_matrix(q))
        bias = np.array(dyn.bias_forces(q, v))
        assert_close(bias, -mass @ np.array(dyn.forward_dynamics(q, v, [0.0] * dyn.NV)), 1e-10, "h")
        qdd = np.array(dyn.forward_dynamics(q, v, tau))
        assert_close(mass @ qdd + bias, np.array(tau), 1e-10, "M qdd + h = tau")


@pytest.mark.parametrize("name", SHIPPED)
def test_contact_jacobians_are_derivatives_of_contact_positions(name: str) -> None:
    dyn = shipped_dynamics(name)
    q, v, _ = random_state(name, 4)
    jacobians = np.array(dyn.contact_jacobians(q))
    assert jacobians.shape == (len(dyn.CONTACT_NAMES), 3, dyn.NV)
    for j in range(dyn.NV):
        column = derivative(dyn, dyn.contact_positions, q, unit(dyn.NV, j))
        what = f"Jacobian column {dyn.V_NAMES[j]}"
        assert_close(jacobians[:, :, j], column, 1e-8, what, scale=np.abs(jacobians).max())
    velocities = np.array(dyn.contact_velocities(q, v))
    assert_close(velocities, jacobians @ np.array(v), 1e-12, "contact velocities = J v")
    assert_close(velocities, derivative(dyn, dyn.contact_positions, q, v), 1e-8, "d/dt positions")


@pytest.mark.parametrize("name", SHIPPED)
def test_angular_jacobians_turn_the_contact_bodies(name: str) -> None:
    dyn = shipped_dynamics(name)
    model = shipped_model(name)
    q, v, _ = random_state(name, 5)
    index = [dyn.BODY_NAMES.index(c.body) for c in model.contacts]

    def rotations(qq: list[float]) -> np.ndarray:
        poses = dyn.body_poses(qq)
        return np.array([np.reshape(poses[i][1], (3, 3)) for i in index])

    rot = rotations(q)
    rate = derivative(dyn, rotations, q, v)
    for k in range(len(index)):
        spin = rate[k] @ rot[k].T  # skew(world angular velocity)
        omega = np.array([spin[2, 1], spin[0, 2], spin[1, 0]])
        expected = np.array(dyn.contact_angular_jacobians(q))[k] @ np.array(v)
        assert_close(omega, expected, 1e-8, "angular velocity")


@pytest.mark.parametrize("name", SHIPPED)
def test_body_velocities_are_rates_of_the_body_poses(name: str) -> None:
    dyn = shipped_dynamics(name)
    q, v, _ = random_state(name, 7)

    def origins(qq: list[float]) -> np.ndarray:
        return np.array([origin for origin, _ in dyn.body_poses(qq)])

    def rotations(qq: list[float]) -> np.ndarray:
        return np.array([np.reshape(rot, (3, 3)) for _, rot in dyn.body_poses(qq)])

    velocities = dyn.body_velocities(q, v)
    linear = np.array([lin for lin, _ in velocities])
    assert_close(linear, derivative(dyn, origins, q, v), 1e-8, "body origin velocities")
    rot, rate = rotations(q), derivative(dyn, rotations, q, v)
    for k, (_, angular) in enumerate(velocities):
        spin = rate[k] @ rot[k].T  # skew(world angular velocity)
        omega = np.array([spin[2, 1], spin[0, 2], spin[1, 0]])
        assert_close(np.array(angular), omega, 1e-8, f"angular velocity of {dyn.BODY_NAMES[k]}")


@pytest.mark.parametrize("name", SHIPPED)
def test_poses_mass_centre_and_energies_agree(name: str) -> None:
    dyn = shipped_dynamics(name)
    model = shipped_model(name)
    q, v, _ = random_state(name, 6)
    poses = dyn.body_poses(q)
    centre = np.zeros(3)
    for body, (origin, rot) in zip(model.bodies, poses, strict=True):
        r = np.reshape(rot, (3, 3))
        assert_close(r @ r.T, np.eye(3), 1e-12, "rotation")
        centre += body.mass * (np.array(origin) + r @ np.array(body.com))
    centre /= dyn.TOTAL_MASS
    assert_close(np.array(dyn.center_of_mass(q)), centre, 1e-12, "mass centre")
    for contact, position in zip(model.contacts, dyn.contact_positions(q), strict=True):
        origin, rot = poses[dyn.BODY_NAMES.index(contact.body)]
        expected = np.array(origin) + np.reshape(rot, (3, 3)) @ np.array(contact.point)
        assert_close(np.array(position), expected, 1e-12, "contact position")
    com_rate = derivative(dyn, dyn.center_of_mass, q, v)
    assert_close(
        np.array(dyn.center_of_mass_velocity(q, v)), com_rate, 1e-8, "mass centre velocity"
    )
    mass = np.array(dyn.mass_matrix(q))
    kinetic = 0.5 * np.array(v) @ mass @ np.array(v)
    assert math.isclose(dyn.kinetic_energy(q, v), kinetic, rel_tol=1e-12)
    assert math.isclose(
        dyn.potential_energy(q), -dyn.TOTAL_MASS * float(np.dot(dyn.GRAVITY, centre)), rel_tol=1e-12
    )
    # gravity's generalized force is minus the gradient of the potential energy
    gravity = np.array(dyn.bias_forces(q, [0.0] * dyn.NV))
    gradient = [derivative(dyn, dyn.potential_energy, q, unit(dyn.NV, j)) for j in range(dyn.NV)]
    assert_close(gravity, np.array(gradient), 1e-8, "h(q, 0) = dV/dq")
