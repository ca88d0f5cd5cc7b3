"""The link tree as a chain of one-degree-of-freedom frames, and its symbolic kinematics.

Every joint becomes one node per ``Dof`` primitive (a hinge or a slide),
applied in order, each frame moving with the ones before it (so a ball joint
is roll, then pitch about the rolled y axis, then yaw: what MuJoCo does with
several hinges in one body). The last node of a joint carries the body; the
others are massless. A weld (or a fixed root) is one node with no freedom;
the 3D free root is one six-DOF node with MuJoCo's free-joint coordinates.

``Tree`` gives, for one generated function (one ``Block``), each node's
transform from its parent, its world pose, its spatial velocity and its
velocity-product acceleration, each built once on demand.
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy
from sympy import Expr, Symbol

from legdsl.ir.model import Body, Dof, Joint, Model, Vec3
from legdsl.lower.spatial import (
    EYE,
    ZERO,
    ZERO_MOTION,
    Mat,
    Motion,
    RigidInertia,
    Transform,
    Vec,
    add,
    cross,
    let_mat,
    let_vec,
    matmul,
    matvec,
    rodrigues,
    scale,
    transpose,
)
from legdsl.lower.straightline import Block, num

# Locals in generated functions never take these names.
API_NAMES = (
    "mass_matrix",
    "bias_forces",
    "forward_dynamics",
    "state_derivative",
    "contact_positions",
    "contact_velocities",
    "contact_jacobians",
    "contact_angular_jacobians",
    "body_poses",
    "body_velocities",
    "center_of_mass",
    "center_of_mass_velocity",
    "kinetic_energy",
    "potential_energy",
)
RESERVED = frozenset({"q", "v", "tau", "math", *API_NAMES})


@dataclass(frozen=True)
class Node:
    """One frame of the tree: a hinge or slide primitive, a weld, or the 3D free root."""

    index: int
    parent: int  # -1: the world
    kind: str  # hinge, slide, weld or free3d
    offset: Vec3  # the frame's origin in the parent frame, at zero coordinate
    axis: Vec3  # unit axis of a hinge or slide, the same in the parent and this frame
    dof: Dof | None
    joint: Joint
    body: Body | None  # the body this frame carries; None for a joint's inner frames

    @property
    def label(self) -> str:
        what = self.dof.name if self.dof else self.joint.name
        body = f"{self.body.name}, " if self.body else ""
        return f"{body}{self.kind} {what}"


def build_nodes(model: Model) -> tuple[Node, ...]:
    nodes: list[Node] = []
    carrier: dict[str, int] = {}  # body name -> the node that carries it
    for joint, body in zip(model.joints, model.bodies, strict=True):
        parent = -1 if joint.parent is None else carrier[joint.parent]
        if joint.is_free_3d:
            nodes.append(
                Node(len(nodes), parent, "free3d", joint.origin, (0.0, 0.0, 0.0), None, joint, body)
            )
        elif not joint.dofs:
            nodes.append(
                Node(len(nodes), parent, "weld", joint.origin, (0.0, 0.0, 0.0), None, joint, body)
            )
        else:
            last = len(joint.dofs) - 1
            for k, dof in enumerate(joint.dofs):
                kind = "hinge" if dof.motion == "hinge" else "slide"
                offset = joint.origin if k == 0 else (0.0, 0.0, 0.0)
                nodes.append(
                    Node(
                        len(nodes),
                        parent,
                        kind,
                        offset,
                        dof.axis,
                        dof,
                        joint,
                        body if k == last else None,
                    )
                )
                parent = len(nodes) - 1
        carrier[body.name] = len(nodes) - 1
    return tuple(nodes)


def vec(v: Vec3) -> Vec:
    return (num(v[0]), num(v[1]), num(v[2]))


def rigid_inertia(body: Body) -> RigidInertia:
    """The body's spatial inertia about its frame origin, with exact zeros where the model has them."""
    rows = body.inertia
    inertia = (vec(rows[0]), vec(rows[1]), vec(rows[2]))
    return RigidInertia.of_body(num(body.mass), vec(body.com), inertia)


class Tree:
    """Symbolic kinematics of the link tree inside one generated function."""

    def __init__(self, model: Model, nodes: tuple[Node, ...], block: Block):
        self.model = model
        self.nodes = nodes
        self.block = block
        self.gravity = vec(model.gravity)
        self._rotation: dict[int, Mat] = {}
        self._transform: dict[int, Transform] = {}
        self._world: dict[int, tuple[Mat, Vec]] = {}
        self._velocity: dict[int, Motion] = {}

    # ------------------------------------------------------------ inputs
    def q(self, dof: Dof) -> Symbol:
        return self.block.input(dof.name, "q", dof.q_index)

    def qd(self, dof: Dof) -> Symbol:
        return self.block.input(f"qd_{dof.name}", "v", dof.v_index)

    def tau(self, dof: Dof) -> Symbol:
        return self.block.input(f"tau_{dof.name}", "tau", dof.v_index)

    def root_q(self, node: Node, k: int) -> Symbol:
        """Coordinate k of the 3D free root: x, y, z, qw, qx, qy, qz."""
        i = node.joint.q_start + k
        return self.block.input(self.model.q_names[i], "q", i)

    def root_v(self, node: Node, k: int) -> Symbol:
        """Velocity k of the 3D free root: vx, vy, vz (world), wx, wy, wz (body)."""
        i = node.joint.v_start + k
        return self.block.input(self.model.v_names[i], "v", i)

    def root_tau(self, node: Node, k: int) -> Symbol:
        i = node.joint.v_start + k
        return self.block.input(f"tau_{self.model.v_names[i]}", "tau", i)

    def cos_sin(self, dof: Dof) -> tuple[Expr, Expr]:
        angle = self.q(dof)
        return (
            self.block.define(f"c_{angle.name}", sympy.cos(angle)),
            self.block.define(f"s_{angle.name}", sympy.sin(angle)),
        )

    # ------------------------------------------------------------ per node
    def joint_motion(self, node: Node) -> Motion:
        """The unit motion S of a hinge or slide, in the node's frame."""
        axis = vec(node.axis)
        return Motion(axis, ZERO) if node.kind == "hinge" else Motion(ZERO, axis)

    def rate(self, node: Node) -> Symbol:
        assert node.dof is not None
        return self.qd(node.dof)

    def rotation(self, i: int) -> Mat:
        """The node's axes in its parent's axes."""
        if i not in self._rotation:
            node = self.nodes[i]
            if node.kind == "hinge":
                assert node.dof is not None
                c, s = self.cos_sin(node.dof)
                rot = let_mat(self.block, rodrigues(vec(node.axis), c, s))
            elif node.kind == "free3d":
                rot = let_mat(self.block, self._quaternion_rotation(node))
            else:
                rot = EYE
            self._rotation[i] = rot
        return self._rotation[i]

    def _quaternion_rotation(self, node: Node) -> Mat:
        """The rotation of a quaternion, scaled by its norm so it stays a rotation if not unit."""
        w, x, y, z = (self.root_q(node, k) for k in range(3, 7))
        s = self.block.define("qscale", 2 / (w * w + x * x + y * y + z * z))
        return (
            (1 - s * (y * y + z * z), s * (x * y - w * z), s * (x * z + w * y)),
            (s * (x * y + w * z), 1 - s * (x * x + z * z), s * (y * z - w * x)),
            (s * (x * z - w * y), s * (y * z + w * x), 1 - s * (x * x + y * y)),
        )

    def origin(self, i: int) -> Vec:
        """The node's origin in its parent's frame."""
        node = self.nodes[i]
        offset = vec(node.offset)
        if node.kind == "slide":
            assert node.dof is not None
            return let_vec(self.block, add(offset, scale(self.q(node.dof), vec(node.axis))))
        if node.kind == "free3d":
            return add(offset, (self.root_q(node, 0), self.root_q(node, 1), self.root_q(node, 2)))
        return offset

    def transform(self, i: int) -> Transform:
        if i not in self._transform:
            self._transform[i] = Transform(transpose(self.rotation(i)), self.origin(i))
        return self._transform[i]

    def world(self, i: int) -> tuple[Mat, Vec]:
        """The node's orientation and origin in the world."""
        if i not in self._world:
            node = self.nodes[i]
            rot, origin = self.rotation(i), self.origin(i)
            if node.parent >= 0:
                parent_rot, parent_origin = self.world(node.parent)
                origin = let_vec(self.block, add(parent_origin, matvec(parent_rot, origin)))
                rot = let_mat(self.block, matmul(parent_rot, rot))
            self._world[i] = (rot, origin)
        return self._world[i]

    def velocity(self, i: int) -> Motion:
        """The node's spatial velocity in its own frame."""
        if i not in self._velocity:
            node = self.nodes[i]
            if node.kind == "free3d":
                w = (self.root_v(node, 3), self.root_v(node, 4), self.root_v(node, 5))
                v_world = (self.root_v(node, 0), self.root_v(node, 1), self.root_v(node, 2))
                v = Motion(w, matvec(transpose(self.rotation(i)), v_world))
            else:
                v = (
                    self.transform(i).motion(self.velocity(node.parent))
                    if node.parent >= 0
                    else ZERO_MOTION
                )
                if node.dof is not None:
                    v = v + self.joint_motion(node).scaled(self.rate(node))
            self._velocity[i] = v.let(self.block)
        return self._velocity[i]

    def velocity_product(self, i: int) -> Motion:
        """The acceleration the node has from velocities alone, with zero joint accelerations.

        v ×m (S qd) for a hinge or slide. For the free root it is (0, -w × u): the
        body-frame image of a world-frame linear acceleration that is zero.
        """
        node = self.nodes[i]
        v = self.velocity(i)
        if node.kind == "free3d":
            return Motion(ZERO, scale(-1, cross(v.w, v.u))).let(self.block)
        if node.dof is None or node.parent < 0:
            return ZERO_MOTION
        return v.cross(self.joint_motion(node).scaled(self.rate(node))).let(self.block)

    def world_acceleration(self) -> Motion:
        """Gravity as an upward acceleration of the world (Featherstone's trick), in world axes."""
        return Motion(ZERO, scale(-1, self.gravity))

    def ancestors(self, i: int) -> list[Node]:
        """The node and every node above it, nearest first."""
        out = []
        while i >= 0:
            out.append(self.nodes[i])
            i = self.nodes[i].parent
        return out
