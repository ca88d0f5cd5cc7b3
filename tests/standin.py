"""Test helpers: forward kinematics straight from the model IR, and synthetic run directories.

``ModelKinematics`` follows the frame conventions of ``legdsl.ir.model`` (a body
frame sits at its joint, each joint primitive slides along or turns about its
axis, in order); it stands in for a generated dynamics module in the exporter
tests so that they do not depend on the dynamics compiler, and it is checked
against poses computed by hand in ``test_motion.py``.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np

from legdsl.ir.model import Model
from legdsl.sim.trajectory import Trajectory, empty


def axis_angle(axis: tuple[float, float, float], angle: float) -> np.ndarray:
    x, y, z = axis
    c, s = math.cos(angle), math.sin(angle)
    k = np.array([[0, -z, y], [z, 0, -x], [-y, x, 0]])
    return np.eye(3) + s * k + (1 - c) * (k @ k)


def quat_wxyz_matrix(w: float, x: float, y: float, z: float) -> np.ndarray:
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )


class ModelKinematics:
    def __init__(self, model: Model):
        self.model = model
        self.BODY_NAMES = tuple(b.name for b in model.bodies)

    def _frames(self, q: list[float]) -> list[tuple[np.ndarray, np.ndarray]]:
        frames: list[tuple[np.ndarray, np.ndarray]] = []
        names = list(self.BODY_NAMES)
        for body, joint in zip(self.model.bodies, self.model.joints, strict=True):
            if body.parent is None:
                p, r = np.array(joint.origin, dtype=float), np.eye(3)
            else:
                pp, pr = frames[names.index(body.parent)]
                p, r = pp + pr @ np.array(joint.origin), pr.copy()
            if joint.is_free_3d:
                s = joint.q_start
                p = p + np.array(q[s : s + 3])
                r = r @ quat_wxyz_matrix(*q[s + 3 : s + 7])
            else:
                for dof in joint.dofs:
                    value = q[dof.q_index]
                    if dof.motion == "slide":
                        p = p + r @ (value * np.array(dof.axis))
                    else:
                        r = r @ axis_angle(dof.axis, value)
            frames.append((p, r))
        return frames

    def body_poses(self, q: list[float]) -> list[tuple[tuple[float, ...], tuple[float, ...]]]:
        return [(tuple(p), tuple(r.reshape(9))) for p, r in self._frames(q)]

    def contact_positions(self, q: list[float]) -> list[tuple[float, float, float]]:
        frames = self._frames(q)
        names = list(self.BODY_NAMES)
        out = []
        for c in self.model.contacts:
            p, r = frames[names.index(c.body)]
            x, y, z = p + r @ np.array(c.point)
            out.append((float(x), float(y), float(z)))
        return out

    def center_of_mass(self, q: list[float]) -> tuple[float, float, float]:
        total = np.zeros(3)
        for body, (p, r) in zip(self.model.bodies, self._frames(q), strict=True):
            total += body.mass * (p + r @ np.array(body.com))
        x, y, z = total / self.model.total_mass
        return float(x), float(y), float(z)


def synthetic_run(
    model: Model,
    source: Path,
    out: Path,
    duration: float = 1.0,
    rate: float = 200.0,
    drop: float = 0.1,
) -> Trajectory:
    """A made-up run: the creature falls ``drop`` metres while walking forward and swinging its joints."""
    kin = ModelKinematics(model)
    n = int(round(duration * rate)) + 1
    tr = empty(
        n, model.nq, model.nv, len(model.contacts), len(model.legs),
        q_names=model.q_names, v_names=model.v_names,
        contact_names=tuple(c.name for c in model.contacts),
        leg_names=tuple(leg.name for leg in model.legs),
        leg_feet=tuple([c.name for c in model.contacts].index(leg.foot) for leg in model.legs),
        state_names=("FLIGHT", "STANCE"), total_mass=model.total_mass, planar=model.planar,
    )  # fmt: skip
    tr.t[:] = np.arange(n) / rate
    z_index = model.q_names.index("z")
    x_index = model.q_names.index("x")
    root = model.joints[0]
    for k, t in enumerate(tr.t):
        q = np.array(model.q0, dtype=float)
        q[x_index] += 0.5 * t
        q[z_index] += drop * max(0.0, 1 - t / (0.6 * duration))
        for d in model.dofs:
            if d.joint != root.name and d.motion == "hinge":
                q[d.q_index] += 0.25 * math.sin(2 * math.pi * t / duration)
        if root.is_free_3d:  # a slow yaw of the trunk
            yaw = 0.3 * t
            q[3:7] = (math.cos(yaw / 2), 0.0, 0.0, math.sin(yaw / 2))
        tr.q[k] = q
        tr.com[k] = kin.center_of_mass(list(q))
        tr.root_pos[k] = kin.body_poses(list(q))[0][0]
        tr.root_rpy[k, 2] = 0.3 * t if root.is_free_3d else 0.0
        touching = t > 0.6 * duration
        tr.contact[k] = 1 if touching else 0
        tr.force[k, :, 2] = model.total_mass * 9.81 / max(1, len(model.contacts)) if touching else 0
        tr.state[k] = 1 if touching else 0
        tr.speed_command[k] = 0.5
    tr.com_vel[:] = np.gradient(tr.com, tr.t, axis=0)
    tr.save(out)
    events = [
        {"t": float(tr.t[np.argmax(tr.contact[:, 0] > 0)]), "kind": "touchdown", "contact": c.name}
        for c in model.contacts
    ]
    info = {"source": str(source), "creature": model.name, "events": events, "status": "ok"}
    (out / "run.json").write_text(json.dumps(info, indent=2))
    return tr
