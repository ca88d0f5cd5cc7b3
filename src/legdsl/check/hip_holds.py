"""A servo that turns a body through a leg's hip must be given the body the hip holds.

A hip actuator's torque acts between the leg and the body the leg hangs from (the parent
of the leg's first joint, with whatever is welded to it). An action that sets it from a
body's orientation (``servo_pitch(leg, body, ...)``: the torque from ``body.pitch``) is
eq. (4) only for that body: given another (the leg's own thigh), the torque turns the
trunk while reading a body it cannot hold, and no run of it can be right. So a call whose
statements set a hip actuator from the orientation of a body given as an argument is told
at that argument, with the body the hip holds. Likewise a body whose yaw turns a ``place``'s
goals (``place_foot_3d(leg, body, ...)``) must be the root, whose yaw the goals' heading
frame is.

A trunk in several bodies (a spine: the rear legs hang from a rear half hinged to the front
half, the root) is held by every hip: a hip's torque reaches each body of the trunk through
the joints between them, which belong to no leg. So a body that no leg's joints carry is
held by any hip; only a body below a hip (a leg's thigh, shank, foot) cannot be.
"""

from __future__ import annotations

from collections.abc import Iterator

from legdsl.check.control_names import Scope, Value
from legdsl.ir import controller as ir
from legdsl.ir.model import Model
from legdsl.lang import ast
from legdsl.lang.errors import Span

# What a body's orientation is read as (the posture and heading servos read these).
_ORIENTATION = {"pitch", "roll", "yaw", "pitch_rate", "roll_rate", "yaw_rate"}


def misaimed_bodies(
    scope: Scope, s: ast.InvokeStmt, given: list[Value], body: tuple[ir.Stmt, ...]
) -> Iterator[tuple[Span, str]]:
    """Each argument of the call ``s`` that is a body a hip it drives cannot hold: where,
    and what to say."""
    model = scope.model
    for arg, value in zip(s.args, given, strict=True):
        if not (isinstance(value, ir.Part) and value.kind == "body"):
            continue
        trunk = _trunk_bodies(model)
        for leg, held, swapped in _hips_driven_from(scope, body, value.name):
            if value.name in _welded(model, held) or value.name in trunk:
                continue
            yield (
                arg.span,
                f"action '{s.action.name}' sets the hip's torque from the orientation of "
                f"'{value.name}', which that torque cannot hold: the hip of leg '{leg}'"
                f"{swapped} holds body '{held}'; did you mean '{held}'?",
            )
            break
        else:
            root = next((j.child for j in model.joints if j.parent is None), None)
            if root is None or value.name in _welded(model, root):
                continue
            if _places_from(body, value.name):
                yield (
                    arg.span,
                    f"action '{s.action.name}' places a foot from the yaw of "
                    f"'{value.name}', but 'place' offsets the foot from its hip in the heading "
                    f"frame, turned by the yaw of the root body '{root}'; did you mean '{root}'?",
                )


def _hips_driven_from(
    scope: Scope, stmts: tuple[ir.Stmt, ...], name: str
) -> Iterator[tuple[str, str, str]]:
    """(leg, the body its hip hangs from, how a swap made the leg the role's) for each hip
    actuator set from ``name``'s orientation."""
    model = scope.model
    hip_of = {leg.name: leg.joints[0] for leg in model.legs if leg.joints}
    parent = {j.name: j.parent for j in model.joints}
    for assign in assigns(stmts):
        if not reads_orientation(assign.value, name):
            continue
        for leg, joint in _joints_of(scope, assign.actuator):
            hip = hip_of.get(leg)
            held = parent.get(hip) if hip is not None else None
            if joint == hip and held is not None:
                yield leg, held, _swapped_in(scope, assign.actuator, leg)


def _places_from(stmts: tuple[ir.Stmt, ...], name: str) -> bool:
    """Whether a ``place`` among ``stmts`` puts a foot from ``name``'s yaw (its goals turned
    by it into the heading frame, which is the root's)."""
    places = (s for s in ir.flat(stmts) if isinstance(s, ir.Place))
    return any(reads_orientation(g, name, {"yaw", "yaw_rate"}) for p in places for g in p.goals)


def assigns(stmts: tuple[ir.Stmt, ...]) -> Iterator[ir.Assign]:
    return (s for s in ir.flat(stmts) if isinstance(s, ir.Assign))


def reads_orientation(e: object, name: str, members: set[str] = _ORIENTATION) -> bool:
    """Whether ``e`` reads body ``name``'s orientation or its rate."""
    return any(
        isinstance(x, ir.Read)
        and isinstance(x.thing, ir.Part)
        and x.thing.name == name
        and x.member in members
        for x in ir.leaves(e)
    )


def _joints_of(scope: Scope, actuator: ir.Part | ir.Alias) -> Iterator[tuple[str, str]]:
    """(leg, joint) of the actuator on each leg it can stand for."""
    model = scope.model
    joint_of_dof = {d.name: d.joint for d in model.dofs}
    joint_of = {a.name: joint_of_dof.get(a.dof) for a in model.actuators}
    if isinstance(actuator, ir.Part):
        joint = joint_of.get(actuator.name)
        for one in model.legs:
            if joint is not None and joint in one.joints:
                yield one.name, joint
        return
    for leg in _legs(scope, actuator.legs):
        joint = joint_of.get(scope.aliases.get(leg, {}).get(actuator.alias, ""))
        if joint is not None:
            yield leg, joint


def _swapped_in(scope: Scope, actuator: ir.Part | ir.Alias, leg: str) -> str:
    """How ``leg`` came to be read through a role, when only a swap makes it the role's."""
    role = actuator.legs.root().role if isinstance(actuator, ir.Alias) else None
    if role is None or leg in scope.roles.get(role, ()):
        return ""
    return f" (role '{role}' stands for it once the table's swaps have run)"


def _legs(scope: Scope, legs: ir.Legs) -> tuple[str, ...]:
    root = legs.root()
    if root.leg is not None:
        return (root.leg,)
    if root.role is None:
        return ()
    # every leg the role stands for under any binding the table's swaps reach
    first = scope.roles.get(root.role, ())
    return tuple(dict.fromkeys(n for g in scope.bound.get(root.role, (first,)) for n in g))


def _trunk_bodies(model: Model) -> set[str]:
    """The bodies no leg's joints carry: the root and those hung from it by joints of no leg
    (a spine's rear half, a head, a tail), which every hip's torque reaches. A body whose
    chain meets a misspelt parent or goes round a cycle (both already told as errors) is not
    the trunk's."""
    first = {leg.joints[0] for leg in model.legs if leg.joints}
    parent_joint = {b.name: (b.parent, b.joint) for b in model.bodies}
    trunk = set()
    for name in parent_joint:
        body: str | None = name
        seen: set[str] = set()
        while body in parent_joint and body not in seen and parent_joint[body][1] not in first:
            seen.add(body)
            body = parent_joint[body][0]
        if body is None:
            trunk.add(name)
    return trunk


def _welded(model: Model, body: str) -> set[str]:
    """``body`` and the bodies welded to it, rigidly one with it."""
    group = {body}
    welds = [(j.parent, j.child) for j in model.joints if j.kind == "weld"]
    grew = True
    while grew:
        grew = False
        for a, b in welds:
            if (a in group) != (b in group) and a is not None:
                group |= {a, b}
                grew = True
    return group
