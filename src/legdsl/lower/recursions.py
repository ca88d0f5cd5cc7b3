"""The three recursive dynamics algorithms, unrolled over a link tree (Featherstone 2008).

* ``forward_dynamics``: the articulated-body algorithm (ABA, ch. 7), O(n).
* ``bias_forces``: recursive Newton-Euler (RNEA, ch. 5) with zero joint
  accelerations, which gives h(q, v) in M(q) qdd + h(q, v) = tau.
* ``mass_matrix``: the composite-rigid-body algorithm (CRBA, ch. 6).

All three work in each node's own frame with gravity as an upward
acceleration of the world. The 3D free root is a six-DOF node whose motion
subspace maps MuJoCo's velocities (world linear, body angular) to the
body-frame spatial velocity: S = [[0, 1], [Rᵀ, 0]]; its generalized forces
are therefore a world force and a body-frame torque. At the root the ABA
needs a 6x6 solve; it is emitted as an unrolled LDLᵀ on run-time numbers.
"""

from __future__ import annotations

from sympy import Expr, Integer

from legdsl.lower.linktree import Node, Tree, rigid_inertia
from legdsl.lower.spatial import (
    ZERO,
    ZERO_ARTICULATED,
    ZERO_FORCE,
    ZERO_RIGID,
    ArticulatedInertia,
    Force,
    Motion,
    RigidInertia,
    add,
    cross,
    let_vec,
    matvec,
    skew,
    solve_spd,
    sub,
    tmatvec,
)


def _parent_acceleration(tree: Tree, node: Node, accel: dict[int, Motion]) -> Motion:
    """The parent's acceleration seen in this node's frame, plus the velocity-product term."""
    parent = accel[node.parent] if node.parent >= 0 else tree.world_acceleration()
    a = tree.transform(node.index).motion(parent) + tree.velocity_product(node.index)
    return a.let(tree.block)


def _root_gravity(tree: Tree, node: Node) -> Motion:
    """The world's upward acceleration in the free root's frame."""
    rot = tree.rotation(node.index)
    return Motion(ZERO, let_vec(tree.block, tmatvec(rot, tree.world_acceleration().u)))


def bias_forces(tree: Tree) -> list[Expr]:
    """h(q, v): the generalized forces that hold every joint at zero acceleration."""
    block, nodes = tree.block, tree.nodes
    h: list[Expr] = [Integer(0)] * tree.model.nv
    accel: dict[int, Motion] = {}
    force: dict[int, Force] = {}
    for node in nodes:
        block.note(f"{node.label}: velocity, acceleration, force")
        v = tree.velocity(node.index)
        if node.kind == "free3d":
            a = (tree.velocity_product(node.index) + _root_gravity(tree, node)).let(block)
        else:
            a = _parent_acceleration(tree, node, accel)
        accel[node.index] = a
        if node.body is None:
            force[node.index] = ZERO_FORCE
            continue
        inertia = rigid_inertia(node.body)
        force[node.index] = (inertia.times(a) + v.cross_force(inertia.times(v))).let(block)
    for node in reversed(nodes):
        f = force[node.index]
        if node.kind == "free3d":
            block.note(f"{node.label}: world force and body torque")
            start = node.joint.v_start
            world_force = matvec(tree.rotation(node.index), f.f)
            for k in range(3):
                h[start + k] = block.let(world_force[k])
                h[start + 3 + k] = f.n[k]
        elif node.dof is not None:
            h[node.dof.v_index] = block.let(tree.joint_motion(node).dot(f))
        if node.parent >= 0:
            block.note(f"{node.label}: force on the parent")
            moved = tree.transform(node.index).force_to_parent(f)
            force[node.parent] = (force[node.parent] + moved).let(block)
    return h


def mass_matrix(tree: Tree) -> list[list[Expr]]:
    """M(q) by composite rigid bodies: each column from the composite inertia below a joint."""
    block, nodes = tree.block, tree.nodes
    nv = tree.model.nv
    m: list[list[Expr]] = [[Integer(0)] * nv for _ in range(nv)]
    composite: dict[int, RigidInertia] = {
        n.index: rigid_inertia(n.body) if n.body else ZERO_RIGID for n in nodes
    }
    for node in reversed(nodes):
        if node.parent >= 0:
            block.note(f"{node.label}: composite inertia seen from the parent")
            moved = tree.transform(node.index).rigid_to_parent(composite[node.index], block)
            composite[node.parent] = (composite[node.parent] + moved).let(block)
    for node in nodes:
        if node.kind == "free3d":
            _free_root_block(tree, node, composite[node.index], m)
        if node.dof is None:
            continue
        block.note(f"{node.label}: column {node.dof.v_index}")
        col = node.dof.v_index
        f = composite[node.index].times(tree.joint_motion(node)).let(block)
        m[col][col] = block.let(tree.joint_motion(node).dot(f))
        child = node
        while child.parent >= 0:
            f = tree.transform(child.index).force_to_parent(f).let(block)
            above = nodes[child.parent]
            if above.dof is not None:
                row = above.dof.v_index
                m[row][col] = m[col][row] = block.let(tree.joint_motion(above).dot(f))
            elif above.kind == "free3d":
                start = above.joint.v_start
                world_force = matvec(tree.rotation(above.index), f.f)
                for k in range(3):
                    m[start + k][col] = m[col][start + k] = block.let(world_force[k])
                    m[start + 3 + k][col] = m[col][start + 3 + k] = f.n[k]
            child = above
    return m


def _free_root_block(tree: Tree, node: Node, body: RigidInertia, m: list[list[Expr]]) -> None:
    """Sᵀ I S for the free root: [[mass 1, R (h×)ᵀ], [(h×) Rᵀ, I]], written so 1 stays exact."""
    block = tree.block
    block.note(f"{node.label}: the 6x6 block of the free root")
    start = node.joint.v_start
    coupling = [let_vec(block, matvec(skew(body.h), row)) for row in tree.rotation(node.index)]
    for i in range(3):
        m[start + i][start + i] = body.mass
        for j in range(3):
            # (h×) Rᵀ: column i is h × (row i of R)
            m[start + 3 + j][start + i] = m[start + i][start + 3 + j] = coupling[i][j]
            m[start + 3 + i][start + 3 + j] = body.inertia[i][j]


def forward_dynamics(tree: Tree) -> list[Expr]:
    """qdd = M⁻¹ (tau - h) by the articulated-body algorithm, never forming M."""
    block, nodes = tree.block, tree.nodes
    articulated: dict[int, ArticulatedInertia] = {}
    bias: dict[int, Force] = {}
    for node in nodes:
        block.note(f"{node.label}: velocity and bias force")
        v = tree.velocity(node.index)
        if node.body is None:
            articulated[node.index], bias[node.index] = ZERO_ARTICULATED, ZERO_FORCE
            continue
        inertia = rigid_inertia(node.body)
        articulated[node.index] = inertia.articulated()
        bias[node.index] = v.cross_force(inertia.times(v)).let(block)

    # Inward: articulated inertias and bias forces, one joint primitive at a time.
    u_force: dict[int, Force] = {}  # U = I^A S
    d: dict[int, Expr] = {}  # Sᵀ U
    u_tau: dict[int, Expr] = {}  # tau - Sᵀ p^A
    for node in reversed(nodes):
        i = node.index
        big_i, p = articulated[i], bias[i]
        if node.kind == "free3d":
            continue
        if node.dof is not None:
            block.note(f"{node.label}: articulated inertia")
            s = tree.joint_motion(node)
            u_force[i] = big_i.times(s).let(block)
            d[i] = s.dot(u_force[i])
            u_tau[i] = tree.tau(node.dof) - s.dot(p)  # kept whole: U u / D folds along S
            if node.parent < 0:
                continue
            # U / D, divided entry by entry so that along a coordinate axis the ratio is exactly 1
            # and the articulated inertia's row and column along S come out exactly zero.
            w = u_force[i].scaled(1 / d[i]).let(block)
            big_i = big_i.minus_outer(w, u_force[i]).let(block)
            c = tree.velocity_product(i)
            p = (p + big_i.times(c) + w.scaled(u_tau[i])).let(block)
        if node.parent >= 0:
            block.note(f"{node.label}: seen from the parent")
            x = tree.transform(i)
            articulated[node.parent] = (
                articulated[node.parent] + x.articulated_to_parent(big_i, block)
            ).let(block)
            bias[node.parent] = (bias[node.parent] + x.force_to_parent(p)).let(block)

    # Outward: accelerations.
    qdd: list[Expr] = [Integer(0)] * tree.model.nv
    accel: dict[int, Motion] = {}
    for node in nodes:
        i = node.index
        if node.kind == "free3d":
            accel[i] = _free_root_acceleration(tree, node, articulated[i], bias[i], qdd)
            continue
        block.note(f"{node.label}: acceleration")
        a = _parent_acceleration(tree, node, accel)
        if node.dof is not None:
            q_acc = block.let((u_tau[i] - a.dot(u_force[i])) / d[i])
            qdd[node.dof.v_index] = q_acc
            a = (a + tree.joint_motion(node).scaled(q_acc)).let(block)
        accel[i] = a
    return qdd


def _free_root_acceleration(
    tree: Tree, node: Node, big_i: ArticulatedInertia, p: Force, qdd: list[Expr]
) -> Motion:
    """Solve I^A a = S⁻ᵀ tau - p^A at the free root; a includes the world's upward acceleration."""
    block = tree.block
    block.note(f"{node.label}: solve the 6x6 articulated inertia")
    rot = tree.rotation(node.index)
    world_force = (tree.root_tau(node, 0), tree.root_tau(node, 1), tree.root_tau(node, 2))
    body_torque = (tree.root_tau(node, 3), tree.root_tau(node, 4), tree.root_tau(node, 5))
    rhs = [*sub(body_torque, p.n), *sub(tmatvec(rot, world_force), p.f)]
    a = solve_spd(block, big_i.rows(), rhs)
    accel = Motion((a[0], a[1], a[2]), (a[3], a[4], a[5]))
    block.note(f"{node.label}: accelerations in MuJoCo's coordinates")
    v = tree.velocity(node.index)
    # a.u = Rᵀ p̈ - w × u - Rᵀ (-g), so p̈ = R (a.u + w × u) + g
    linear = add(matvec(rot, add(accel.u, cross(v.w, v.u))), tree.gravity)
    start = node.joint.v_start
    for k in range(3):
        qdd[start + k] = block.let(linear[k])
        qdd[start + 3 + k] = accel.w[k]
    return accel
