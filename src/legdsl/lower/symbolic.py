"""Symbolic lowering: a checked ``Model`` becomes straight-line sympy programs.

One ``Function`` per entry of the generated module's API (see
docs/compiler.md). The dynamics come from the recursive algorithms in
``recursions``; the point kinematics (contacts, mass centre, energies) are
built here from the same link tree. Nothing here prints code: ``codegen``
does that with ``printer``.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Iterator, Mapping
from dataclasses import dataclass, field
from typing import TypeAlias

from sympy import Add, Expr, Float, Integer, Symbol, nan, oo, zoo

from legdsl.check.magnitudes import overflow_message
from legdsl.ir.model import Model
from legdsl.lang.errors import LegError
from legdsl.lower import recursions
from legdsl.lower.linktree import RESERVED, Node, Tree, build_nodes, rigid_inertia, vec
from legdsl.lower.names import output_names
from legdsl.lower.spatial import (
    EYE,
    ZERO,
    Mat,
    Vec,
    add,
    column,
    cross,
    dot,
    let_vec,
    matvec,
    scale,
    sub,
)
from legdsl.lower.straightline import Assign, Block, Statement, num


@dataclass(frozen=True)
class Call:
    """A call to another generated function, printed as written."""

    text: str


# What a generated function returns: expressions nested in lists and tuples.
Nested: TypeAlias = "Expr | Call | list[Nested] | tuple[Nested, ...]"


@dataclass(frozen=True)
class Function:
    """One generated function; ``names`` and ``bases`` as in ``straightline.Program``."""

    name: str
    params: tuple[str, ...]
    statements: tuple[Statement, ...]
    result: Nested
    names: Mapping[Symbol, str] = field(default_factory=dict)
    bases: Mapping[Expr, Symbol] = field(default_factory=dict)

    def name_of(self, sym: Symbol) -> str:
        return self.names.get(sym, sym.name)


@dataclass(frozen=True)
class SymbolicSystem:
    model: Model
    nodes: tuple[Node, ...]
    functions: tuple[Function, ...]

    def function(self, name: str) -> Function:
        return next(f for f in self.functions if f.name == name)


def lower(
    model: Model, cse: bool = True, done: Callable[[float], None] | None = None
) -> SymbolicSystem:
    """Every function of the generated module, as straight-line sympy code; ``done`` is told
    the share of the work done after each function (for a compile's time left)."""
    nodes = build_nodes(model)
    # (name, parameters, builder, its share in percent of the lowering's time: about the same
    # for the kangaroo and the quadruped, the recursions of the dynamics half of it)
    builders: list[tuple[str, tuple[str, ...], Callable[[Tree], Nested], int]] = [
        ("mass_matrix", ("q",), recursions.mass_matrix, 13),
        ("bias_forces", ("q", "v"), recursions.bias_forces, 15),
        ("forward_dynamics", ("q", "v", "tau"), recursions.forward_dynamics, 27),
        ("state_derivative", ("q", "v", "tau"), _state_derivative, 1),
        ("contact_positions", ("q",), _contact_positions, 3),
        ("contact_velocities", ("q", "v"), _contact_velocities, 5),
        ("contact_jacobians", ("q",), _contact_jacobians, 3),
        ("contact_angular_jacobians", ("q",), _contact_angular_jacobians, 1),
        ("body_poses", ("q",), _body_poses, 2),
        ("body_velocities", ("q", "v"), _body_velocities, 5),
        ("center_of_mass", ("q",), _center_of_mass, 7),
        ("center_of_mass_velocity", ("q", "v"), _center_of_mass_velocity, 11),
        ("kinetic_energy", ("q", "v"), _kinetic_energy, 5),
        ("potential_energy", ("q",), _potential_energy, 2),
    ]
    total, finished = sum(b[3] for b in builders), 0
    functions = []
    for name, params, build, share in builders:
        block = Block(RESERVED)
        result = build(Tree(model, nodes, block))
        leaves = list(_leaves(result))
        names = output_names(model, name)
        assert not names or len(names) == len(leaves), name
        program = block.finish(leaves, cse=cse, names=names or None)
        _refuse_overflow(model, program.statements, program.outputs)
        outputs = iter(program.outputs)
        functions.append(
            Function(
                name,
                params,
                program.statements,
                _rebuild(result, outputs),
                program.names,
                program.bases,
            )
        )
        finished += share
        if done is not None:
            done(finished / total)
    return SymbolicSystem(model, nodes, tuple(functions))


def _refuse_overflow(
    model: Model, statements: Iterable[Statement], outputs: Iterable[Expr]
) -> None:
    """An error at the body to blame where the dynamics hold a constant past a double (a mass
    times a length squared over 1.8e308): the printed code would read ``inf``, a name that is
    not defined in Python and not in C."""
    values = [s.value for s in statements if isinstance(s, Assign)] + list(outputs)
    if all(_finite(v) for v in values):
        return
    span = model.span
    for body in model.bodies:
        reach = math.hypot(*body.com) + (body.length or 0.0)
        moments = [body.mass * reach * reach, *(x for row in body.inertia for x in row)]
        if not all(math.isfinite(x) for x in moments):
            span = body.span
            break
    raise LegError.at(span, overflow_message(model.name))


def _finite(value: Expr) -> bool:
    if value.has(zoo, oo, -oo, nan):
        return False
    return all(math.isfinite(float(f)) for f in value.atoms(Float))


def _leaves(result: Nested) -> Iterator[Expr]:
    if isinstance(result, list | tuple):
        for item in result:
            yield from _leaves(item)
    elif not isinstance(result, Call):
        yield result


def _rebuild(result: Nested, outputs: Iterator[Expr]) -> Nested:
    if isinstance(result, list):
        return [_rebuild(item, outputs) for item in result]
    if isinstance(result, tuple):
        return tuple(_rebuild(item, outputs) for item in result)
    if isinstance(result, Call):
        return result
    return next(outputs)


# ------------------------------------------------------------------ helpers
def _carrier(tree: Tree, body: str) -> int:
    return next(n.index for n in tree.nodes if n.body is not None and n.body.name == body)


def _velocities(tree: Tree) -> list[Symbol]:
    """The symbols of v, in order."""
    out: list[Symbol] = []
    for node in tree.nodes:
        if node.kind == "free3d":
            out += [tree.root_v(node, k) for k in range(6)]
        elif node.dof is not None:
            out.append(tree.qd(node.dof))
    return out


def _parent_rotation(tree: Tree, node: Node) -> Mat:
    return tree.world(node.parent)[0] if node.parent >= 0 else EYE


def _point_jacobian(tree: Tree, i: int, point: Vec) -> list[Vec]:
    """Columns of d(point velocity)/dv for a world point fixed to node i (zero columns elsewhere)."""
    cols: list[Vec] = [ZERO] * tree.model.nv
    for node in tree.ancestors(i):
        rot, origin = tree.world(node.index)
        arm = let_vec(tree.block, sub(point, origin))
        if node.kind == "free3d":
            start = node.joint.v_start
            for k in range(3):
                cols[start + k] = EYE[k]  # a world velocity moves every point alike
                cols[start + 3 + k] = let_vec(tree.block, cross(column(rot, k), arm))
        elif node.dof is not None:
            axis = let_vec(tree.block, matvec(_parent_rotation(tree, node), vec(node.axis)))
            slide = node.kind == "slide"
            cols[node.dof.v_index] = axis if slide else let_vec(tree.block, cross(axis, arm))
    return cols


def _angular_jacobian(tree: Tree, i: int) -> list[Vec]:
    """Columns of d(world angular velocity of node i)/dv."""
    cols: list[Vec] = [ZERO] * tree.model.nv
    for node in tree.ancestors(i):
        if node.kind == "free3d":
            rot = tree.world(node.index)[0]
            for k in range(3):
                cols[node.joint.v_start + 3 + k] = column(rot, k)
        elif node.kind == "hinge":
            assert node.dof is not None
            axis = matvec(_parent_rotation(tree, node), vec(node.axis))
            cols[node.dof.v_index] = let_vec(tree.block, axis)
    return cols


def _rows(cols: list[Vec]) -> list[list[Expr]]:
    return [[c[k] for c in cols] for k in range(3)]


def _times(cols: list[Vec], v: list[Symbol], tree: Tree) -> Vec:
    # one sum of all the terms: adding them one by one re-sorts the growing sum each time
    terms = [scale(vi, c) for c, vi in zip(cols, v, strict=True)]
    return let_vec(
        tree.block,
        (Add(*(t[0] for t in terms)), Add(*(t[1] for t in terms)), Add(*(t[2] for t in terms))),
    )


def _world_point(tree: Tree, i: int, point: Vec) -> Vec:
    rot, origin = tree.world(i)
    return let_vec(tree.block, add(origin, matvec(rot, point)))


def _mass_centres(tree: Tree) -> list[tuple[Expr, int, Vec]]:
    """(mass, node, world mass centre) of every body."""
    out = []
    for body in tree.model.bodies:
        i = _carrier(tree, body.name)
        tree.block.note(f"{body.name}: mass centre")
        out.append((num(body.mass), i, _world_point(tree, i, vec(body.com))))
    return out


# ------------------------------------------------------------------ the functions
def _state_derivative(tree: Tree) -> Nested:
    v = _velocities(tree)
    qdot: list[Expr] = []
    for node in tree.nodes:
        if node.kind == "free3d":
            w, x, y, z = (tree.root_q(node, k) for k in range(3, 7))
            wx, wy, wz = v[node.joint.v_start + 3 : node.joint.v_start + 6]
            half = num(0.5)
            qdot += v[node.joint.v_start : node.joint.v_start + 3]
            qdot += [  # 0.5 * q ⊗ (0, w_body)
                tree.block.let(-half * (x * wx + y * wy + z * wz)),
                tree.block.let(half * (w * wx + y * wz - z * wy)),
                tree.block.let(half * (w * wy + z * wx - x * wz)),
                tree.block.let(half * (w * wz + x * wy - y * wx)),
            ]
        elif node.dof is not None:
            qdot.append(v[node.dof.v_index])
    return (qdot, Call("forward_dynamics(q, v, tau)"))


def _contact_positions(tree: Tree) -> Nested:
    out: list[Nested] = []
    for contact in tree.model.contacts:
        tree.block.note(f"{contact.name}")
        out.append(_world_point(tree, _carrier(tree, contact.body), vec(contact.point)))
    return out


def _contact_jacobians(tree: Tree) -> Nested:
    out: list[Nested] = []
    for contact in tree.model.contacts:
        tree.block.note(f"{contact.name}")
        i = _carrier(tree, contact.body)
        out.append(_rows(_point_jacobian(tree, i, _world_point(tree, i, vec(contact.point)))))
    return out


def _contact_velocities(tree: Tree) -> Nested:
    v = _velocities(tree)
    out: list[Nested] = []
    for contact in tree.model.contacts:
        tree.block.note(f"{contact.name}")
        i = _carrier(tree, contact.body)
        cols = _point_jacobian(tree, i, _world_point(tree, i, vec(contact.point)))
        out.append(_times(cols, v, tree))
    return out


def _contact_angular_jacobians(tree: Tree) -> Nested:
    out: list[Nested] = []
    for contact in tree.model.contacts:
        tree.block.note(f"{contact.name}")
        out.append(_rows(_angular_jacobian(tree, _carrier(tree, contact.body))))
    return out


def _body_poses(tree: Tree) -> Nested:
    out: list[Nested] = []
    for body in tree.model.bodies:
        tree.block.note(body.name)
        rot, origin = tree.world(_carrier(tree, body.name))
        out.append((origin, tuple(e for row in rot for e in row)))
    return out


def _body_velocities(tree: Tree) -> Nested:
    v = _velocities(tree)
    out: list[Nested] = []
    for body in tree.model.bodies:
        tree.block.note(body.name)
        i = _carrier(tree, body.name)
        origin = tree.world(i)[1]
        linear = _times(_point_jacobian(tree, i, origin), v, tree)
        angular = _times(_angular_jacobian(tree, i), v, tree)
        out.append((linear, angular))
    return out


def _center_of_mass(tree: Tree) -> Nested:
    total: Vec = ZERO
    for mass, _, centre in _mass_centres(tree):
        total = add(total, scale(mass, centre))
    return scale(num(1 / tree.model.total_mass), total)


def _center_of_mass_velocity(tree: Tree) -> Nested:
    v = _velocities(tree)
    cols: list[Vec] = [ZERO] * tree.model.nv
    for mass, i, centre in _mass_centres(tree):
        body_cols = _point_jacobian(tree, i, centre)
        cols = [
            let_vec(tree.block, add(c, scale(mass, b)))
            for c, b in zip(cols, body_cols, strict=True)
        ]
    return scale(num(1 / tree.model.total_mass), _times(cols, v, tree))


def _kinetic_energy(tree: Tree) -> Nested:
    total: Expr = Integer(0)
    for node in tree.nodes:
        if node.body is None:
            continue
        tree.block.note(f"{node.body.name}")
        v = tree.velocity(node.index)
        total += tree.block.let(v.dot(rigid_inertia(node.body).times(v)))
    return num(0.5) * total


def _potential_energy(tree: Tree) -> Nested:
    total: Expr = Integer(0)
    for mass, _, centre in _mass_centres(tree):
        total += tree.block.let(mass * dot(tree.gravity, centre))
    return -total
