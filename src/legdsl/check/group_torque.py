"""A single-leg library action given a group role: each member would apply the whole torque.

Assigning through a group role sets every member's actuator (docs/language.md, "Virtual
legs"), which is right for a spring's rest or a servo's gains but not for a posture
torque computed from a body's orientation: ``servo_pitch(pair, trunk, ...)`` has each of
the pair's hips apply eq. (4)'s whole torque, so the trunk feels it once per member (the
gains silently multiplied). The virtual-leg actions share it (``each`` member applies a
part); a library statement that sets a ``force`` through the group itself is told at the
argument that gave the group.

Likewise an action that predicts the apex from a spring's strain energy (``hop_apex``,
``hop_height``) given a group reads the members' mean force and stiffness: it counts one
spring's energy where the group's springs store it once per member, and the stroke it sizes
for one leg goes to each (a pair of legs asked for 0.85 m rose to 1.02 m). The virtual-leg
actions count ``feet_down`` springs; a library record that reads a group's spring force and
stiffness but not its ``feet_down`` is told at the argument.
"""

from __future__ import annotations

from collections.abc import Iterator

from legdsl.check.control_names import Scope, Value
from legdsl.check.hip_holds import assigns, reads_orientation
from legdsl.ir import controller as ir
from legdsl.lang import ast
from legdsl.lang.errors import Span

# A planar one-leg posture servo's counterpart for a virtual leg (raibert.leg's end).
SHARED_SERVOS = {"servo_pitch": "servo_pitch_shared", "servo_pitch_rate": "servo_pitch_rate_shared"}


def whole_torque_per_member(
    scope: Scope, s: ast.InvokeStmt, given: list[Value], body: tuple[ir.Stmt, ...]
) -> Iterator[tuple[Span, str]]:
    """Each group-role argument of ``s`` through which a library statement sets a torque
    from a body's orientation: where, and what to say."""
    bodies = {v.name for v in given if isinstance(v, ir.Part) and v.kind == "body"}
    for arg, value, legs in _group_arguments(scope, s, given):
        torque = next(
            (
                a
                for a in assigns(body)
                if a.key == "force"
                and a.span.file != scope.user_file
                and isinstance(a.actuator, ir.Alias)
                and a.actuator.legs == value
                and any(reads_orientation(a.value, b) for b in bodies)
            ),
            None,
        )
        if torque is None:
            continue
        assert isinstance(torque.actuator, ir.Alias)
        role, n = value.role, len(legs)
        each = (
            f"'each m in {role} {{ {s.action.name}(m, ...) }}' with the gains divided by "
            f"'max({role}.feet_down, 1)'"
        )
        shared = SHARED_SERVOS.get(s.action.name) if scope.model.planar else None
        how = f"call '{shared}({role}, ...)' (or {each})" if shared else each
        yield (
            arg.span,
            f"action '{s.action.name}' is for one leg, but {_group(scope, role, legs)}: "
            f"each member's '{torque.actuator.alias}' would apply the "
            f"whole torque, {n} times what is meant; share it: {how}"
            + ("" if scope.model.planar else " (as servo_posture_virtual does)"),
        )


def one_spring_per_group(
    scope: Scope, s: ast.InvokeStmt, given: list[Value], body: tuple[ir.Stmt, ...]
) -> Iterator[tuple[Span, str]]:
    """Each group-role argument of ``s`` whose spring energy a library record counts once,
    as if the group were one leg: where, and what to say."""
    for arg, value, legs in _group_arguments(scope, s, given):
        spring = next(
            (
                alias
                for r in ir.flat(body)
                if isinstance(r, ir.Record) and r.span.file != scope.user_file
                for alias in _energy_without_count(r.value, value)
            ),
            None,
        )
        if spring is None:
            continue
        role, n = value.role, len(legs)
        yield (
            arg.span,
            f"action '{s.action.name}' is for one leg, but {_group(scope, role, legs)}: "
            f"it predicts the apex from the energy of one leg's "
            f"'{spring}', where the {n} members' store {n} times it, and gives each the "
            f"stroke sized for one leg, so the hop overshoots; for a virtual leg use "
            f"'hop_height_virtual' (on entering thrust) or 'hop_height_apex' (at touchdown; "
            f"'hop_height_apex_rotary' for a knee's spring)",
        )


def _energy_without_count(e: ir.Expr, group: ir.Legs) -> Iterator[str]:
    """The alias whose force and stiffness ``e`` reads through ``group`` (a strain energy),
    if it does not also read how many of the group's feet are down."""
    reads = [x for x in ir.leaves(e) if isinstance(x, ir.Read)]
    if any(x.thing == group and x.member == "feet_down" for x in reads):
        return
    through = {
        (x.thing.alias, x.member)
        for x in reads
        if isinstance(x.thing, ir.Alias) and x.thing.legs == group
    }
    for alias in sorted({a for a, m in through if m == "force"}):
        if (alias, "k") in through:
            yield alias


def _group_arguments(
    scope: Scope, s: ast.InvokeStmt, given: list[Value]
) -> Iterator[tuple[ast.Expr, ir.Legs, tuple[str, ...]]]:
    """The arguments of ``s`` that give a group role of two legs or more, with its legs:
    the first group the role is bound to, a swap's too (a leg's role swapped with a pair's)."""
    for arg, value in zip(s.args, given, strict=True):
        if isinstance(value, ir.Legs) and value.each is None and value.role is not None:
            first = tuple(scope.roles.get(value.role, ()))
            every = scope.bound.get(value.role, (first,))
            legs = next((g for g in every if len(g) >= 2), ())
            if legs:
                yield arg, value, legs


def _group(scope: Scope, role: str | None, legs: tuple[str, ...]) -> str:
    """'pair' is a group of 2 legs (a, b), or becomes one by a swap."""
    verb = "is" if scope.roles.get(role or "") == legs else "becomes, by a 'swap',"
    return f"'{role}' {verb} a group of {len(legs)} legs ({', '.join(legs)})"
