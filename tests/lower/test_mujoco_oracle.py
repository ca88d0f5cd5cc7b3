"""The generated dynamics of every shipped creature against MuJoCo on the exported MJCF.

MuJoCo is a reference no one here wrote: for each creature the exported model
is loaded, and at random states (joint values within +-1 rad / +-0.1 m, a
random unit quaternion, random velocities), with contacts and actuators off,
its mass matrix (``mj_fullM``), bias forces (``qfrc_bias``) and accelerations
(``qacc_smooth``, without and with a random ``qfrc_applied``) must equal those
of ``generated/NAME/dynamics.py`` to 1e-9, norm-wise relative. Coordinates are
matched by name, never by position. Point kinematics, the mass centre and the
energies are compared too.

These tests skip only when ``generated/NAME/dynamics.py`` does not exist (the
compiler has not produced it); any other problem fails.
"""

from __future__ import annotations

import importlib.util
from types import ModuleType

import mujoco
import numpy as np
import pytest
from conftest import CREATURES, ROOT
from mjhelpers import index_maps, load_mjcf, random_state, set_state

from legdsl.check.source import check_model
from legdsl.ir.model import Model

SHIPPED = ["kangaroo", "biped", "quadruped"]
GENERATED = ROOT / "generated"
STATES = 20
RTOL = 1e-9


def _load_generated(name: str) -> ModuleType:
    path = GENERATED / name / "dynamics.py"
    if not path.is_file():
        pytest.skip(
            f"!!! MUJOCO ORACLE NOT RUN for '{name}': {path.relative_to(ROOT)} does not exist. "
            f"Generate it (legdsl compile creatures/{name}.leg) to check the dynamics. !!!"
        )
    spec = importlib.util.spec_from_file_location(f"_oracle_generated_{name}_dynamics", path)
    assert spec is not None and spec.loader is not None, f"cannot import {path}"
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def close(a: object, b: object, rtol: float = RTOL) -> bool:
    """Norm-wise relative closeness: |a - b| <= rtol * max(1, |b|)."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    assert a.shape == b.shape, f"shapes differ: {a.shape} vs {b.shape}"
    return bool(np.linalg.norm(a - b) <= rtol * max(1.0, float(np.linalg.norm(b))))


def _err(a: object, b: object) -> str:
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    return f"|a-b| = {np.linalg.norm(a - b):.3e}, |b| = {np.linalg.norm(b):.3e}"


class Oracle:
    """The exported MuJoCo model with contacts and actuators off, evaluated at legdsl states."""

    def __init__(self, model: Model):
        self.model = model
        self.mj = load_mjcf(model)
        self.mj.opt.disableflags |= mujoco.mjtDisableBit.mjDSBL_CONTACT
        # The exported springs and servos would push with ctrl = 0; the dynamics has no actuators.
        self.mj.opt.disableflags |= mujoco.mjtDisableBit.mjDSBL_ACTUATION
        self.mj.opt.enableflags |= mujoco.mjtEnableBit.mjENBL_ENERGY
        self.data = mujoco.MjData(self.mj)
        self.qmap, self.vmap = index_maps(model, self.mj)
        self.root = self.mj.body(model.bodies[0].name).id

    def forward(self, q: np.ndarray, v: np.ndarray, tau: np.ndarray | None = None) -> None:
        set_state(self.mj, self.data, (self.qmap, self.vmap), q, v)
        self.data.qfrc_applied[:] = 0.0
        if tau is not None:
            self.data.qfrc_applied[self.vmap] = tau
        mujoco.mj_forward(self.mj, self.data)

    def mass_matrix(self) -> np.ndarray:
        full = np.zeros((self.mj.nv, self.mj.nv))
        mujoco.mj_fullM(self.mj, self.data, full)
        return full[np.ix_(self.vmap, self.vmap)]

    def bias(self) -> np.ndarray:
        return self.data.qfrc_bias[self.vmap].copy()

    def qacc_smooth(self) -> np.ndarray:
        return self.data.qacc_smooth[self.vmap].copy()

    def site_jacobian(self, name: str) -> np.ndarray:
        jacp = np.zeros((3, self.mj.nv))
        mujoco.mj_jacSite(self.mj, self.data, jacp, None, self.mj.site(name).id)
        return jacp[:, self.vmap]

    def com_jacobian(self) -> np.ndarray:
        jacp = np.zeros((3, self.mj.nv))
        mujoco.mj_jacSubtreeCom(self.mj, self.data, jacp, self.root)
        return jacp[:, self.vmap]


def _states(model: Model, seed: int) -> list[tuple[np.ndarray, np.ndarray, np.ndarray]]:
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(STATES):
        q, v = random_state(model, rng)
        out.append((q, v, rng.normal(scale=5.0, size=model.nv)))
    return out


@pytest.fixture(params=SHIPPED)
def case(request: pytest.FixtureRequest) -> tuple[Model, ModuleType, Oracle]:
    name = request.param
    dyn = _load_generated(name)
    model = check_model(CREATURES / f"{name}.leg")
    return model, dyn, Oracle(model)


def test_generated_metadata_matches_model_and_mujoco(
    case: tuple[Model, ModuleType, Oracle],
) -> None:
    model, dyn, oracle = case
    assert (dyn.NQ, dyn.NV) == (model.nq, model.nv) == (oracle.mj.nq, oracle.mj.nv)
    assert tuple(dyn.Q_NAMES) == model.q_names
    assert tuple(dyn.V_NAMES) == model.v_names
    assert tuple(dyn.BODY_NAMES) == tuple(b.name for b in model.bodies)
    assert tuple(dyn.CONTACT_NAMES) == tuple(c.name for c in model.contacts)
    assert close(dyn.GRAVITY, oracle.mj.opt.gravity)
    assert close(dyn.TOTAL_MASS, mujoco.mj_getTotalmass(oracle.mj))


def test_mass_matrix_bias_and_accelerations(case: tuple[Model, ModuleType, Oracle]) -> None:
    model, dyn, oracle = case
    for k, (q, v, tau) in enumerate(_states(model, seed=len(model.name) * 101)):
        qs, vs, taus = list(q), list(v), list(tau)
        oracle.forward(q, v)
        m_ref, h_ref, a_ref = oracle.mass_matrix(), oracle.bias(), oracle.qacc_smooth()
        m_gen = dyn.mass_matrix(qs)
        assert close(m_gen, m_ref), f"state {k}: mass matrix, {_err(m_gen, m_ref)}"
        h_gen = dyn.bias_forces(qs, vs)
        assert close(h_gen, h_ref), f"state {k}: bias forces, {_err(h_gen, h_ref)}"
        a_gen = dyn.forward_dynamics(qs, vs, [0.0] * model.nv)
        assert close(a_gen, a_ref), f"state {k}: qacc (tau = 0), {_err(a_gen, a_ref)}"

        oracle.forward(q, v, tau)
        a_ref = oracle.qacc_smooth()
        a_gen = dyn.forward_dynamics(qs, vs, taus)
        assert close(a_gen, a_ref), f"state {k}: qacc (random tau), {_err(a_gen, a_ref)}"
        qdot, vdot = dyn.state_derivative(qs, vs, taus)
        assert close(vdot, a_ref), f"state {k}: state_derivative vdot, {_err(vdot, a_ref)}"
        assert close(qdot, _qdot(model, q, v)), f"state {k}: state_derivative qdot"


def quat_rate(quat: np.ndarray, w_body: np.ndarray) -> np.ndarray:
    """d(quat)/dt = quat * (0, w) / 2 for an angular velocity w in body axes.

    (MuJoCo's ``mju_derivQuat`` uses another convention; this one matches how
    ``mj_integratePos`` moves a free joint, see ``test_quat_rate_is_mujocos``.)
    """
    w, x, y, z = quat
    wx, wy, wz = w_body
    return 0.5 * np.array(
        [
            -(x * wx + y * wy + z * wz),
            w * wx + y * wz - z * wy,
            w * wy + z * wx - x * wz,
            w * wz + x * wy - y * wx,
        ]
    )


def _qdot(model: Model, q: np.ndarray, v: np.ndarray) -> np.ndarray:
    """dq/dt: v for 1-DOF coordinates, the quaternion rate for the free root."""
    qdot = np.zeros(model.nq)
    for j in model.joints:
        if j.is_free_3d:
            s, t = j.q_start, j.v_start
            qdot[s : s + 3] = v[t : t + 3]
            qdot[s + 3 : s + 7] = quat_rate(q[s + 3 : s + 7], v[t + 3 : t + 6])
        for d in j.dofs:
            qdot[d.q_index] = v[d.v_index]
    return qdot


def test_quat_rate_is_mujocos() -> None:
    """The expected qdot above is how MuJoCo itself advances a free joint (central difference)."""
    model = check_model(CREATURES / "biped.leg")
    oracle = Oracle(model)
    rng = np.random.default_rng(9)
    h = 1e-6
    for _ in range(10):
        q, v = random_state(model, rng)
        qpos = np.zeros(oracle.mj.nq)
        qvel = np.zeros(oracle.mj.nv)
        qpos[oracle.qmap], qvel[oracle.vmap] = q, v
        ahead, behind = qpos.copy(), qpos.copy()
        mujoco.mj_integratePos(oracle.mj, ahead, qvel, h)
        mujoco.mj_integratePos(oracle.mj, behind, qvel, -h)
        rate = ((ahead - behind) / (2 * h))[oracle.qmap]
        assert np.abs(rate - _qdot(model, q, v)).max() < 1e-8


def test_point_kinematics_and_energy(case: tuple[Model, ModuleType, Oracle]) -> None:
    model, dyn, oracle = case
    n = len(model.contacts)
    for k, (q, v, _) in enumerate(_states(model, seed=len(model.name) * 211)):
        qs, vs = list(q), list(v)
        oracle.forward(q, v)
        pos = np.reshape(np.asarray(dyn.contact_positions(qs), dtype=float), (n, 3))
        vel = np.reshape(np.asarray(dyn.contact_velocities(qs, vs), dtype=float), (n, 3))
        jac = np.asarray(dyn.contact_jacobians(qs), dtype=float).reshape(n, 3, model.nv)
        for i, c in enumerate(model.contacts):
            j_ref = oracle.site_jacobian(c.name)
            assert close(pos[i], oracle.data.site(c.name).xpos), f"state {k}: {c.name} position"
            assert close(jac[i], j_ref), f"state {k}: {c.name} Jacobian, {_err(jac[i], j_ref)}"
            assert close(vel[i], j_ref @ v), f"state {k}: {c.name} velocity"
        com = oracle.data.subtree_com[oracle.root]
        assert close(dyn.center_of_mass(qs), com), f"state {k}: mass centre"
        com_vel = oracle.com_jacobian() @ v
        assert close(dyn.center_of_mass_velocity(qs, vs), com_vel), f"state {k}: COM velocity"
        kinetic, potential = oracle.data.energy[1], oracle.data.energy[0]
        assert close(dyn.kinetic_energy(qs, vs), kinetic), f"state {k}: kinetic energy"
        assert close(dyn.potential_energy(qs), potential), f"state {k}: gravity potential"


def test_oracle_is_not_vacuous() -> None:
    """Without generated code, show that the comparison can fail: a 1e-6 change is caught."""
    model = check_model(CREATURES / "biped.leg")
    oracle = Oracle(model)
    q, v, _ = _states(model, seed=1)[0]
    oracle.forward(q, v)
    m = oracle.mass_matrix()
    assert close(m, m.copy())
    assert not close(m * (1 + 1e-6), m)
    assert np.allclose(m, m.T) and np.linalg.eigvalsh(m).min() > 0
    assert oracle.bias().shape == (model.nv,)
    assert not np.allclose(oracle.bias(), 0.0)
