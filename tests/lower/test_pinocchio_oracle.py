"""The generated dynamics of every shipped creature against Pinocchio on the exported URDF.

A second reference no one here wrote, beside MuJoCo (``test_mujoco_oracle.py``), and through
the other export: the URDF from ``legdsl export --format urdf --base free`` is loaded by
Pinocchio (a 3D free root as its ``JointModelFreeFlyer``), and at random states its
articulated-body forward dynamics (``aba``) and its mass matrix (``crba``) must equal
``generated/NAME/dynamics.py``'s to 1e-12, norm-wise relative.

Conventions are converted, never assumed equal: coordinates are matched by name; an
unlimited hinge is a URDF ``continuous`` joint, which Pinocchio holds as (cos, sin); the
free root's quaternion is (x, y, z, w) there and (w, x, y, z) here; and its linear velocity,
force and acceleration are in the root's frame there, in the world here (a legdsl velocity
``v`` is Pinocchio's ``T v`` with ``T = diag(R^T, 1)``, a force ``f`` is ``T f``, and the
world acceleration of the root's origin is ``R (a + w x v)`` of Pinocchio's local ``a``).
"""

from __future__ import annotations

import zlib

import numpy as np
import pinocchio as pin
import pytest
from conftest import SHIPPED, shipped_dynamics, shipped_model
from mjhelpers import quat_to_matrix, random_state

from legdsl.export.urdf import model_to_urdf
from legdsl.ir.model import Model

STATES = 20
RTOL = 1e-12


class Reference:
    """The URDF export in Pinocchio, and the conversion of legdsl states to its own."""

    def __init__(self, model: Model):
        self.model = model
        self.free = model.joints[0].is_free_3d
        urdf = model_to_urdf(model, base="free")
        root = (pin.JointModelFreeFlyer(),) if self.free else ()
        self.pin = pin.buildModelFromXML(urdf, *root)
        self.pin.gravity.linear = np.array(model.gravity, dtype=float)
        self.data = self.pin.createData()
        # Pinocchio's velocity index of each legdsl velocity
        self.vmap = np.zeros(model.nv, dtype=int)
        for j in model.joints:
            if j.is_free_3d:
                self.vmap[j.v_start : j.v_start + 6] = np.arange(6)
            for d in j.dofs:
                self.vmap[d.v_index] = self._joint(d.name).idx_v
        assert sorted(self.vmap) == list(range(self.pin.nv)), "every velocity matched by name"

    def _joint(self, name: str) -> pin.JointModel:
        jid = self.pin.getJointId(name)
        assert jid < self.pin.njoints, f"no joint {name!r} in the URDF"
        return self.pin.joints[jid]

    def convert(self, q: np.ndarray, v: np.ndarray, tau: np.ndarray) -> tuple[np.ndarray, ...]:
        """Pinocchio's (q, v, tau) for legdsl's, and the root's rotation R."""
        qp, vp, tp = pin.neutral(self.pin), np.zeros(self.pin.nv), np.zeros(self.pin.nv)
        rot = np.eye(3)
        for j in self.model.joints:
            if j.is_free_3d:
                s, t = j.q_start, j.v_start
                rot = quat_to_matrix(q[s + 3 : s + 7])
                qp[0:7] = [*q[s : s + 3], *q[s + 4 : s + 7], q[s + 3]]
                vp[0:3], vp[3:6] = rot.T @ v[t : t + 3], v[t + 3 : t + 6]
                tp[0:3], tp[3:6] = rot.T @ tau[t : t + 3], tau[t + 3 : t + 6]
            for d in j.dofs:
                jm = self._joint(d.name)
                angle = q[d.q_index]
                qp[jm.idx_q : jm.idx_q + jm.nq] = (
                    (np.cos(angle), np.sin(angle)) if jm.nq == 2 else angle
                )
                vp[jm.idx_v], tp[jm.idx_v] = v[d.v_index], tau[d.v_index]
        return qp, vp, tp, rot

    def accelerations(self, q: np.ndarray, v: np.ndarray, tau: np.ndarray) -> np.ndarray:
        qp, vp, tp, rot = self.convert(q, v, tau)
        a = np.array(pin.aba(self.pin, self.data, qp, vp, tp))
        out = a[self.vmap]
        if self.free:  # the root origin's acceleration in the world
            out[0:3] = rot @ (a[0:3] + np.cross(vp[3:6], vp[0:3]))
        return out

    def mass_matrix(self, q: np.ndarray) -> np.ndarray:
        qp, _, _, rot = self.convert(q, np.zeros(self.model.nv), np.zeros(self.model.nv))
        upper = np.array(pin.crba(self.pin, self.data, qp))
        full = np.triu(upper) + np.triu(upper, 1).T
        full = full[np.ix_(self.vmap, self.vmap)]
        if self.free:  # kinetic energy 1/2 (T v)' M (T v)
            t = np.eye(self.model.nv)
            t[0:3, 0:3] = rot.T
            full = t.T @ full @ t
        return full


def _relative(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.linalg.norm(a - b) / max(1.0, float(np.linalg.norm(b))))


@pytest.mark.parametrize("name", SHIPPED)
def test_forward_dynamics_and_mass_matrix_equal_pinocchios(name: str) -> None:
    model, dynamics = shipped_model(name), shipped_dynamics(name)
    reference = Reference(model)
    rng = np.random.default_rng(zlib.crc32(f"pinocchio-{name}".encode()))
    for _ in range(STATES):
        q, v = random_state(model, rng)
        v = 3.0 * v  # rates that make the velocity terms count
        tau = rng.uniform(-20.0, 20.0, model.nv)
        ours = np.array(dynamics.forward_dynamics(list(q), list(v), list(tau)))
        theirs = reference.accelerations(q, v, tau)
        assert _relative(ours, theirs) < RTOL, (name, ours, theirs)
        mass = np.array(dynamics.mass_matrix(list(q)))
        assert _relative(mass, reference.mass_matrix(q)) < RTOL, name


def test_a_wrong_convention_is_caught() -> None:
    """The check can fail: a force on the root passed in the world's axes, not the root's."""
    model, dynamics = shipped_model("biped"), shipped_dynamics("biped")
    reference = Reference(model)
    q, v = random_state(model, np.random.default_rng(7))
    q[3:7] = [np.cos(0.4), 0.0, 0.0, np.sin(0.4)]  # yawed by 0.8 rad
    tau = np.zeros(model.nv)
    tau[0] = 50.0  # pushed along the world's x
    qp, vp, tp, rot = reference.convert(q, v, tau)
    tp[0:3] = tau[0:3]  # the mistake
    a = np.array(pin.aba(reference.pin, reference.data, qp, vp, tp))[reference.vmap]
    a[0:3] = rot @ (a[0:3] + np.cross(vp[3:6], vp[0:3]))
    ours = np.array(dynamics.forward_dynamics(list(q), list(v), list(tau)))
    assert _relative(ours, reference.accelerations(q, v, tau)) < RTOL
    assert _relative(ours, a) > 1e-2
