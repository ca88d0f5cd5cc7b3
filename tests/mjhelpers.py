"""Helpers shared by the MuJoCo tests: load an exported model, map states by name, draw states.

MuJoCo and legdsl both order coordinates root first, then depth-first through
the tree, but nothing here relies on that: coordinates are matched by name
(``model.joint(name).qposadr``/``dofadr`` on the MuJoCo side, the ``Dof``
indices on the legdsl side).
"""

from __future__ import annotations

import mujoco
import numpy as np

from legdsl.export.mjcf import model_to_mjcf
from legdsl.ir.model import Model


def load_mjcf(model: Model) -> mujoco.MjModel:
    """The export without anchor pads: MuJoCo's tree is then exactly the model's."""
    return mujoco.MjModel.from_xml_string(model_to_mjcf(model, pads=False))


def index_maps(model: Model, mj: mujoco.MjModel) -> tuple[np.ndarray, np.ndarray]:
    """(qmap, vmap): MuJoCo qpos[qmap[i]] is legdsl q[i], and qvel[vmap[i]] is legdsl v[i].

    Every MuJoCo coordinate is a legdsl one or, in an export with anchor pads, a pad's.
    """
    qmap = np.full(model.nq, -1)
    vmap = np.full(model.nv, -1)
    for j in model.joints:
        if j.is_free_3d:
            jj = mj.joint("root")
            assert mj.jnt_type[jj.id] == mujoco.mjtJoint.mjJNT_FREE
            qmap[j.q_start : j.q_start + 7] = jj.qposadr[0] + np.arange(7)
            vmap[j.v_start : j.v_start + 6] = jj.dofadr[0] + np.arange(6)
            continue
        for d in j.dofs:
            jj = mj.joint(d.name)
            qmap[d.q_index] = jj.qposadr[0]
            vmap[d.v_index] = jj.dofadr[0]
    # every other MuJoCo coordinate is an anchor pad's (an export with pads)
    known = {d.name for d in model.dofs} | {"root"}
    pads = [j for j in range(mj.njnt) if mj.joint(j).name not in known]
    assert all(mj.body(int(mj.jnt_bodyid[j])).name.endswith("_pad") for j in pads)
    assert sorted([*qmap, *mj.jnt_qposadr[pads]]) == list(range(mj.nq))
    assert sorted([*vmap, *mj.jnt_dofadr[pads]]) == list(range(mj.nv))
    return qmap, vmap


def random_state(model: Model, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """Joint values within +-1 rad / +-0.1 m, a random unit quaternion, velocities in +-1."""
    q = np.zeros(model.nq)
    for j in model.joints:
        if j.is_free_3d:
            quat = rng.normal(size=4)
            q[j.q_start : j.q_start + 7] = [*rng.uniform(-1, 1, 3), *(quat / np.linalg.norm(quat))]
        for d in j.dofs:
            q[d.q_index] = rng.uniform(-1, 1) * (1.0 if d.motion == "hinge" else 0.1)
    return q, rng.uniform(-1, 1, model.nv)


def set_state(
    mj: mujoco.MjModel, data: mujoco.MjData, maps: tuple[np.ndarray, np.ndarray], q, v
) -> None:
    qmap, vmap = maps
    data.qpos[qmap] = q
    data.qvel[vmap] = v


def rotation(axis, angle: float) -> np.ndarray:
    """Rotation by ``angle`` about unit ``axis`` (right-hand rule)."""
    a = np.asarray(axis, dtype=float)
    k = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * k @ k


def quat_to_matrix(quat) -> np.ndarray:
    w, x, y, z = quat
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )


def forward_kinematics(model: Model, q: np.ndarray) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """World (position, rotation) of every body frame, from the IR alone.

    This is model.py's rule written out: a body frame starts at its joint's
    origin in the parent frame with the parent's axes, then the joint's
    primitives act in order, each about or along its axis in the frame that
    the previous ones produced. A 3D free root is placed by (x, y, z) and its
    quaternion.
    """
    poses: dict[str, tuple[np.ndarray, np.ndarray]] = {}
    for body, joint in zip(model.bodies, model.joints, strict=True):
        if joint.parent is None:
            p, r = np.zeros(3), np.eye(3)
        else:
            p, r = poses[joint.parent]
        if joint.is_free_3d:
            s = joint.q_start
            poses[body.name] = (np.array(q[s : s + 3]), quat_to_matrix(q[s + 3 : s + 7]))
            continue
        p = p + r @ np.asarray(joint.origin)
        for d in joint.dofs:
            if d.motion == "slide":
                p = p + r @ (np.asarray(d.axis) * q[d.q_index])
            else:
                r = r @ rotation(d.axis, q[d.q_index])
        poses[body.name] = (p, r)
    return poses
